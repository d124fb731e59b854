// ray_aabb_oracle_test.cpp — the oracle's ray/Aabb answers: hand-computed rational
// intervals and faces (entry sides, the lowest-axis tie rule at edges and corners, face -1
// when t_min is in the box, t_min exactly at the entry), parallel rays with ±0 on and off
// the slab planes, flat boxes, every invalid class; then, over every generator, agreement
// with CGAL's own Segment/Ray/Line vs Iso_cuboid_3 predicates and constructions.
#include "oracle_test_support.hpp"

namespace {

using namespace rayproof;
using namespace rayproof::oracle_test;

template <class T> class AabbOracle : public ::testing::Test {};
TYPED_TEST_SUITE(AabbOracle, Scalars, ScalarNames);

TYPED_TEST(AabbOracle, ThroughTheMiddle) {
    using T = TypeParam;
    const Aabb<T> b{{0, 0, 0}, {1, 1, 1}};
    expect_answer(oracle::exact(Ray<T>{{-1, T(0.5), T(0.5)}, {1, 0, 0}}, b), "1", "2", 0);
    expect_answer(oracle::exact(Ray<T>{{2, T(0.5), T(0.5)}, {-1, 0, 0}}, b), "1", "2", 1);
    expect_answer(oracle::exact(Ray<T>{{T(0.5), -2, T(0.5)}, {0, 3, 0}}, b), "2/3", "1", 2);
    expect_answer(oracle::exact(Ray<T>{{T(0.5), T(0.5), 5}, {0, 0, -4}}, b), "1", "5/4", 5);
}

TYPED_TEST(AabbOracle, OriginInsideAndTMinAtTheEntryGiveFaceMinusOne) {
    using T = TypeParam;
    const Aabb<T> b{{0, 0, 0}, {1, 1, 1}};
    expect_answer(oracle::exact(Ray<T>{{T(0.5), T(0.5), T(0.5)}, {1, 0, 0}}, b), "0", "1/2", -1);
    expect_answer(oracle::exact(Ray<T>{{-1, T(0.5), T(0.5)}, {1, 0, 0}, 1}, b), "1", "2", -1);  // t_min at the entry
    expect_answer(oracle::exact(Ray<T>{{-1, T(0.5), T(0.5)}, {1, 0, 0}, T(1.5)}, b), "3/2", "2", -1);
    // The whole line: the entry is behind the origin.
    expect_answer(oracle::exact(Ray<T>{{T(0.5), T(0.5), T(0.5)}, {1, 0, 0}, -inf<T>(), inf<T>()}, b), "-1/2", "1/2", 0);
}

TYPED_TEST(AabbOracle, TiesGoToTheLowestAxis) {
    using T = TypeParam;
    const Aabb<T> b{{0, 0, 0}, {1, 1, 1}};
    expect_answer(oracle::exact(Ray<T>{{-1, -1, -1}, {1, 1, 1}}, b), "1", "2", 0);   // corner (0,0,0)
    expect_answer(oracle::exact(Ray<T>{{2, 2, 2}, {-1, -1, -1}}, b), "1", "2", 1);   // corner (1,1,1)
    expect_answer(oracle::exact(Ray<T>{{T(0.5), -1, 2}, {0, 1, -1}}, b), "1", "2", 2);  // edge y = 0, z = 1
    expect_answer(oracle::exact(Ray<T>{{T(0.5), 2, -1}, {0, -1, 1}}, b), "1", "2", 3);  // edge y = 1, z = 0
    // A tie with t_min keeps face -1.
    expect_answer(oracle::exact(Ray<T>{{-1, -1, T(0.5)}, {1, 1, 0}, 1}, b), "1", "2", -1);
}

TYPED_TEST(AabbOracle, GrazingACornerIsASinglePoint) {
    using T = TypeParam;
    const Aabb<T> b{{0, 0, 0}, {1, 1, 1}};
    // The line x + y = 2 touches the square only at (1, 1): entries x 0, y 1; exits x 1, y 2.
    expect_answer(oracle::exact(Ray<T>{{0, 2, T(0.5)}, {1, -1, 0}}, b), "1", "1", 3);
    // One ulp of direction off the corner: a miss.
    const T dy = std::nextafter(T(-1), T(0));
    EXPECT_EQ(oracle::exact(Ray<T>{{0, 2, T(0.5)}, {1, dy, 0}}, b).verdict, Verdict::miss);
}

TYPED_TEST(AabbOracle, ParallelRaysWithSignedZeros) {
    using T = TypeParam;
    const Aabb<T> b{{0, 0, 0}, {1, 1, 1}};
    for (const T z : {T(0), -T(0)}) {
        EXPECT_EQ(oracle::exact(Ray<T>{{-1, 2, T(0.5)}, {1, z, 0}}, b).verdict, Verdict::miss);
        expect_answer(oracle::exact(Ray<T>{{-1, 1, T(0.5)}, {1, z, z}}, b), "1", "2", 0);  // on the plane y = 1
        expect_answer(oracle::exact(Ray<T>{{-1, 0, 0}, {1, z, z}}, b), "1", "2", 0);        // along an edge
        expect_answer(oracle::exact(Ray<T>{{T(0.5), 0, 1}, {z, z, -2}}, b), "0", "1/2", -1);
    }
}

TYPED_TEST(AabbOracle, FlatBoxesAndRangeEnds) {
    using T = TypeParam;
    const Aabb<T> flat{{0, 0, 1}, {1, 1, 1}};
    expect_answer(oracle::exact(Ray<T>{{T(0.5), T(0.5), 0}, {0, 0, 2}}, flat), "1/2", "1/2", 4);
    const Aabb<T> b{{0, 0, 0}, {1, 1, 1}};
    expect_answer(oracle::exact(Ray<T>{{-1, T(0.5), T(0.5)}, {1, 0, 0}, 0, 1}, b), "1", "1", 0);  // t_max at the entry
    EXPECT_EQ(oracle::exact(Ray<T>{{-1, T(0.5), T(0.5)}, {1, 0, 0}, 0, std::nextafter(T(1), T(0))}, b).verdict,
              Verdict::miss);
    EXPECT_EQ(oracle::exact(Ray<T>{{-1, T(0.5), T(0.5)}, {1, 0, 0}, std::nextafter(T(2), T(3))}, b).verdict,
              Verdict::miss);
}

TYPED_TEST(AabbOracle, DenormalScale) {
    using T = TypeParam;
    const T m = std::numeric_limits<T>::denorm_min();
    const Aabb<T> b{{2 * m, 0, 0}, {4 * m, m, m}};
    // From the origin along (3m, 0, 0)·: x = 3m·t reaches 2m at t = 2/3 and 4m at 4/3.
    expect_answer(oracle::exact(Ray<T>{{0, 0, 0}, {3 * m, 0, 0}}, b), "2/3", "4/3", 0);
}

TYPED_TEST(AabbOracle, EveryInvalidClass) {
    using T = TypeParam;
    const Aabb<T> b{{0, 0, 0}, {1, 1, 1}};
    const Ray<T> r{{-1, T(0.5), T(0.5)}, {1, 0, 0}};
    expect_invalid_ray_classes(r, b);
    Aabb<T> bad = b;
    bad.lo[1] = std::nextafter(T(1), T(2));
    EXPECT_EQ(oracle::exact(r, bad).verdict, Verdict::invalid);
    bad = b;
    bad.hi[2] = nan<T>();
    EXPECT_EQ(oracle::exact(r, bad).verdict, Verdict::invalid);
    bad = b;
    bad.lo[0] = -inf<T>();
    EXPECT_EQ(oracle::exact(r, bad).verdict, Verdict::invalid);
    // Valid edge values: -0 bounds, t_min = -inf, t_max = +inf, t_min == t_max.
    EXPECT_NE(oracle::exact(Ray<T>{r.origin, r.direction, -inf<T>(), inf<T>()}, Aabb<T>{{-T(0), 0, 0}, {0, 1, 1}}).verdict,
              Verdict::invalid);
    EXPECT_NE(oracle::exact(Ray<T>{r.origin, r.direction, 3, 3}, b).verdict, Verdict::invalid);
}

TYPED_TEST(AabbOracle, AgreesWithCgalOnEveryGenerator) {
    using T = TypeParam;
    crosscheck_all_generators<T, Aabb<T>>(kCrosscheckCases);
}

}  // namespace
