// props_support.hpp — the property tester shared by the four property suites: one
// template over the scalar type and the shape, instantiated for float and double by
// RAYPROOF_PROPERTY_SUITE in each suite's file.
//
// Cases come from the shared generators (rayproof/generators.hpp), stratified (strata.hpp):
// of the N cases of a run (RC_PARAMS max_success=N, suite seed S from seed=S), case i is
// generator i mod G's case from a seed hashed from (S, shape, type, i), so every generator
// (general position, log-uniform, exact grazing, near grazing, ±0 directions, boundary
// origins, extreme scenes, invalid inputs) gets N/G cases of every property, whatever
// RapidCheck's size parameter. Each property prints its count of cases per generator. A
// failing case is run again under RapidCheck, which shrinks the choices the property made
// beyond the input (a scaling exponent, a permutation, a batch size), and the failure
// prints the suite seed, the case index and the generator, the command that runs that
// case alone (RAYPROOF_PROPS_CASE=i RC_PARAMS="seed=S" ... --gtest_filter=...), the call
// that rebuilds the input,
//   rayproof::gen::make_case<double, rayproof::Aabb<double>>("grazing", 0x...)
// the inputs in hexfloat, and RapidCheck's RC_PARAMS="reproduce=..." string, which replays
// the shrunk case. What each mode promises against the exact oracle is decided by the
// shared contract checker (rayproof/oracle/contract.hpp), as in the fuzz targets and the
// audit.
//
// A property about a mode the kernel does not provide (rayproof::Answerable false) is
// skipped with GTEST_SKIP and its reason, never passed silently.
#pragma once

#include <rayproof/generators.hpp>
#include "strata.hpp"
#include <rayproof/oracle/contract.hpp>
#include <rayproof/oracle/oracle.hpp>
#include <rayproof/rayproof.hpp>

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace rayproof::props {

using Scalars = ::testing::Types<float, double>;
struct ScalarNames {
    template <class T> static std::string GetName(int) { return std::is_same_v<T, float> ? "float" : "double"; }
};

template <class Shape> std::string shape_type_name() {
    std::string s(gen::shape_name<Shape>());
    s[0] = char(s[0] - 'a' + 'A');
    return s;
}

// The C++ call that rebuilds a case.
template <class T, class Shape> std::string reproducer(std::string_view generator, std::uint64_t seed) {
    std::ostringstream os;
    const std::string t(gen::scalar_name<T>());
    os << "rayproof::gen::make_case<" << t << ", rayproof::" << shape_type_name<Shape>() << '<' << t << ">>(\""
       << generator << "\", 0x" << std::hex << seed << ")";
    return os.str();
}

// The running test's name for --gtest_filter ("AabbProps/1.CertifiedEqualsOracle").
inline std::string current_test() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    return std::string(info->test_suite_name()) + "." + info->name();
}

// Case i of the run (strata.hpp): its input and what reproduces it.
template <class T, class Shape> struct Drawn {
    const Plan<T, Shape>* plan;
    std::uint64_t index;
    gen::Case<T, Shape> c;

    std::uint64_t seed() const { return plan->case_seed(index); }
    std::uint64_t choice(std::uint64_t salt) const { return plan->choice(index, salt); }
    std::string where() const {
        std::ostringstream os;
        os << "case " << index << " of suite seed " << plan->suite_seed << ", generator '" << c.generator
           << "', case seed 0x" << std::hex << seed() << std::dec << "\n  this case alone: RAYPROOF_PROPS_CASE="
           << index << " RC_PARAMS=\"seed=" << plan->suite_seed << "\" ./ray_" << gen::shape_name<Shape>()
           << "_props --gtest_filter='" << current_test() << "'\n  its input: "
           << reproducer<T, Shape>(c.generator, seed())
           << "\n  " << c;
        return os.str();
    }
};

// A choice of a case beyond its input (a scaling exponent, a permutation, a batch size).
// PlainPick keeps the value the case seed chose; RapidPick hands it to RapidCheck, which,
// once the case fails, shrinks it towards `target` while the failure persists (the value
// does not depend on RapidCheck's Random or size, so its reproduce string replays it).
struct PlainPick {
    int operator()(int value, int) const { return value; }
};
struct RapidPick {
    int operator()(int value, int target) const {
        return *rc::Gen<int>([value, target](const rc::Random&, int) {
            return rc::shrinkable::shrinkRecur(value, [target](int v) { return rc::shrink::towards(v, target); });
        });
    }
};

