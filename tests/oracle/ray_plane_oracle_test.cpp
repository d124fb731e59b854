// ray_plane_oracle_test.cpp — the oracle's ray/plane answers: rational crossings, a
// crossing behind the origin, rays lying in the plane (the whole range, infinite ends
// included), parallel rays off the plane, crossings exactly at t_min / t_max, non-unit
// normals, every invalid class; and, over every generator, agreement with CGAL's
// Segment/Ray/Line vs Plane_3 predicates and intersection points.
#include "oracle_test_support.hpp"

namespace {

using namespace rayproof;
using namespace rayproof::oracle_test;

template <class T> class PlaneOracle : public ::testing::Test {};
TYPED_TEST_SUITE(PlaneOracle, Scalars, ScalarNames);

TYPED_TEST(PlaneOracle, Crossings) {
    using T = TypeParam;
    const Plane<T> z1{{0, 0, 1}, 1};
    expect_answer(oracle::exact(Ray<T>{{0, 0, 0}, {0, 0, 3}}, z1), "1/3", "1/3", -1);
    EXPECT_EQ(oracle::exact(Ray<T>{{0, 0, 0}, {0, 0, -1}}, z1).verdict, Verdict::miss);
    expect_answer(oracle::exact(Ray<T>{{0, 0, 0}, {0, 0, -1}, -inf<T>()}, z1), "-1", "-1", -1);
    // Non-unit normals: 2x - 4y = -6 and 3x = 1.
    expect_answer(oracle::exact(Ray<T>{{1, 0, 0}, {0, 1, 0}}, Plane<T>{{2, -4, 0}, -6}), "2", "2", -1);
    expect_answer(oracle::exact(Ray<T>{{0, 0, 0}, {1, 1, 1}}, Plane<T>{{3, 0, 0}, 1}), "1/3", "1/3", -1);
}

TYPED_TEST(PlaneOracle, LyingInThePlaneHitsOnTheWholeRange) {
    using T = TypeParam;
    const Plane<T> z1{{0, 0, 1}, 1};
    expect_answer(oracle::exact(Ray<T>{{0, 0, 1}, {1, 2, 0}}, z1), "0", "+inf", -1);
    expect_answer(oracle::exact(Ray<T>{{0, 0, 1}, {1, 2, -T(0)}, -inf<T>(), inf<T>()}, z1), "-inf", "+inf", -1);
    expect_answer(oracle::exact(Ray<T>{{0, 0, 1}, {1, 2, 0}, 2, 5}, z1), "2", "5", -1);
    EXPECT_EQ(oracle::exact(Ray<T>{{0, 0, std::nextafter(T(1), T(2))}, {1, 2, 0}}, z1).verdict, Verdict::miss);
}

TYPED_TEST(PlaneOracle, CrossingsAtTheRangeEnds) {
    using T = TypeParam;
    const Plane<T> z2{{0, 0, 1}, 2};
    expect_answer(oracle::exact(Ray<T>{{0, 0, 0}, {0, 0, 1}, 0, 2}, z2), "2", "2", -1);
    EXPECT_EQ(oracle::exact(Ray<T>{{0, 0, 0}, {0, 0, 1}, 0, std::nextafter(T(2), T(0))}, z2).verdict, Verdict::miss);
    expect_answer(oracle::exact(Ray<T>{{0, 0, 0}, {0, 0, 1}, 2, 2}, z2), "2", "2", -1);
    expect_answer(oracle::exact(Ray<T>{{0, 0, 2}, {0, 0, 1}}, z2), "0", "0", -1);  // origin on the plane
    EXPECT_EQ(oracle::exact(Ray<T>{{0, 0, 2}, {0, 0, 1}, std::numeric_limits<T>::denorm_min()}, z2).verdict,
              Verdict::miss);
}

TYPED_TEST(PlaneOracle, EveryInvalidClass) {
    using T = TypeParam;
    const Plane<T> p{{0, 0, 1}, 1};
    expect_invalid_ray_classes(Ray<T>{{0, 0, 0}, {0, 0, 1}}, p);
    const Ray<T> r{{0, 0, 0}, {0, 0, 1}};
    EXPECT_EQ(oracle::exact(r, Plane<T>{{0, -T(0), 0}, 1}).verdict, Verdict::invalid);
    EXPECT_EQ(oracle::exact(r, Plane<T>{{0, 0, 1}, nan<T>()}).verdict, Verdict::invalid);
    EXPECT_EQ(oracle::exact(r, Plane<T>{{0, 0, 1}, -inf<T>()}).verdict, Verdict::invalid);
    EXPECT_EQ(oracle::exact(r, Plane<T>{{inf<T>(), 0, 1}, 0}).verdict, Verdict::invalid);
    EXPECT_NE(oracle::exact(r, Plane<T>{{std::numeric_limits<T>::denorm_min(), 0, 0}, 0}).verdict, Verdict::invalid);
}

TYPED_TEST(PlaneOracle, AgreesWithCgalOnEveryGenerator) {
    using T = TypeParam;
    crosscheck_all_generators<T, Plane<T>>(kCrosscheckCases);
}

}  // namespace
