// props_support.hpp — the property tester shared by the four property suites: one
// template over the scalar type and the shape, instantiated for float and double by
// RAYPROOF_PROPERTY_SUITE in each suite's file.
//
// Cases come from the shared generators (rayproof/generators.hpp): RapidCheck draws a
// generator and a 64-bit seed, so every generator (general position, log-uniform, exact
// grazing, near grazing, ±0 directions, boundary origins, extreme scenes, invalid inputs)
// feeds every property, and a failure prints the call that rebuilds the case,
//   rayproof::gen::make_case<double, rayproof::Aabb<double>>("grazing", 0x...)
// together with the inputs in hexfloat and RapidCheck's own reproduce string. What each
// mode promises against the exact oracle is decided by the shared contract checker
// (rayproof/oracle/contract.hpp), as in the fuzz targets and the audit.
//
// A property about a mode the kernel does not provide (rayproof::Answerable false) is
// skipped with GTEST_SKIP and its reason, never passed silently.
#pragma once

#include <rayproof/generators.hpp>
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

// A case drawn by RapidCheck: a generator of the shape and a seed.
template <class T, class Shape> struct Drawn {
    gen::Case<T, Shape> c;
    std::uint64_t seed;
    std::string where() const {
        std::ostringstream os;
        os << reproducer<T, Shape>(c.generator, seed) << "\n  " << c;
        return os.str();
    }
};
template <class T, class Shape> Drawn<T, Shape> draw() {
    const auto gens = gen::generators<T, Shape>();
    const auto i = *rc::gen::inRange<std::size_t>(0, gens.size());
    const auto seed = *rc::gen::arbitrary<std::uint64_t>();
    gen::Rng rng(seed);
    Drawn<T, Shape> d{gens[i].make(rng), seed};
    RC_LOG() << d.where() << '\n';
    return d;
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

template <class T, class Shape> struct Tester {
    static constexpr bool has_conservative = Answerable<T, Shape, conservative_t>;
    static constexpr bool has_certified = Answerable<T, Shape, certified_t>;

    // Every mode answers invalid exactly for the inputs the contract calls invalid.
    static void invalid_agrees() {
        rc::detail::checkGTest([] {
            const auto d = draw<T, Shape>();
            const auto e = oracle::exact(d.c.ray, d.c.shape);
            const bool exact_invalid = e.verdict == Verdict::invalid;
            for_each_mode<T, Shape>([&](auto mode) {
                const Hit<T> h = intersect(d.c.ray, d.c.shape, mode);
                if (oracle::check_contract(d.c.ray, d.c.shape, h, e, mode).invalid_mismatch())
                    RC_FAIL(std::string(mode_name(mode)) + " answered " + to_string(h.verdict) + ", exact validity is " +
                            (exact_invalid ? "invalid" : "valid") + "\n  " + d.where());
            });
        });
    }

    // conservative: never a false miss, the interval encloses the exact one.
    static void conservative_encloses() {
        if constexpr (!has_conservative) {
            GTEST_SKIP() << skip_reason<T, Shape>(conservative);
        } else {
            rc::detail::checkGTest([] {
                const auto d = draw<T, Shape>();
                const auto e = oracle::exact(d.c.ray, d.c.shape);
                const Hit<T> h = intersect(d.c.ray, d.c.shape, conservative);
                const auto c = oracle::check_contract(d.c.ray, d.c.shape, h, e, conservative);
                if (c.promise_broken()) {
                    std::ostringstream os;
                    os << "conservative " << h << "\n  " << e << "\n  " << c.mode_judgement() << "\n  " << d.where();
                    RC_FAIL(os.str());
                }
            });
        }
    }

    // certified: the exact verdict and face, each t a faithful rounding of the exact one.
    static void certified_exact() {
        if constexpr (!has_certified) {
            GTEST_SKIP() << skip_reason<T, Shape>(certified);
        } else {
            rc::detail::checkGTest([] {
                const auto d = draw<T, Shape>();
                const auto e = oracle::exact(d.c.ray, d.c.shape);
                const Hit<T> h = intersect(d.c.ray, d.c.shape, certified);
                const auto c = oracle::check_contract(d.c.ray, d.c.shape, h, e, certified);
                if (c.promise_broken()) {
                    std::ostringstream os;
                    os << "certified " << h << "\n  " << e << "\n  " << c.mode_judgement() << "\n  " << d.where();
                    RC_FAIL(os.str());
                }
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
            rc::detail::checkGTest([] {
                const auto d = draw<T, Shape>();
                const auto check = [&](auto mode, bool in_range) {
                    const Hit<T> h = intersect(d.c.ray, d.c.shape, mode);
                    if (h.verdict != Verdict::hit) return;
                    bool ok = h.t_enter <= h.t_exit;
                    if (in_range) ok = ok && d.c.ray.t_min <= h.t_enter && h.t_exit <= d.c.ray.t_max;
                    if (!ok) {
                        std::ostringstream os;
                        os << mode_name(mode) << " " << h << " is not an ordered interval"
                           << (in_range ? " within [t_min, t_max]" : "") << "\n  " << d.where();
                        RC_FAIL(os.str());
                    }
                };
                if constexpr (has_conservative) check(conservative, false);
                if constexpr (has_certified) check(certified, true);
            });
        }
    }

    // Oracle-free: scaling every position and the direction by 2^k (and the Obb axes or
    // the plane normal by 2^j) is exact and leaves the exact answer unchanged, so certified
    // must give the same verdict and face and, for each t, the same value or the adjacent
    // float (both are faithful roundings of one exact value; the contract allows either).
    static void certified_scale_invariant() {
        if constexpr (!has_certified) {
            GTEST_SKIP() << skip_reason<T, Shape>(certified);
        } else {
            rc::detail::checkGTest([] {
                const auto d = draw<T, Shape>();
                constexpr int E = std::numeric_limits<T>::max_exponent - std::numeric_limits<T>::min_exponent;
                int k = *rc::gen::inRange(-E, E + 1), j = *rc::gen::inRange(-E / 2, E / 2 + 1);
                auto scaled = d.c;
                while ((k != 0 || j != 0) && !gen::exact_scale(scaled, k, k, j)) {
                    k /= 2;
                    j /= 2;
                }
                RC_LOG() << "scaled by 2^" << k << " (axes/normal 2^" << j << "): " << scaled << '\n';
                const Hit<T> a = intersect(d.c.ray, d.c.shape, certified);
                const Hit<T> b = intersect(scaled.ray, scaled.shape, certified);
                if (a.verdict != b.verdict || a.face != b.face ||
                    (a.verdict == Verdict::hit &&
                     (!same_or_adjacent(a.t_enter, b.t_enter) || !same_or_adjacent(a.t_exit, b.t_exit)))) {
                    std::ostringstream os;
                    os << "certified " << a << " but after scaling by 2^" << k << " (axes 2^" << j << ") " << b
                       << "\n  scaled " << scaled << "\n  " << d.where();
                    RC_FAIL(os.str());
                }
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
            rc::detail::checkGTest([] {
                static constexpr std::array<std::array<int, 3>, 5> perms = {
                    {{0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
                const auto d = draw<T, Shape>();
                const auto& p = perms[*rc::gen::inRange<std::size_t>(0, perms.size())];
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
                if (!ok) {
                    std::ostringstream os;
                    os << "certified " << a << " but with axes permuted (" << p[0] << p[1] << p[2] << ") " << b
                       << "\n  permuted " << q << "\n  " << d.where();
                    RC_FAIL(os.str());
                }
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
            rc::detail::checkGTest([] {
                const auto d = draw<T, Shape>();
                const Ray<T> r = reversed(d.c.ray);
                const Hit<T> a = intersect(d.c.ray, d.c.shape, certified);
                const Hit<T> b = intersect(r, d.c.shape, certified);
                if (a.verdict != b.verdict ||
                    (a.verdict == Verdict::hit &&
                     (!same_or_adjacent(b.t_enter, T(-a.t_exit)) || !same_or_adjacent(b.t_exit, T(-a.t_enter))))) {
                    std::ostringstream os;
                    os << "certified " << a << " but reversed " << b << "\n  reversed ray " << r << "\n  " << d.where();
                    RC_FAIL(os.str());
                }
            });
        }
    }

    // The batch form equals the scalar form element by element, bit for bit, in the
    // certified and conservative modes; in fast mode, which promises nothing (CONTRACT:
    // a vectorized or contracted batch path may round differently), in validity only.
    static void batch_equals_scalar() {
        rc::detail::checkGTest([] {
            const auto gens = gen::generators<T, Shape>();
            const auto gi = *rc::gen::inRange<std::size_t>(0, gens.size());
            const auto seed = *rc::gen::arbitrary<std::uint64_t>();
            const auto n = *rc::gen::inRange<std::size_t>(1, 17);
            gen::Rng rng(seed);
            const auto first = gens[gi].make(rng);
            std::vector<Ray<T>> rays{first.ray};
            while (rays.size() < n) rays.push_back(gens[gi].make(rng).ray);
            RC_LOG() << "generator " << gens[gi].name << " seed 0x" << std::hex << seed << std::dec << ", " << n
                     << " rays from one Rng, shape of the first: " << first.shape << '\n';
            for_each_mode<T, Shape>([&](auto mode) {
                std::vector<Hit<T>> out(rays.size());
                intersect(std::span<const Ray<T>>(rays), first.shape, mode, std::span<Hit<T>>(out));
                for (std::size_t i = 0; i < rays.size(); ++i) {
                    const Hit<T> s = intersect(rays[i], first.shape, mode);
                    const bool fast_mode = std::is_same_v<decltype(mode), fast_t>;
                    if (fast_mode ? (s.verdict == Verdict::invalid) != (out[i].verdict == Verdict::invalid)
                                  : !identical(s, out[i])) {
                        std::ostringstream os;
                        os << mode_name(mode) << " ray " << i << " " << rays[i] << ": batch " << out[i] << ", scalar "
                           << s;
                        RC_FAIL(os.str());
                    }
                }
            });
        });
    }

    // verdict() (the verdict alone), scalar and batch, equals the full answer's verdict
    // in the certified and conservative modes (in fast mode, which promises nothing, in
    // validity only), and in certified mode the oracle's verdict (so a verdict path of
    // its own, as the certified Aabb has, cannot drift from the full query).
    static void verdict_query_equals_full_query() {
        rc::detail::checkGTest([] {
            const auto d = draw<T, Shape>();
            const Verdict exact = oracle::exact(d.c.ray, d.c.shape).verdict;
            const std::vector<Ray<T>> rays{d.c.ray, reversed(d.c.ray)};
            for_each_mode<T, Shape>([&](auto mode) {
                std::vector<Verdict> batch(rays.size());
                verdict(std::span<const Ray<T>>(rays), d.c.shape, mode, std::span<Verdict>(batch));
                for (std::size_t i = 0; i < rays.size(); ++i) {
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
                           << batch[i] << ", full answer " << full << "\n  " << d.where();
                        RC_FAIL(os.str());
                    }
                }
                if constexpr (std::is_same_v<decltype(mode), certified_t>) {
                    if (verdict(d.c.ray, d.c.shape, mode) != exact) {
                        std::ostringstream os;
                        os << "certified verdict() " << verdict(d.c.ray, d.c.shape, mode) << ", exact " << exact << "\n  "
                           << d.where();
                        RC_FAIL(os.str());
                    }
                }
            });
        });
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
    TYPED_TEST(Suite, CertifiedAxisPermutationPermutesFaces) { Suite##Tester<TypeParam>::certified_permutation(); } \
    TYPED_TEST(Suite, CertifiedReversalMirrorsInterval) { Suite##Tester<TypeParam>::certified_reversal(); }    \
    TYPED_TEST(Suite, BatchEqualsScalar) { Suite##Tester<TypeParam>::batch_equals_scalar(); }                  \
    TYPED_TEST(Suite, VerdictQueryEqualsFullQuery) { Suite##Tester<TypeParam>::verdict_query_equals_full_query(); } \
    TYPED_TEST(Suite, FastModeErrorsPerGenerator) { Suite##Tester<TypeParam>::fast_mode_error_counts(); }