// Runs a property over the cases of the run: body(d, pick) returns a failure message or
// nothing. The cases run as plain calls; the first that fails is run again under
// RapidCheck (one test, id "<test>#seed=S,case=i"), which shrinks its picks and reports it with
// its RC_PARAMS="reproduce=..." string. RC_PARAMS="reproduce=..." replays such a case: the
// property it names runs that case alone, the others are skipped. Prints the number of
// cases of each generator.
template <class T, class Shape, class Body> void run_cases(Body body) {
    namespace rcd = ::rc::detail;
    const rcd::Configuration& config = rcd::configuration();
    std::string error;
    Plan<T, Shape> plan{config.testParams.seed, std::uint64_t(config.testParams.maxSuccess),
                        case_from_environment(error)};
    ASSERT_TRUE(error.empty()) << error;
    const std::string test = current_test();

    // The id names the test, the suite seed and the case: a reproduce string carries them.
    const std::string prefix = test + "#seed=";
    const auto under_rapidcheck = [&](std::uint64_t i) {
        rcd::TestMetadata meta;
        meta.id = prefix + std::to_string(plan.suite_seed) + ",case=" + std::to_string(i);
        meta.description = meta.id;
        rcd::TestParams params = config.testParams;
        params.maxSuccess = 1;
        const auto result = rcd::checkTestable(
            [&] {
                const Drawn<T, Shape> d{&plan, i, plan.make(i)};
                if (const std::optional<std::string> failure = body(d, RapidPick{}))
                    RC_FAIL(*failure + "\n  " + d.where());
            },
            meta, params);
        std::ostringstream os;
        rcd::printResultMessage(result, os);
        if (result.template is<rcd::SuccessResult>())
            ADD_FAILURE() << "case " << i << " failed, then passed when run again under RapidCheck (a property "
                          << "that is not a function of its case?)\n  "
                          << Drawn<T, Shape>{&plan, i, plan.make(i)}.where();
        else
            ADD_FAILURE() << os.str();
    };

    if (!config.reproduce.empty()) {
        for (const auto& entry : config.reproduce) {
            const std::string& id = entry.first;
            const auto comma = id.find(",case=");
            if (id.compare(0, prefix.size(), prefix) == 0 && comma != std::string::npos) {
                plan.suite_seed = std::stoull(id.substr(prefix.size(), comma - prefix.size()));
                under_rapidcheck(std::stoull(id.substr(comma + 6)));
                return;
            }
        }
        GTEST_SKIP() << "RC_PARAMS reproduce= names other properties";
    }
    std::vector<std::uint64_t> count(plan.generator_count(), 0);
    for (std::uint64_t i = plan.first(); i < plan.end(); ++i) {
        ++count[plan.generator_of(i)];
        const Drawn<T, Shape> d{&plan, i, plan.make(i)};
        if (body(d, PlainPick{})) {
            under_rapidcheck(i);
            break;
        }
    }
    std::cout << shares_text<T, Shape>(count) << '\n';
}

// Calls f(mode) for each mode the kernel answers for (T, Shape).
template <class T, class Shape, class F> void for_each_mode(F&& f) {
    if constexpr (Answerable<T, Shape, fast_t>) f(fast);
    if constexpr (Answerable<T, Shape, conservative_t>) f(conservative);
    if constexpr (Answerable<T, Shape, certified_t>) f(certified);
}

template <class T> bool same_bits(T a, T b) { return std::memcmp(&a, &b, sizeof(T)) == 0; }
template <class T> bool identical(const Hit<T>& a, const Hit<T>& b) {
    return a.verdict == b.verdict && a.face == b.face && same_bits(a.t_enter, b.t_enter) && same_bits(a.t_exit, b.t_exit);
}
// Two faithful roundings of the same exact value: equal, or adjacent floats.
template <class T> bool same_or_adjacent(T a, T b) {
    return a == b || std::nextafter(a, std::numeric_limits<T>::infinity()) == b ||
           std::nextafter(b, std::numeric_limits<T>::infinity()) == a;
}

template <class T, class Shape, class Mode> std::string skip_reason(Mode m) {
    return std::string("the ") + mode_name(m) + " mode is not available for " + std::string(gen::shape_name<Shape>()) +
           "<" + std::string(gen::scalar_name<T>()) + "> in this build (rayproof::Answerable is false)";
}

// The bits of a case's input (ray and shape), to compare inputs exactly.
template <class T> void append_bits(std::string& out, T x) { out.append(reinterpret_cast<const char*>(&x), sizeof x); }
template <class T, int R, int C> void append_bits(std::string& out, const Eigen::Matrix<T, R, C>& m) {
    for (Eigen::Index i = 0; i < m.size(); ++i) append_bits(out, m.data()[i]);
}
template <class T> void append_shape(std::string& out, const Aabb<T>& b) {
    append_bits(out, b.lo), append_bits(out, b.hi);
}
template <class T> void append_shape(std::string& out, const Obb<T>& b) {
    append_bits(out, b.center), append_bits(out, b.axes), append_bits(out, b.half_extent);
}
template <class T> void append_shape(std::string& out, const Plane<T>& p) {
    append_bits(out, p.normal), append_bits(out, p.offset);
}
template <class T> void append_shape(std::string& out, const Sphere<T>& s) {
    append_bits(out, s.center), append_bits(out, s.radius);
}
template <class T, class Shape> std::string input_bytes(const gen::Case<T, Shape>& c) {
    std::string out;
    append_bits(out, c.ray.origin), append_bits(out, c.ray.direction), append_bits(out, c.ray.t_min),
        append_bits(out, c.ray.t_max);
    append_shape(out, c.shape);
    return out;
}

