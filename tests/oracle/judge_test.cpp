// judge_test.cpp — the oracle's exact values and its judge, against hand-computed answers:
// faithful brackets of 1/3 and of an irrational sphere root (checked by independent
// integer arithmetic), brackets beyond the largest finite value and below the smallest
// denormal, ulp distances, and every outcome class of judge().
#include <rayproof/oracle/oracle.hpp>
#include <rayproof/rayproof.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

namespace {

using namespace rayproof;
using oracle::ExactValue;
using oracle::Order;
using oracle::Outcome;

using detail::step_down;
using detail::step_up;

// Ray (-1, 1/2, 1/2) + t·(3, 0, 0) against [0, 1]³: exactly [1/3, 2/3], face 0.
template <class T> oracle::Exact<T> third() {
    const Ray<T> r{{-1, 0.5, 0.5}, {3, 0, 0}};
    const Aabb<T> b{{0, 0, 0}, {1, 1, 1}};
    return oracle::exact(r, b);
}

TEST(ExactValue, OneThirdIsRationalWithTheHandComputedBracket) {
    const auto ef = third<float>();
    ASSERT_EQ(ef.verdict, Verdict::hit);
    EXPECT_EQ(ef.face, 0);
    EXPECT_EQ(ef.t_enter.kind(), ExactValue::Kind::rational);
    EXPECT_EQ(ef.t_enter.str(), "1/3");
    EXPECT_EQ(ef.t_exit.str(), "2/3");
    // 1/3 = 0x1.5555...p-2: the float neighbours end in ...554 and ...556.
    const auto bf = ef.enter_bracket();
    EXPECT_EQ(bf.lo, 0x1.555554p-2f);
    EXPECT_EQ(bf.hi, 0x1.555556p-2f);
    EXPECT_LT(3.0 * double(bf.lo), 1.0);  // exact in double: 24-bit times 2-bit
    EXPECT_GT(3.0 * double(bf.hi), 1.0);
    EXPECT_EQ(ef.enter_vs(bf.lo), Order::below);
    EXPECT_EQ(ef.enter_vs(bf.hi), Order::above);

    const auto ed = third<double>();
    const auto bd = ed.enter_bracket();
    EXPECT_EQ(bd.lo, 0x1.5555555555555p-2);
    EXPECT_EQ(bd.hi, 0x1.5555555555556p-2);
    EXPECT_LT(3.0L * static_cast<long double>(bd.lo), 1.0L);  // exact in the 64-bit long double
    EXPECT_GT(3.0L * static_cast<long double>(bd.hi), 1.0L);
    EXPECT_FALSE(bd.representable());
}

TEST(ExactValue, RepresentableValuesAreTheirOwnBracket) {
    const Ray<double> r{{-1, 0.5, 0.5}, {2, 0, 0}};
    const Aabb<double> b{{0, 0, 0}, {1, 1, 1}};
    const auto e = oracle::exact(r, b);  // [1/2, 1]
    ASSERT_EQ(e.verdict, Verdict::hit);
    EXPECT_EQ(e.t_enter.str(), "1/2");
    const auto br = e.enter_bracket();
    EXPECT_TRUE(br.representable());
    EXPECT_EQ(br.lo, 0.5);
    EXPECT_EQ(e.enter_vs(0.5), Order::equal);
    EXPECT_EQ(e.enter_vs(step_up(0.5)), Order::above);
    EXPECT_EQ(e.enter_vs(std::numeric_limits<double>::quiet_NaN()), Order::unordered);
}

TEST(ExactValue, ZeroComparesEqualToBothSignedZeros) {
    const Ray<float> r{{0, 0.5f, 0.5f}, {1, 0, 0}};
    const Aabb<float> b{{0, 0, 0}, {1, 1, 1}};
    const auto e = oracle::exact(r, b);  // origin on the face x = 0: [0, 1], face -1
    ASSERT_EQ(e.verdict, Verdict::hit);
    EXPECT_EQ(e.face, -1);
    EXPECT_EQ(e.enter_vs(0.0f), Order::equal);
    EXPECT_EQ(e.enter_vs(-0.0f), Order::equal);
    EXPECT_EQ(oracle::ulps_from(-0.0f, e.t_enter), 0u);
}

TEST(ExactValue, BracketAboveTheLargestFiniteValueReachesInfinity) {
    using L = std::numeric_limits<double>;
    // t = (max - (-max)) / denorm_min = 2·max·2^1074, far beyond max.
    const Ray<double> r{{-L::max(), 0, 0}, {L::denorm_min(), 0, 0}};
    const Aabb<double> b{{L::max(), -1, -1}, {L::max(), 1, 1}};
    const auto e = oracle::exact(r, b);
    ASSERT_EQ(e.verdict, Verdict::hit);
    const auto br = e.enter_bracket();
    EXPECT_EQ(br.lo, L::max());
    EXPECT_EQ(br.hi, L::infinity());
    EXPECT_EQ(oracle::ulps_from(L::infinity(), e.t_enter), 0u);
    EXPECT_EQ(oracle::ulps_from(L::max(), e.t_enter), 0u);
    EXPECT_EQ(oracle::ulps_from(step_down(L::max()), e.t_enter), 1u);
}

TEST(ExactValue, BracketBelowTheSmallestDenormalReachesZero) {
    using L = std::numeric_limits<float>;
    // t = denorm_min / max: positive, far below denorm_min.
    const Ray<float> r{{0, 0, 0}, {L::max(), 0, 0}};
    const Aabb<float> b{{L::denorm_min(), -1, -1}, {L::denorm_min(), 1, 1}};
    const auto e = oracle::exact(r, b);
    ASSERT_EQ(e.verdict, Verdict::hit);
    const auto br = e.enter_bracket();
    EXPECT_EQ(br.lo, 0.0f);
    EXPECT_EQ(br.hi, L::denorm_min());
    EXPECT_EQ(e.enter_vs(0.0f), Order::below);
    // The same below zero: the ray reversed.
    const auto en = oracle::exact(reversed(Ray<float>{r.origin, r.direction, -L::infinity(), L::infinity()}), b);
    ASSERT_EQ(en.verdict, Verdict::hit);
    const auto bn = en.enter_bracket();
    EXPECT_EQ(bn.lo, -L::denorm_min());
    EXPECT_EQ(bn.hi, 0.0f);
}

// sqrt(3)/2 checks by integer arithmetic: for x in [1, 2), x = m·2^-52 and 2 - x = k·2^-52,
// so x < 2 - sqrt(3/4) iff k² > 3·2^102 (k < 2^52, k² fits 128 bits).
__extension__ typedef unsigned __int128 u128;
bool below_root_double(double x) {
    const std::uint64_t k = std::uint64_t(std::ldexp(2.0 - x, 52));  // 2 - x is exact (Sterbenz)
    return u128(k) * k > (u128(3) << 102);
}
bool below_root_float(float x) {
    const std::uint64_t k = std::uint64_t(std::ldexp(2.0f - x, 23));
    return k * k > (std::uint64_t(3) << 44);
}

TEST(ExactValue, IrrationalSphereRootHasTheIntegerCheckedBracket) {
    // Unit ball at 0, ray (-2, 1/2, 0) + t·(1, 0, 0): roots 2 ∓ sqrt(3/4).
    const Sphere<double> s{{0, 0, 0}, 1};
    const auto e = oracle::exact(Ray<double>{{-2, 0.5, 0}, {1, 0, 0}}, s);
    ASSERT_EQ(e.verdict, Verdict::hit);
    EXPECT_EQ(e.t_enter.kind(), ExactValue::Kind::quadratic_root);
    EXPECT_EQ(e.t_enter.str(), "2 - sqrt(3/4)");
    EXPECT_EQ(e.t_exit.str(), "2 + sqrt(3/4)");
    const auto br = e.enter_bracket();
    EXPECT_EQ(br.hi, step_up(br.lo));
    EXPECT_TRUE(below_root_double(br.lo));
    EXPECT_FALSE(below_root_double(br.hi));
    EXPECT_NEAR(br.lo, 2 - std::sqrt(0.75), 1e-15);

    const auto ef = oracle::exact(Ray<float>{{-2, 0.5f, 0}, {1, 0, 0}}, Sphere<float>{{0, 0, 0}, 1});
    const auto bf = ef.enter_bracket();
    EXPECT_EQ(bf.hi, step_up(bf.lo));
    EXPECT_TRUE(below_root_float(bf.lo));
    EXPECT_FALSE(below_root_float(bf.hi));
    EXPECT_EQ(oracle::ulps_from(bf.lo, ef.t_enter), 0u);
    EXPECT_EQ(oracle::ulps_from(bf.hi, ef.t_enter), 0u);
    EXPECT_EQ(oracle::ulps_from(step_up(bf.hi), ef.t_enter), 1u);
    EXPECT_EQ(oracle::ulps_from(step_down(step_down(bf.lo)), ef.t_enter), 2u);
}

TEST(UlpDistance, CountsRepresentableSteps) {
    using L = std::numeric_limits<double>;
    EXPECT_EQ(oracle::ulp_distance(1.0, step_up(1.0)), 1u);
    EXPECT_EQ(oracle::ulp_distance(step_up(1.0), 1.0), 1u);
    EXPECT_EQ(oracle::ulp_distance(-0.0, 0.0), 0u);
    EXPECT_EQ(oracle::ulp_distance(-L::denorm_min(), L::denorm_min()), 2u);
    EXPECT_EQ(oracle::ulp_distance(L::max(), L::infinity()), 1u);
    EXPECT_EQ(oracle::ulp_distance(1.0f, 2.0f), std::uint64_t(1) << 23);
    EXPECT_EQ(oracle::ulp_distance(L::quiet_NaN(), 1.0), std::numeric_limits<std::uint64_t>::max());
    EXPECT_EQ(oracle::ulp_distance(-L::infinity(), L::infinity()), 2 * std::uint64_t(0x7ff0000000000000));
}

Hit<float> hit(float a, float b, int face) { return {Verdict::hit, a, b, face}; }

TEST(Judge, ClassifiesEveryOutcome) {
    const auto e = third<float>();  // [1/3, 2/3], face 0
    const auto be = e.enter_bracket(), bx = e.exit_bracket();

    auto j = oracle::judge(hit(be.lo, bx.hi, 0), e);
    EXPECT_EQ(j.outcome, Outcome::agree);
    EXPECT_TRUE(j.exact_match());
    EXPECT_TRUE(j.encloses);

    j = oracle::judge(hit(be.hi, bx.lo, 0), e);  // faithful but inside: does not enclose
    EXPECT_TRUE(j.exact_match());
    EXPECT_FALSE(j.encloses);

    j = oracle::judge(hit(step_down(be.lo), step_up(bx.hi), 0), e);
    EXPECT_EQ(j.outcome, Outcome::agree);
    EXPECT_EQ(j.enter_ulps, 1u);
    EXPECT_EQ(j.exit_ulps, 1u);
    EXPECT_FALSE(j.exact_match());
    EXPECT_TRUE(j.encloses);

    j = oracle::judge(hit(be.lo, bx.hi, 3), e);
    EXPECT_EQ(j.outcome, Outcome::face_mismatch);
    EXPECT_EQ(oracle::judge(hit(be.lo, bx.hi, 3), e, /*compare_face=*/false).outcome, Outcome::agree);

    Hit<float> miss;
    EXPECT_EQ(oracle::judge(miss, e).outcome, Outcome::false_miss);
    Hit<float> inv;
    inv.verdict = Verdict::invalid;
    EXPECT_EQ(oracle::judge(inv, e).outcome, Outcome::invalid_mismatch);

    const auto m = oracle::exact(Ray<float>{{-1, 2, 0.5f}, {1, 0, 0}}, Aabb<float>{{0, 0, 0}, {1, 1, 1}});
    ASSERT_EQ(m.verdict, Verdict::miss);
    EXPECT_EQ(oracle::judge(hit(1, 2, 0), m).outcome, Outcome::false_hit);
    EXPECT_EQ(oracle::judge(miss, m).outcome, Outcome::agree);
    EXPECT_EQ(oracle::judge(inv, m).outcome, Outcome::invalid_mismatch);

    const auto bad = oracle::exact(Ray<float>{{0, 0, 0}, {0, 0, 0}}, Aabb<float>{{0, 0, 0}, {1, 1, 1}});
    ASSERT_EQ(bad.verdict, Verdict::invalid);
    EXPECT_EQ(oracle::judge(inv, bad).outcome, Outcome::agree);
    EXPECT_EQ(oracle::judge(miss, bad).outcome, Outcome::invalid_mismatch);

    j = oracle::judge(hit(std::numeric_limits<float>::quiet_NaN(), bx.hi, 0), e);
    EXPECT_EQ(j.enter_ulps, std::numeric_limits<std::uint64_t>::max());
    EXPECT_FALSE(j.encloses);
}

TEST(Judge, AgreesWithTheKernelOnEasyExactCases) {
    // Integer inputs whose answers are small integers: any sane floating-point evaluation
    // is exact, so the fast mode must be judged an exact match (a wrong judge fails here).
    const Aabb<double> b{{0, 0, 0}, {4, 4, 4}};
    for (int x = -3; x <= 7; ++x)
        for (int dx = -2; dx <= 2; dx += 4) {
            const Ray<double> r{{double(x), 1, 2}, {double(dx), 0, 0}};
            const auto j = oracle::judge(intersect(r, b, fast), oracle::exact(r, b));
            EXPECT_TRUE(j.exact_match()) << r << ' ' << j;
        }
}

}  // namespace
