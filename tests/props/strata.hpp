// strata.hpp — how the property suites choose their cases: stratified by generator and
// seeded by a counter-based hash, so that the mix of a run does not depend on RapidCheck's
// size parameter.
//
// A run of a suite has a suite seed S and a case count N (RC_PARAMS seed= and
// max_success=). Case i (0 <= i < N) of shape × scalar type is
//   generator   i mod G              (G generators of the shape: each gets floor(N/G) or
//                                     ceil(N/G) cases, whatever N is)
//   case seed   splitmix(key + i)    key = a hash of (S, shape, type); SplitMix64's mixing
//                                     is a bijection of the 64-bit integers, so distinct i
//                                     give distinct seeds
// and its input is gen::make_case<T, Shape>(generator, case seed). Choices a property makes
// beyond the input (a power-of-two exponent, a permutation, a batch size) come from the
// case seed too (choice(i, salt)), so case i is the same whichever property runs it, and
// RAYPROOF_PROPS_CASE=i rebuilds it alone.
//
// The power-of-two scaling of a case always scales: choose_scaling returns an exponent
// k != 0 whenever some k != 0 scales the case exactly, and nothing only for the cases no
// k != 0 scales (NaN or infinite numbers other than t_min and t_max, or values at both ends of the range).
#pragma once

#include <rayproof/generators.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace rayproof::props {

// SplitMix64's finalizer (Steele, Lea, Flood 2014): a bijection of the 64-bit integers
// that mixes every input bit into every output bit.
constexpr std::uint64_t splitmix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

template <class T, class Shape> struct Plan {
    std::uint64_t suite_seed = 0;
    std::uint64_t cases = 0;
    std::optional<std::uint64_t> only;  // RAYPROOF_PROPS_CASE: run this case alone

    static constexpr std::size_t generator_count() { return gen::generators<T, Shape>().size(); }

    std::size_t generator_of(std::uint64_t i) const { return std::size_t(i % generator_count()); }
    std::string_view generator_name(std::uint64_t i) const { return gen::generators<T, Shape>()[generator_of(i)].name; }
    std::uint64_t case_seed(std::uint64_t i) const {
        const std::uint64_t key = splitmix(splitmix(splitmix(suite_seed) ^ gen::name_hash(gen::shape_name<Shape>())) ^
                                           gen::name_hash(gen::scalar_name<T>()));
        return splitmix(key + i);
    }
    // A 64-bit choice of case i beyond its input, one per salt.
    std::uint64_t choice(std::uint64_t i, std::uint64_t salt) const { return splitmix(case_seed(i) ^ splitmix(salt)); }
    gen::Case<T, Shape> make(std::uint64_t i) const {
        gen::Rng rng(case_seed(i));
        return gen::generators<T, Shape>()[generator_of(i)].make(rng);
    }

    // The indices this run checks: [0, cases), or the one case asked for.
    std::uint64_t first() const { return only ? *only : 0; }
    std::uint64_t end() const { return only ? *only + 1 : cases; }
};

// The number of cases of each generator among indices [first, end).
template <class T, class Shape> std::vector<std::uint64_t> shares(const Plan<T, Shape>& p) {
    std::vector<std::uint64_t> n(p.generator_count(), 0);
    for (std::uint64_t i = p.first(); i < p.end(); ++i) ++n[p.generator_of(i)];
    return n;
}
template <class T, class Shape> std::string shares_text(const std::vector<std::uint64_t>& n) {
    std::ostringstream os;
    os << "cases per generator (" << gen::shape_name<Shape>() << '<' << gen::scalar_name<T>() << ">):";
    const auto gens = gen::generators<T, Shape>();
    for (std::size_t g = 0; g < gens.size(); ++g) os << ' ' << gens[g].name << ' ' << n[g];
    return os.str();
}

// A power-of-two scaling of a case: positions and direction by 2^k, the Obb axes or the
// plane normal by 2^j.
struct Scaling {
    int k = 0, j = 0;
};

// Scales positions and direction of c by 2^k and the Obb axes or plane normal by 2^j
// (gen::exact_scale with kp == kd == k, so t is unchanged and an infinite t_min or t_max
// stays as it is); false, leaving c untouched, when some number would not scale exactly.
template <class T, class Shape> bool scale_exactly(gen::Case<T, Shape>& c, int k, int j) {
    const T t_min = c.ray.t_min, t_max = c.ray.t_max;
    const bool inf_min = std::isinf(t_min), inf_max = std::isinf(t_max);
    if (inf_min) c.ray.t_min = 0;
    if (inf_max) c.ray.t_max = 0;
    const bool ok = gen::exact_scale(c, k, k, j);
    if (inf_min) c.ray.t_min = t_min;
    if (inf_max) c.ray.t_max = t_max;
    return ok;
}

// The scaling of case c that `choice` picks: k uniform in [-E, E] \ {0} and j in
// [-E/2, E/2] (E the width of T's exponent range); when that is not exact, k and j halved
// together down to |k| == 1, then with j = 0 k halved from the other sign. Nothing when no
// tried exponent scales c exactly; then neither k = 1 nor k = -1 does (both are tried).
template <class T, class Shape>
std::optional<Scaling> choose_scaling(const gen::Case<T, Shape>& c, std::uint64_t choice) {
    constexpr int E = std::numeric_limits<T>::max_exponent - std::numeric_limits<T>::min_exponent;
    const int magnitude = 1 + int((choice >> 1) % std::uint64_t(E));  // in [1, E]
    const int sign = (choice & 1) ? -1 : 1;
    int j = int((choice >> 32) % std::uint64_t(E + 1)) - E / 2;  // in [-E/2, E/2]
    auto fits = [&c](int k, int j_) {
        auto s = c;
        return scale_exactly(s, k, j_);
    };
    for (int m = magnitude; m >= 1; m /= 2, j /= 2)
        if (fits(sign * m, j)) return Scaling{sign * m, j};
    for (int m = magnitude; m >= 1; m /= 2)
        if (fits(-sign * m, 0)) return Scaling{-sign * m, 0};
    if (fits(sign, 0)) return Scaling{sign, 0};
    return std::nullopt;
}

// RAYPROOF_PROPS_CASE: the one case index to run, when set. A value that is not a decimal
// index is an error, reported in `error`.
inline std::optional<std::uint64_t> case_from_environment(std::string& error) {
    const char* v = std::getenv("RAYPROOF_PROPS_CASE");
    if (!v) return std::nullopt;
    char* end = nullptr;
    const unsigned long long i = std::strtoull(v, &end, 10);
    if (*v < '0' || *v > '9' || *end != '\0') {
        error = std::string("RAYPROOF_PROPS_CASE must be a case index (a decimal number), got '") + v + "'";
        return std::nullopt;
    }
    return std::uint64_t(i);
}

}  // namespace rayproof::props