// Salts of the choices a property makes beyond the input (Plan::choice).
inline constexpr std::uint64_t kScaleSalt = 1, kPermutationSalt = 2, kBatchSalt = 3, kScaledOracleSalt = 4;

// The exact power-of-two scaling of case c that `choice` picks (choose_scaling, strata.hpp),
// with k and j passed through RapidCheck's `pick` so that a failure shrinks them towards
// ±1 and 0 (a shrunk pair that does not scale exactly is discarded). Nothing when no
// k != 0 scales c exactly.
template <class T, class Shape> struct ScaledCase {
    int k, j;
    gen::Case<T, Shape> c;  // the scaled case
};
template <class T, class Shape, class Pick>
std::optional<ScaledCase<T, Shape>> scaled_case(const gen::Case<T, Shape>& c, std::uint64_t choice, Pick pick) {
    const std::optional<Scaling> chosen = choose_scaling(c, choice);
    if (!chosen) return std::nullopt;
    ScaledCase<T, Shape> s{pick(chosen->k, chosen->k < 0 ? -1 : 1), pick(chosen->j, 0), c};
    if (!scale_exactly(s.c, s.k, s.j)) {
        RC_DISCARD("a shrunk exponent that does not scale exactly");
    }
    return s;
}

// A certified batch's lane path (detail/ray_aabb_batch.hpp, detail/ray_plane_batch.hpp:
// detail::batch::certified_lanes) in backend B, called directly (batch_of takes it only
// where it pays, so the batch property of the Tester may not reach it): for a span of R
// (Ray or PreparedRay), intersect and verdict, each element equals the scalar certified
// answer bit for bit (which CertifiedEqualsOracle judges against the exact oracle).
template <class B, class R, class T, class Shape>
std::optional<std::string> lanes_equal_scalar(const std::vector<Ray<T>>& in, const Shape& shape) {
    std::vector<R> rs;
    for (const Ray<T>& r : in) rs.push_back(R(r));
    const auto prepared = detail::prepare(shape);
    std::vector<Hit<T>> hits(rs.size());
    std::vector<Verdict> verdicts(rs.size());
    detail::batch::certified_lanes<B>(std::span<const R>(rs), prepared, std::span<Hit<T>>(hits));
    detail::batch::certified_lanes<B>(std::span<const R>(rs), prepared, std::span<Verdict>(verdicts));
    for (std::size_t i = 0; i < rs.size(); ++i) {
        const Hit<T> s = intersect(rs[i], shape, certified);
        if (!identical(s, hits[i]) || verdicts[i] != s.verdict) {
            std::ostringstream os;
            os << (std::is_same_v<B, detail::simd::portable> ? "portable" : "native")
               << (detail::is_prepared_ray_v<R> ? " prepared" : " ray") << " element " << i << " of " << rs.size()
               << " " << in[i] << ": lanes " << hits[i] << " / " << verdicts[i] << ", scalar " << s;
            return os.str();
        }
    }
    return std::nullopt;
}

// The lane property over the run's cases: the batch is case i's ray followed by more rays
// of its generator (W to 4W + W - 1 of them, so that the case's ray and its neighbours
// fill whole blocks and a partial one; shrunk towards W), against case i's shape, in both
// backends, for Ray and PreparedRay spans.
template <class T, class Shape> void lane_batch_equals_scalar() {
    run_cases<T, Shape>([](const auto& d, auto pick) -> std::optional<std::string> {
        constexpr int W = detail::batch::kBatchLanes;
        const auto& g = gen::generators<T, Shape>()[d.plan->generator_of(d.index)];
        const auto n = std::size_t(pick(W + int(d.choice(kBatchSalt) % (4 * W)), W));
        gen::Rng rng(d.seed());
        const auto first = g.make(rng);  // == d.c
        std::vector<Ray<T>> rays{first.ray};
        while (rays.size() < n) rays.push_back(g.make(rng).ray);
        namespace simd = detail::simd;
        if (auto f = lanes_equal_scalar<simd::portable, Ray<T>>(rays, first.shape)) return f;
        if (auto f = lanes_equal_scalar<simd::native, Ray<T>>(rays, first.shape)) return f;
        if (auto f = lanes_equal_scalar<simd::portable, PreparedRay<T>>(rays, first.shape)) return f;
        return lanes_equal_scalar<simd::native, PreparedRay<T>>(rays, first.shape);
    });
}

