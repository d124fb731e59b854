// ray_plane_props.cpp — RapidCheck properties of ray vs plane: rays lying exactly in the plane, exactly parallel rays off it, nearly parallel rays.
//
// Covered, for float and double, over every generator of the shape (see
// props_support.hpp): every mode answers invalid exactly for invalid inputs;
// conservative never misses an exact hit and encloses the exact interval; certified
// equals the exact oracle (verdict, face, faithfully rounded t); both of them again,
// against the oracle, on the case moved elsewhere in the exponent range by an exact
// power-of-two scaling; oracle-free invariants of certified under exact power-of-two
// scaling, axis permutation and ray reversal; a
// hit's interval is ordered; batch equals scalar bit for bit (also the certified lane
// path, in both SIMD backends); a PreparedRay's certified
// answer equals the Ray's bit for bit and its conservative answer meets the contract;
// for float, every conservative hit a hit of the double enclosure (the float stage adds
// no false hit); for double, cases whose normal, origin and direction are scaled apart
// out of the pin's range (the rescaled pin) against the oracle and their unscaled
// answers; and the fast mode's wrong answers counted per generator (printed, not
// asserted).
#include "props_support.hpp"

RAYPROOF_PROPERTY_SUITE(PlaneProps, rayproof::Plane)

// The certified batch's lane path (detail/ray_plane_batch.hpp: the enclosure for float
// rays, the verdict filter for double rays) in both SIMD backends, against the scalar
// certified answer bit for bit (props_support.hpp, lane_batch_equals_scalar).
TYPED_TEST(PlaneProps, CertifiedLaneBatchEqualsScalar) {
    rayproof::props::lane_batch_equals_scalar<TypeParam, rayproof::Plane<TypeParam>>();
}

// Float input only: conservative mode's first stage computes the enclosure in float and
// answers where it lies inside [t_min, t_max] (a hit, exact then) or outside it; the rest
// goes to the enclosure in double. So every conservative hit is a hit of the double
// enclosure, on every case where that enclosure holds: a float stage that answered a
// straddling enclosure would add false hits near t_min and t_max. (For double input the
// double enclosure is the first stage: nothing to compare.)
TEST(PlaneFloatConservative, EveryHitIsAHitOfTheDoubleEnclosure) {
    using T = float;
    rayproof::props::run_cases<T, rayproof::Plane<T>>([](const auto& d, auto) -> std::optional<std::string> {
        namespace dt = rayproof::detail;
        const rayproof::Ray<T>& r = d.c.ray;
        const dt::PlaneEnclosure<double> e = dt::plane_enclosure(dt::plane_sums<double>(r, d.c.shape));
        if (!(e.ok && dt::valid_range(r))) return std::nullopt;
        const bool double_hit = dt::outward_to<T>(e.lo, e.hi, r.t_min, r.t_max).meets;
        const rayproof::Hit<T> h = rayproof::intersect(r, d.c.shape, rayproof::conservative);
        if (h.verdict != rayproof::Verdict::hit || double_hit) return std::nullopt;
        std::ostringstream os;
        os << "conservative " << h << ", the double enclosure [" << std::hexfloat << e.lo << ", " << e.hi
           << "] misses";
        return os.str();
    });
}

// Double input only: the plane's pin (plane_pin) takes input with exponents within about
// ±450 and pins the rest on the input rescaled by powers of two (plane_pin_rescaled, on
// the general path). Here each case's normal, origin and direction are scaled apart: n by
// 2^a, o by 2^b, the offset by 2^(a+b) and d by 2^c (t_min and t_max by 2^(b-c)), so the
// exact t scales by 2^(b-c) (gen::exact_scale). The exponents are drawn from the case's
// choice until every value scales exactly and some value leaves the pin's range; a shrink
// moves them towards 0. The certified answer of the scaled case meets the contract
// against its exact answer, has the unscaled answer's verdict, and each t is the
// unscaled t times 2^(b-c) or a double adjacent to it (both faithful roundings of one
// exact value) where both are normal doubles below the largest.
TEST(PlaneRescaledPin, SeparateScalingsMeetTheContractAndScaleT) {
    using T = double;
    using P = rayproof::Plane<T>;
    constexpr std::uint64_t kSalt = 11;
    std::uint64_t total = 0, scaled = 0;
    rayproof::props::run_cases<T, P>([&](const auto& d, auto pick) -> std::optional<std::string> {
        ++total;
        using rayproof::props::same_or_adjacent;
        const auto outside = [](T v) { return v != 0 && (std::abs(v) < 0x1p-450 || std::abs(v) > 0x1p490); };
        std::uint64_t state = d.choice(kSalt);
        for (int attempt = 0; attempt < 16; ++attempt) {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            const int a0 = int((state >> 11) % 1801) - 900, b0 = int((state >> 27) % 1801) - 900,
                      c0 = int((state >> 43) % 1801) - 900;
            const int a = pick(a0, 0), b = pick(b0, 0), c = pick(c0, 0);
            rayproof::gen::Case<T, P> s = d.c;
            // positions (and the offset's share) by 2^b, d by 2^c, the normal by 2^a
            if (!rayproof::gen::exact_scale(s, b, c, a)) continue;
            bool far = outside(s.shape.offset);
            for (int j = 0; j < 3; ++j)
                far = far || outside(s.shape.normal[j]) || outside(s.ray.origin[j]) || outside(s.ray.direction[j]);
            if (!far) continue;
            ++scaled;
            const rayproof::Hit<T> h = rayproof::intersect(s.ray, s.shape, rayproof::certified);
            const auto e = rayproof::oracle::exact(s.ray, s.shape);
            const auto k = rayproof::oracle::check_contract(s.ray, s.shape, h, e, rayproof::certified);
            const rayproof::Hit<T> u = rayproof::intersect(d.c.ray, d.c.shape, rayproof::certified);
            // Compared where both are normal and below the largest double (which also
            // stands for any t beyond it); elsewhere the contract check alone.
            const auto scales = [&](T from, T to) {
                constexpr T small = std::numeric_limits<T>::min(), big = std::numeric_limits<T>::max();
                const T want = std::ldexp(from, b - c);
                if (!(std::abs(from) >= small && std::abs(from) < big && std::abs(to) < big)) return true;
                return !(std::abs(want) >= small && std::abs(want) <= big) || same_or_adjacent(want, to);
            };
            const bool same = u.verdict == h.verdict &&
                              (h.verdict != rayproof::Verdict::hit || (scales(u.t_enter, h.t_enter) && scales(u.t_exit, h.t_exit)));
            if (k.ok() && same) return std::nullopt;
            std::ostringstream os;
            os << "scaled by n 2^" << a << ", o 2^" << b << ", d 2^" << c << ": certified " << h << " (unscaled " << u
               << ")\n  " << k.mode_judgement() << "\n  scaled " << s;
            return os.str();
        }
        return std::nullopt;  // no exact scaling leaves the range (NaN or infinite input, say)
    });
    // Not vacuous: most cases find such a scaling (not those with NaN or infinite input,
    // or values at both ends of the range).
    std::cout << scaled << " of " << total << " cases scaled out of the pin's range\n";
    EXPECT_GT(scaled * 2, total) << "too few cases scaled out of the pin's range";
}
