// ray_obb_oracle_test.cpp — the oracle's ray/Obb answers: non-unit, negated, rotated and
// sheared axes with hand-computed intervals and faces (side 0 is (p - c)·a_i == -h_i, ties
// to the lowest column), exact dependence of the axes (invalid) versus a one-ulp escape
// from it (valid), every invalid class; identity-axis boxes agree exactly with the Aabb
// oracle; and, over every generator, the verdict agrees with CGAL on the box cut into six
// exact tetrahedra.
#include "oracle_test_support.hpp"

namespace {

using namespace rayproof;
using namespace rayproof::oracle_test;

template <class T> class ObbOracle : public ::testing::Test {};
TYPED_TEST_SUITE(ObbOracle, Scalars, ScalarNames);

// The matrix with columns a, b, c (Eigen's comma initializer puts vectors side by side).
template <class T> Mat3<T> cols(Vec3<T> a, Vec3<T> b, Vec3<T> c) { return (Mat3<T>() << a, b, c).finished(); }

TYPED_TEST(ObbOracle, NonUnitAndNegatedAxes) {
    using T = TypeParam;
    const Ray<T> r{{-3, 0, 0}, {1, 0, 0}};
    // axes 2·I, half extents 2: the box [-1, 1]³.
    expect_answer(oracle::exact(r, Obb<T>{{0, 0, 0}, Mat3<T>::Identity() * T(2), {2, 2, 2}}), "2", "4", 0);
    // a_0 = -x: the plane (p - c)·a_0 == -h_0 is x == +1, so the ray enters on side 1.
    expect_answer(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>({-1, 0, 0}, {0, 1, 0}, {0, 0, 1}), {1, 1, 1}}), "2", "4", 1);
}

TYPED_TEST(ObbOracle, RotatedSquareTiesToTheLowestColumn) {
    using T = TypeParam;
    // |x + y| <= 2, |y - x| <= 2, |z| <= 1: a square with corners (±2, 0), (0, ±2).
    const Ray<T> r{{-5, 0, 0}, {1, 0, 0}};
    expect_answer(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>({1, 1, 0}, {-1, 1, 0}, {0, 0, 1}), {2, 2, 1}}), "3", "7", 0);
    // The same box with the tying columns moved to 1 and 2: face 2·1 + 0.
    expect_answer(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>({0, 0, 1}, {1, 1, 0}, {-1, 1, 0}), {1, 2, 2}}), "3", "7", 2);
}

TYPED_TEST(ObbOracle, ShearedAxes) {
    using T = TypeParam;
    // |x| <= 1, |x + y| <= 1, |z| <= 1, the ray along +y at x = 0: parallel to slab 0.
    const Obb<T> b{{0, 0, 0}, cols<T>({1, 0, 0}, {1, 1, 0}, {0, 0, 1}), {1, 1, 1}};
    expect_answer(oracle::exact(Ray<T>{{0, -5, 0}, {0, 1, 0}}, b), "4", "6", 2);
    // Off-centre by a translation.
    const Obb<T> moved{{10, 20, 30}, b.axes, b.half_extent};
    expect_answer(oracle::exact(Ray<T>{{10, 15, 30}, {0, 3, 0}}, moved), "4/3", "2", 2);
}

TYPED_TEST(ObbOracle, DependenceIsDecidedExactly) {
    using T = TypeParam;
    const Ray<T> r{{-5, 0, 0}, {1, 0, 0}};
    const Vec3<T> a0(1, 2, 3), a1(-2, 1, 4);
    EXPECT_EQ(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>(a0, a1, a0 + a1), {1, 1, 1}}).verdict, Verdict::invalid);
    EXPECT_EQ(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>(a0, a1, Vec3<T>::Zero()), {1, 1, 1}}).verdict, Verdict::invalid);
    EXPECT_EQ(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>(a0, T(-3) * a0, a1), {1, 1, 1}}).verdict, Verdict::invalid);
    // Scaled into the denormal range, still exactly dependent.
    const T s = std::ldexp(T(1), std::numeric_limits<T>::min_exponent - 8);
    EXPECT_EQ(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>(s * a0, s * a1, s * (a0 + a1)), {1, 1, 1}}).verdict,
              Verdict::invalid);
    // One ulp away from dependence: valid.
    Vec3<T> a2 = a0 + a1;
    a2[1] = std::nextafter(a2[1], T(10));
    EXPECT_NE(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>(a0, a1, a2), {1, 1, 1}}).verdict, Verdict::invalid);
    EXPECT_TRUE(oracle::valid(Obb<T>{{0, 0, 0}, cols<T>(a0, a1, a2), {1, 1, 1}}));
}