template <class T, class Shape> struct Tester {
    static constexpr bool has_conservative = Answerable<T, Shape, conservative_t>;
    static constexpr bool has_certified = Answerable<T, Shape, certified_t>;

    using Failure = std::optional<std::string>;

    // Every mode answers invalid exactly for the inputs the contract calls invalid.
    static void invalid_agrees() {
        run_cases<T, Shape>([](const auto& d, auto) -> Failure {
            const auto e = oracle::exact(d.c.ray, d.c.shape);
            const bool exact_invalid = e.verdict == Verdict::invalid;
            Failure failure;
            for_each_mode<T, Shape>([&](auto mode) {
                const Hit<T> h = intersect(d.c.ray, d.c.shape, mode);
                if (!failure && oracle::check_contract(d.c.ray, d.c.shape, h, e, mode).invalid_mismatch())
                    failure = std::string(mode_name(mode)) + " answered " + to_string(h.verdict) +
                              ", exact validity is " + (exact_invalid ? "invalid" : "valid");
            });
            return failure;
        });
    }

    // conservative: never a false miss, the interval encloses the exact one.
    static void conservative_encloses() {
        if constexpr (!has_conservative) {
            GTEST_SKIP() << skip_reason<T, Shape>(conservative);
        } else {
            run_cases<T, Shape>([](const auto& d, auto) -> Failure {
                const auto e = oracle::exact(d.c.ray, d.c.shape);
                const Hit<T> h = intersect(d.c.ray, d.c.shape, conservative);
                const auto c = oracle::check_contract(d.c.ray, d.c.shape, h, e, conservative);
                if (!c.promise_broken()) return std::nullopt;
                std::ostringstream os;
                os << "conservative " << h << "\n  " << e << "\n  " << c.mode_judgement();
                return os.str();
            });
        }
    }

    // certified: the exact verdict and face, each t a faithful rounding of the exact one.
    static void certified_exact() {
        if constexpr (!has_certified) {
            GTEST_SKIP() << skip_reason<T, Shape>(certified);
        } else {
            run_cases<T, Shape>([](const auto& d, auto) -> Failure {
                const auto e = oracle::exact(d.c.ray, d.c.shape);
                const Hit<T> h = intersect(d.c.ray, d.c.shape, certified);
                const auto c = oracle::check_contract(d.c.ray, d.c.shape, h, e, certified);
                if (!c.promise_broken()) return std::nullopt;
                std::ostringstream os;
                os << "certified " << h << "\n  " << e << "\n  " << c.mode_judgement();
                return os.str();
            });
        }
    }

    // Oracle-free: a hit's interval is ordered (conservative, certified), and for certified
    // it lies in [t_min, t_max] (faithful roundings of values in a range with representable
    // ends stay in it). A miss carries no interval, so only this direction is checked.
    static void verdict_agrees_with_interval() {
        if constexpr (!has_conservative && !has_certified) {
            GTEST_SKIP() << skip_reason<T, Shape>(certified) << "; neither is the conservative mode";
        } else {
            run_cases<T, Shape>([](const auto& d, auto) -> Failure {
                Failure failure;
                const auto check = [&](auto mode, bool in_range) {
                    const Hit<T> h = intersect(d.c.ray, d.c.shape, mode);
                    if (failure || h.verdict != Verdict::hit) return;
                    bool ok = h.t_enter <= h.t_exit;
                    if (in_range) ok = ok && d.c.ray.t_min <= h.t_enter && h.t_exit <= d.c.ray.t_max;
                    if (!ok) {
                        std::ostringstream os;
                        os << mode_name(mode) << " " << h << " is not an ordered interval"
                           << (in_range ? " within [t_min, t_max]" : "");
                        failure = os.str();
                    }
                };
                if constexpr (has_conservative) check(conservative, false);
                if constexpr (has_certified) check(certified, true);
                return failure;
            });
        }
    }

    // Oracle-free: scaling every position and the direction by 2^k (and the Obb axes or
    // the plane normal by 2^j) is exact and leaves the exact answer unchanged, so certified
    // must give the same verdict and face and, for each t, the same value or the adjacent
    // float (both are faithful roundings of one exact value; the contract allows either).
    // k != 0 always (choose_scaling, strata.hpp); a case no k != 0 scales exactly (a NaN
    // or infinite input, values at both ends of the range) has nothing to compare. On a
    // failure RapidCheck shrinks k towards ±1 and j towards 0.
    static void certified_scale_invariant() {
        if constexpr (!has_certified) {
            GTEST_SKIP() << skip_reason<T, Shape>(certified);
        } else {
            run_cases<T, Shape>([](const auto& d, auto pick) -> Failure {
                const std::optional<ScaledCase<T, Shape>> s = scaled_case(d.c, d.choice(kScaleSalt), pick);
                if (!s) return std::nullopt;
                const int k = s->k, j = s->j;
                const gen::Case<T, Shape>& scaled = s->c;
                const Hit<T> a = intersect(d.c.ray, d.c.shape, certified);
                const Hit<T> b = intersect(scaled.ray, scaled.shape, certified);
                if (a.verdict == b.verdict && a.face == b.face &&
                    (a.verdict != Verdict::hit ||
                     (same_or_adjacent(a.t_enter, b.t_enter) && same_or_adjacent(a.t_exit, b.t_exit))))
                    return std::nullopt;
                std::ostringstream os;
                os << "certified " << a << " but after scaling by 2^" << k << " (axes 2^" << j << ") " << b
                   << "\n  scaled " << scaled;
                return os.str();
            });
        }
    }

    // Judged by the oracle: every case moved by an exact power-of-two scaling (its own
    // draw of k and j, as above) to another part of the exponent range, where the bounds'
    // terms and products may be subnormal or huge, still gets conservative and certified
    // answers that keep their promises (against the exact answer of the scaled input).
    // The scale-invariance property above compares certified with itself; this one
    // catches a bound that holds at one magnitude and not at another, in either mode.
    static void scaled_cases_meet_contract() {
        if constexpr (!has_conservative && !has_certified) {
            GTEST_SKIP() << skip_reason<T, Shape>(certified) << "; neither is the conservative mode";
        } else {
            run_cases<T, Shape>([](const auto& d, auto pick) -> Failure {
                const std::optional<ScaledCase<T, Shape>> s = scaled_case(d.c, d.choice(kScaledOracleSalt), pick);
                if (!s) return std::nullopt;
                const int k = s->k, j = s->j;
                const gen::Case<T, Shape>& scaled = s->c;
                const auto e = oracle::exact(scaled.ray, scaled.shape);
                Failure failure;
                auto check = [&](auto mode, const char* name) {
                    if (failure) return;
                    const Hit<T> h = intersect(scaled.ray, scaled.shape, mode);
                    const auto c = oracle::check_contract(scaled.ray, scaled.shape, h, e, mode);
                    if (!c.promise_broken()) return;
                    std::ostringstream os;
                    os << name << " " << h << " after scaling by 2^" << k << " (axes 2^" << j << ")\n  " << e
                       << "\n  " << c.mode_judgement() << "\n  scaled " << scaled;
                    failure = os.str();
                };
                if constexpr (has_conservative) check(conservative, "conservative");
                if constexpr (has_certified) check(certified, "certified");
                return failure;
            });
        }
    }

    // Oracle-free: renaming the axes permutes the faces. With the lowest-axis tie rule, a
    // face may move to another tied axis, which is only possible if both answers name a
    // tied axis that the other rejected for a lower one: new face axis b and old face axis
    // a satisfy perm[b] > a and b < perm⁻¹(a).
    static void certified_permutation() {
        if constexpr (!has_certified) {
            GTEST_SKIP() << skip_reason<T, Shape>(certified);
        } else {
            run_cases<T, Shape>([](const auto& d, auto pick) -> Failure {
                static constexpr std::array<std::array<int, 3>, 5> perms = {
                    {{0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
                const auto& p = perms[std::size_t(pick(int(d.choice(kPermutationSalt) % perms.size()), 0))];
                const auto q = gen::permute_axes(d.c, p);
                const Hit<T> a = intersect(d.c.ray, d.c.shape, certified);
                const Hit<T> b = intersect(q.ray, q.shape, certified);
                bool ok = a.verdict == b.verdict;
                if (ok && a.verdict == Verdict::hit) {
                    ok = same_or_adjacent(a.t_enter, b.t_enter) && same_or_adjacent(a.t_exit, b.t_exit);
                    if (a.face < 0 || b.face < 0) {
                        ok = ok && a.face == b.face;
                    } else {
                        const int old_axis = a.face / 2, new_axis = b.face / 2;
                        int expected = 0;
                        while (p[expected] != old_axis) ++expected;
                        const bool same = new_axis == expected && a.face % 2 == b.face % 2;
                        const bool tie = p[new_axis] > old_axis && new_axis < expected;
                        ok = ok && (same || tie);
                        if constexpr (std::is_same_v<Shape, Aabb<T>>)  // the side is the direction's sign
                            ok = ok && b.face % 2 == int(std::signbit(q.ray.direction[new_axis]));
                    }
                }
                if (ok) return std::nullopt;
                std::ostringstream os;
                os << "certified " << a << " but with axes permuted (" << p[0] << p[1] << p[2] << ") " << b
                   << "\n  permuted " << q;
                return os.str();
            });
        }
    }

    // Oracle-free: the reversed ray (o, -d, [-t_max, -t_min]) covers the same points, so its
    // interval is the mirror image [-t_exit, -t_enter] (negation is exact; each end may be
    // the other faithful rounding).
    static void certified_reversal() {
        if constexpr (!has_certified) {
            GTEST_SKIP() << skip_reason<T, Shape>(certified);
        } else {
            run_cases<T, Shape>([](const auto& d, auto) -> Failure {
                const Ray<T> r = reversed(d.c.ray);
                const Hit<T> a = intersect(d.c.ray, d.c.shape, certified);
                const Hit<T> b = intersect(r, d.c.shape, certified);
                if (a.verdict == b.verdict &&
                    (a.verdict != Verdict::hit ||
                     (same_or_adjacent(b.t_enter, T(-a.t_exit)) && same_or_adjacent(b.t_exit, T(-a.t_enter)))))
                    return std::nullopt;
                std::ostringstream os;
                os << "certified " << a << " but reversed " << b << "\n  reversed ray " << r;
                return os.str();
            });
        }
    }

    // The batch form equals the scalar form element by element, bit for bit, in the
    // certified and conservative modes; in fast mode, which promises nothing (CONTRACT:
    // a vectorized or contracted batch path may round differently), in validity only. The
    // batch is case i's ray followed by n - 1 more rays of its generator from the same Rng
    // (n in [1, 16], shrunk towards 1 on a failure), against case i's shape.
    static void batch_equals_scalar() {
        run_cases<T, Shape>([](const auto& d, auto pick) -> Failure {
            const auto& g = gen::generators<T, Shape>()[d.plan->generator_of(d.index)];
            const auto n = std::size_t(pick(1 + int(d.choice(kBatchSalt) % 16), 1));
            gen::Rng rng(d.seed());
            const auto first = g.make(rng);  // == d.c
            std::vector<Ray<T>> rays{first.ray};
            while (rays.size() < n) rays.push_back(g.make(rng).ray);
            Failure failure;
            for_each_mode<T, Shape>([&](auto mode) {
                std::vector<Hit<T>> out(rays.size());
                intersect(std::span<const Ray<T>>(rays), first.shape, mode, std::span<Hit<T>>(out));
                for (std::size_t i = 0; i < rays.size() && !failure; ++i) {
                    const Hit<T> s = intersect(rays[i], first.shape, mode);
                    const bool fast_mode = std::is_same_v<decltype(mode), fast_t>;
                    if (fast_mode ? (s.verdict == Verdict::invalid) != (out[i].verdict == Verdict::invalid)
                                  : !identical(s, out[i])) {
                        std::ostringstream os;
                        os << mode_name(mode) << " ray " << i << " of " << n << " " << rays[i] << ": batch " << out[i]
                           << ", scalar " << s;
                        failure = os.str();
                    }
                }
            });
            return failure;
        });
    }

    // verdict() (the verdict alone), scalar and batch, equals the full answer's verdict
    // in the certified and conservative modes (in fast mode, which promises nothing, in
    // validity only), and in certified mode the oracle's verdict (so a verdict path of
    // its own, as the certified Aabb has, cannot drift from the full query).
    static void verdict_query_equals_full_query() {
        run_cases<T, Shape>([](const auto& d, auto) -> Failure {
            const Verdict exact = oracle::exact(d.c.ray, d.c.shape).verdict;
            const std::vector<Ray<T>> rays{d.c.ray, reversed(d.c.ray)};
            Failure failure;
            for_each_mode<T, Shape>([&](auto mode) {
                if (failure) return;
                std::vector<Verdict> batch(rays.size());
                verdict(std::span<const Ray<T>>(rays), d.c.shape, mode, std::span<Verdict>(batch));
                for (std::size_t i = 0; i < rays.size() && !failure; ++i) {
                    const Hit<T> full = intersect(rays[i], d.c.shape, mode);
                    const Verdict alone = verdict(rays[i], d.c.shape, mode);
                    const auto agree = [&](Verdict v) {
                        if constexpr (std::is_same_v<decltype(mode), fast_t>)
                            return (v == Verdict::invalid) == (full.verdict == Verdict::invalid);
                        return v == full.verdict;
                    };
                    if (!agree(alone) || !agree(batch[i])) {
                        std::ostringstream os;
                        os << mode_name(mode) << (i ? " (reversed ray)" : "") << ": verdict() " << alone << ", batch "
                           << batch[i] << ", full answer " << full;
                        failure = os.str();
                    }
                }
                if constexpr (std::is_same_v<decltype(mode), certified_t>) {
                    if (!failure && verdict(d.c.ray, d.c.shape, mode) != exact) {
                        std::ostringstream os;
                        os << "certified verdict() " << verdict(d.c.ray, d.c.shape, mode) << ", exact " << exact;
                        failure = os.str();
                    }
                }
            });
            return failure;
        });
    }

    // PreparedRay (prepared_ray.hpp): the certified answer of the prepared ray equals the
    // Ray's bit for bit (verdict, t_enter, t_exit, face; -0 and +0 told apart), and so does
    // its verdict(); the prepared conservative answer meets the mode's contract against the
    // exact oracle (invalid exactly where the input is). On the case's ray and on the
    // reversed ray (whose direction has every sign flipped, -0 included).
    static void prepared_ray_equals_ray() {
        run_cases<T, Shape>([](const auto& d, auto) -> Failure {
            const auto e = oracle::exact(d.c.ray, d.c.shape);
            Failure failure;
            const std::array<Ray<T>, 2> rays{d.c.ray, reversed(d.c.ray)};
            for (std::size_t i = 0; i < rays.size(); ++i) {
                const Ray<T>& r = rays[i];
                const bool rev = i == 1;
                const PreparedRay<T> p(r);
                if constexpr (has_certified) {
                    const Hit<T> hp = intersect(p, d.c.shape, certified), hr = intersect(r, d.c.shape, certified);
                    const Verdict vp = verdict(p, d.c.shape, certified);
                    if (!failure && (!identical(hp, hr) || vp != hr.verdict)) {
                        std::ostringstream os;
                        os << "certified" << (rev ? " (reversed ray)" : "") << ": prepared " << hp << ", verdict() "
                           << vp << "; ray " << hr;
                        failure = os.str();
                    }
                }
                if constexpr (has_conservative) {
                    if (!failure && !rev) {
                        const Hit<T> h = intersect(p, d.c.shape, conservative);
                        const auto c = oracle::check_contract(r, d.c.shape, h, e, conservative);
                        if (c.promise_broken() || c.invalid_mismatch()) {
                            std::ostringstream os;
                            os << "prepared conservative " << h << "\n  " << e << "\n  " << c.mode_judgement();
                            failure = os.str();
                        }
                    }
                }
            }
            return failure;
        });
    }

    // The mix of a run (strata.hpp) at the suite's own case count and seed: every generator
    // gets at least floor(N/G) of the N cases, no two cases have the same input (bit for
    // bit), and the scaling property scales every case by 2^k with k != 0, exactly, except
    // the cases that neither k = 1 nor k = -1 scales exactly (counted and printed).
    static void stratified_shares() {
        const auto& params = rc::detail::configuration().testParams;
        const Plan<T, Shape> plan{params.seed, std::uint64_t(params.maxSuccess), std::nullopt};
        const auto gens = gen::generators<T, Shape>();
        const std::vector<std::uint64_t> n = shares(plan);
        std::uint64_t total = 0;
        for (std::size_t g = 0; g < gens.size(); ++g) {
            total += n[g];
            EXPECT_GE(n[g], plan.cases / gens.size()) << gens[g].name << " gets less than 1/G of the cases";
        }
        EXPECT_EQ(total, plan.cases);

        std::unordered_map<std::string, std::uint64_t> seen;
        std::vector<std::uint64_t> unscaled(gens.size(), 0), repeated(gens.size(), 0);
        for (std::uint64_t i = 0; i < plan.cases; ++i) {
            const auto c = plan.make(i);
            const std::size_t g = plan.generator_of(i);
            const auto [at, fresh] = seen.emplace(input_bytes(c), i);
            if (!fresh && ++repeated[g] <= 3)
                ADD_FAILURE() << "cases " << at->second << " and " << i << " have the same input: " << c;
            if (const auto s = choose_scaling(c, plan.choice(i, kScaleSalt))) {
                auto scaled = c;
                EXPECT_NE(s->k, 0) << "case " << i << ": " << c;
                EXPECT_TRUE(scale_exactly(scaled, s->k, s->j))
                    << "case " << i << ": 2^" << s->k << " (axes 2^" << s->j << ") is not exact: " << c;
            } else {
                ++unscaled[g];
                auto up = c, down = c;
                EXPECT_FALSE(scale_exactly(up, 1, 0) || scale_exactly(down, -1, 0))
                    << "case " << i << " is left unscaled, yet 2^±1 scales it exactly: " << c;
            }
        }
        std::ostringstream os;
        os << shares_text<T, Shape>(n) << "\n  distinct inputs " << seen.size() << " of " << plan.cases
           << "; cases no 2^k (k != 0) scales exactly:";
        for (std::size_t g = 0; g < gens.size(); ++g) os << ' ' << gens[g].name << ' ' << unscaled[g];
        std::cout << os.str() << '\n';
    }

    // The fast mode promises no accuracy: its wrong answers are counted per generator and
    // printed (and recorded as test properties), not asserted. Asserted: what the fast
    // mode does promise (invalid inputs answered invalid, and nothing else answered
    // invalid), and that each generator delivers what its name says (the invalid one only
    // invalid inputs, the others valid ones).
    static void fast_mode_error_counts() {
        constexpr int kCases = 2000;
        std::ostringstream table;
        table << "fast mode vs exact, " << gen::shape_name<Shape>() << '<' << gen::scalar_name<T>() << ">, " << kCases
              << " cases per generator:\n";
        for (const auto& g : gen::generators<T, Shape>()) {
            gen::Rng rng(0xfa57 ^ gen::name_hash(g.name));
            oracle::Tally t;
            int invalid = 0;
            for (int i = 0; i < kCases; ++i) {
                const auto c = g.make(rng);
                const auto e = oracle::exact(c.ray, c.shape);
                const Hit<T> h = intersect(c.ray, c.shape, fast);
                const auto check = oracle::check_contract(c.ray, c.shape, h, e, fast);
                invalid += e.verdict == Verdict::invalid;
                ASSERT_FALSE(check.promise_broken())  // the fast mode's promise: validity
                    << "fast " << h << " vs " << e << "\n  " << g.name << " case " << i << ": " << c;
                ++t.cases;
                t.count_outcome(check.judgement);
                if (h.verdict == Verdict::hit && e.verdict == Verdict::hit) t.count_interval(check.judgement);
                t.count_coherence(h);
            }
            const std::uint64_t wrong = t.wrong(), false_miss = t.false_miss, false_hit = t.false_hit,
                                face = t.face_mismatch, unfaithful = t.t_off, incoherent = t.incoherent,
                                max_ulps = t.max_ulps;
            if (g.name == "invalid") {
                EXPECT_EQ(invalid, kCases) << "the invalid generator made valid inputs";
            } else if (g.name == "log_uniform") {
                EXPECT_LT(invalid, kCases / 100) << "log_uniform: too many invalid inputs (dependent Obb axes?)";
            } else {
                EXPECT_EQ(invalid, 0) << g.name << " made invalid inputs";
            }
            table << "  " << g.name << ": wrong verdicts " << wrong << " (false hits " << false_hit
                  << ", false misses " << false_miss << "), face mismatches " << face << ", t not faithful "
                  << unfaithful << ", max t error "
                  << (max_ulps == std::numeric_limits<std::uint64_t>::max() ? std::string("NaN")
                                                                            : std::to_string(max_ulps))
                  << " ulps, hits with t_enter > t_exit or NaN " << incoherent << '\n';
            ::testing::Test::RecordProperty(std::string(g.name) + "_wrong_verdicts", int(wrong));
            ::testing::Test::RecordProperty(std::string(g.name) + "_false_misses", int(false_miss));
        }
        std::cout << table.str();
    }
};

}  // namespace rayproof::props

// The properties common to all shapes, for float and double. Suite is the test suite
// name, ShapeTemplate one of rayproof::Aabb, Obb, Plane, Sphere.
#define RAYPROOF_PROPERTY_SUITE(Suite, ShapeTemplate)                                                          \
    template <class T> class Suite : public ::testing::Test {};                                                 \
    TYPED_TEST_SUITE(Suite, ::rayproof::props::Scalars, ::rayproof::props::ScalarNames);                        \
    template <class T> using Suite##Tester = ::rayproof::props::Tester<T, ShapeTemplate<T>>;                    \
    TYPED_TEST(Suite, InvalidVerdictAgreesWithOracle) { Suite##Tester<TypeParam>::invalid_agrees(); }          \
    TYPED_TEST(Suite, ConservativeNeverMissesAndEncloses) { Suite##Tester<TypeParam>::conservative_encloses(); } \
    TYPED_TEST(Suite, CertifiedEqualsOracle) { Suite##Tester<TypeParam>::certified_exact(); }                  \
    TYPED_TEST(Suite, VerdictAgreesWithInterval) { Suite##Tester<TypeParam>::verdict_agrees_with_interval(); } \
    TYPED_TEST(Suite, CertifiedPowerOfTwoScalingKeepsT) { Suite##Tester<TypeParam>::certified_scale_invariant(); } \
    TYPED_TEST(Suite, ScaledCaseMeetsContract) { Suite##Tester<TypeParam>::scaled_cases_meet_contract(); }     \
    TYPED_TEST(Suite, CertifiedAxisPermutationPermutesFaces) { Suite##Tester<TypeParam>::certified_permutation(); } \
    TYPED_TEST(Suite, CertifiedReversalMirrorsInterval) { Suite##Tester<TypeParam>::certified_reversal(); }    \
    TYPED_TEST(Suite, BatchEqualsScalar) { Suite##Tester<TypeParam>::batch_equals_scalar(); }                  \
    TYPED_TEST(Suite, VerdictQueryEqualsFullQuery) { Suite##Tester<TypeParam>::verdict_query_equals_full_query(); } \
    TYPED_TEST(Suite, PreparedRayEqualsRay) { Suite##Tester<TypeParam>::prepared_ray_equals_ray(); }           \
    TYPED_TEST(Suite, FastModeErrorsPerGenerator) { Suite##Tester<TypeParam>::fast_mode_error_counts(); }      \
    TYPED_TEST(Suite, StratifiedShares) { Suite##Tester<TypeParam>::stratified_shares(); }
