// ray_sphere_oracle_test.cpp — the oracle's ray/sphere answers: rational roots from a
// 3-4-5 triangle, an exact tangent and a one-ulp miss beside it, irrational roots kept
// symbolic, origins inside and on the sphere, a sphere behind the origin, t_min between
// the roots, point spheres (radius +0 and -0), every invalid class; and, over every
// generator, agreement with CGAL's exact ball predicates.
#include "oracle_test_support.hpp"

namespace {

using namespace rayproof;
using namespace rayproof::oracle_test;

template <class T> class SphereOracle : public ::testing::Test {};
TYPED_TEST_SUITE(SphereOracle, Scalars, ScalarNames);

TYPED_TEST(SphereOracle, RationalRootsAndTangents) {
    using T = TypeParam;
    const Sphere<T> s{{0, 0, 0}, 5};
    expect_answer(oracle::exact(Ray<T>{{-10, 3, 0}, {1, 0, 0}}, s), "6", "14", -1);   // x² + 9 <= 25
    expect_answer(oracle::exact(Ray<T>{{-10, 3, 0}, {2, 0, 0}}, s), "3", "7", -1);    // non-unit direction
    expect_answer(oracle::exact(Ray<T>{{-10, 5, 0}, {1, 0, 0}}, s), "10", "10", -1);  // tangent
    EXPECT_EQ(oracle::exact(Ray<T>{{-10, std::nextafter(T(5), T(6)), 0}, {1, 0, 0}}, s).verdict, Verdict::miss);
    expect_answer(oracle::exact(Ray<T>{{-10, 3, 0}, {1, 0, 0}, 8}, s), "8", "14", -1);  // t_min between the roots
    expect_answer(oracle::exact(Ray<T>{{-10, 3, 0}, {1, 0, 0}, 0, 9}, s), "6", "9", -1);
}

TYPED_TEST(SphereOracle, IrrationalRootsStaySymbolic) {
    using T = TypeParam;
    const auto e = oracle::exact(Ray<T>{{-1, -1, 0}, {1, 1, 0}}, Sphere<T>{{0, 0, 0}, 1});
    expect_answer(e, "1 - sqrt(1/2)", "1 + sqrt(1/2)", -1);
    EXPECT_EQ(e.t_enter.kind(), oracle::ExactValue::Kind::quadratic_root);
    // Integer check of the bracket: t0 = 1 - sqrt(1/2) lies in [1/4, 1/2), where a float
    // of T is x = m·2^-(p+1) (p the precision); with k = 2^(p+1) - m, x < t0 iff
    // (1 - x)² > 1/2 iff k² > 2^(2p+1). k < 2^(p+1), so k² fits 128 bits.
    __extension__ typedef unsigned __int128 u128;
    constexpr int p = std::numeric_limits<T>::digits;
    const auto below_t0 = [](T x) {
        const u128 m = u128(std::ldexp(x, p + 1));
        const u128 k = (u128(1) << (p + 1)) - m;
        return k * k > (u128(1) << (2 * p + 1));
    };
    const auto br = e.enter_bracket();
    ASSERT_GE(br.lo, T(0.25));
    ASSERT_LT(br.hi, T(0.5));
    EXPECT_EQ(br.hi, std::nextafter(br.lo, T(1)));
    EXPECT_TRUE(below_t0(br.lo));
    EXPECT_FALSE(below_t0(br.hi));
}

TYPED_TEST(SphereOracle, OriginInsideOnOrBehind) {
    using T = TypeParam;
    const Sphere<T> s{{0, 0, 0}, 5};
    expect_answer(oracle::exact(Ray<T>{{0, 0, 0}, {1, 0, 0}}, s), "0", "5", -1);
    expect_answer(oracle::exact(Ray<T>{{5, 0, 0}, {1, 0, 0}}, s), "0", "0", -1);  // on the sphere, leaving
    expect_answer(oracle::exact(Ray<T>{{5, 0, 0}, {-1, 0, 0}}, s), "0", "10", -1);
    EXPECT_EQ(oracle::exact(Ray<T>{{10, 0, 0}, {1, 0, 0}}, s).verdict, Verdict::miss);
    expect_answer(oracle::exact(Ray<T>{{10, 0, 0}, {1, 0, 0}, -inf<T>()}, s), "-15", "-5", -1);
}

TYPED_TEST(SphereOracle, PointSpheres) {
    using T = TypeParam;
    for (const T r0 : {T(0), -T(0)}) {
        const Sphere<T> p{{1, 2, 3}, r0};
        expect_answer(oracle::exact(Ray<T>{{0, 0, 0}, {1, 2, 3}}, p), "1", "1", -1);
        EXPECT_EQ(oracle::exact(Ray<T>{{0, 0, 0}, {1, 2, std::nextafter(T(3), T(4))}}, p).verdict, Verdict::miss);
    }
}

TYPED_TEST(SphereOracle, EveryInvalidClass) {
    using T = TypeParam;
    const Sphere<T> s{{0, 0, 0}, 1};
    const Ray<T> r{{-3, 0, 0}, {1, 0, 0}};
    expect_invalid_ray_classes(r, s);
    EXPECT_EQ(oracle::exact(r, Sphere<T>{{0, 0, 0}, -std::numeric_limits<T>::denorm_min()}).verdict, Verdict::invalid);
    EXPECT_EQ(oracle::exact(r, Sphere<T>{{0, 0, 0}, inf<T>()}).verdict, Verdict::invalid);
    EXPECT_EQ(oracle::exact(r, Sphere<T>{{0, nan<T>(), 0}, 1}).verdict, Verdict::invalid);
}

TYPED_TEST(SphereOracle, AgreesWithCgalOnEveryGenerator) {
    using T = TypeParam;
    crosscheck_all_generators<T, Sphere<T>>(kCrosscheckCases);
}

}  // namespace