TYPED_TEST(ObbOracle, EveryInvalidClass) {
    using T = TypeParam;
    const Obb<T> b{{0, 0, 0}, Mat3<T>::Identity(), {1, 1, 1}};
    const Ray<T> r{{-3, 0, 0}, {1, 0, 0}};
    expect_invalid_ray_classes(r, b);
    Obb<T> bad = b;
    bad.half_extent[2] = -std::numeric_limits<T>::denorm_min();
    EXPECT_EQ(oracle::exact(r, bad).verdict, Verdict::invalid);
    bad = b;
    bad.axes(1, 2) = nan<T>();
    EXPECT_EQ(oracle::exact(r, bad).verdict, Verdict::invalid);
    bad = b;
    bad.center[0] = inf<T>();
    EXPECT_EQ(oracle::exact(r, bad).verdict, Verdict::invalid);
    bad = b;
    bad.half_extent[0] = inf<T>();
    EXPECT_EQ(oracle::exact(r, bad).verdict, Verdict::invalid);
    bad = b;
    bad.half_extent[1] = -T(0);  // -0 is not negative: a flat, valid box
    expect_answer(oracle::exact(r, bad), "2", "4", 0);
}

// Identity axes, centre (lo+hi)/2 and half extents (hi-lo)/2 describe the same box as the
// Aabb when those are exact: the answers must be identical (values, faces).
template <class T> bool exact_center(const Aabb<T>& a, Obb<T>& o) {
    o.axes = Mat3<T>::Identity();
    for (int i = 0; i < 3; ++i) {
        const T s = a.lo[i] + a.hi[i], d = a.hi[i] - a.lo[i];
        // Exact iff the rounding error (TwoSum) is zero and halving loses no bit.
        const T bs = s - a.lo[i], es = (a.lo[i] - (s - bs)) + (a.hi[i] - bs);
        const T bd = d - a.hi[i], ed = (a.hi[i] - (d - bd)) + (-a.lo[i] - bd);
        if (!std::isfinite(s) || !std::isfinite(d) || es != 0 || ed != 0) return false;
        o.center[i] = s / 2;
        o.half_extent[i] = d / 2;
        if (o.center[i] * 2 != s || o.half_extent[i] * 2 != d) return false;
    }
    return true;
}

TYPED_TEST(ObbOracle, IdentityAxesAgreeWithTheAabbOracle) {
    using T = TypeParam;
    int compared = 0;
    for (const auto& g : gen::generators<T, Aabb<T>>()) {
        gen::Rng rng(0x0bb ^ gen::name_hash(g.name));
        for (int i = 0; i < 300; ++i) {
            const auto c = g.make(rng);
            Obb<T> o;
            if (!oracle::valid(c.shape) || !exact_center(c.shape, o)) continue;
            const auto ea = oracle::exact(c.ray, c.shape), eo = oracle::exact(c.ray, o);
            ++compared;
            ASSERT_EQ(ea.verdict, eo.verdict) << c;
            if (ea.verdict != Verdict::hit) continue;
            EXPECT_EQ(ea.face, eo.face) << c;
            EXPECT_TRUE(ea.t_enter == eo.t_enter) << c << '\n' << ea << '\n' << eo;
            EXPECT_TRUE(ea.t_exit == eo.t_exit) << c << '\n' << ea << '\n' << eo;
        }
    }
    EXPECT_GT(compared, 1000);
}

TYPED_TEST(ObbOracle, AgreesWithCgalTetrahedraOnEveryGenerator) {
    using T = TypeParam;
    crosscheck_all_generators<T, Obb<T>>(kCrosscheckCases / 2, false);
}

}  // namespace
