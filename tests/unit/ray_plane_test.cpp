// Ray vs Plane, hand-computed answers, over float and double and every mode the kernel
// has. Covers: a perpendicular crossing, a non-unit normal (same plane), an oblique
// normal, a ray lying in the plane (hit on its whole range, t_min = -inf included), a
// parallel ray off the plane, crossings exactly at t_min and t_max and one ulp outside,
// a crossing behind the origin (miss, then hit with t_min = -inf).
#include "unit_support.hpp"

#include <limits>

using namespace rayproof;
using namespace rayproof::testing;

template <class T> class RayPlane : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(RayPlane, Scalars);

TYPED_TEST(RayPlane, Crossings) {
    using T = TypeParam;
    const Plane<T> floor{v<T>(0, 1, 0), -1};
    check(Ray<T>{v<T>(0, 3, 0), v<T>(0, -1, 0)}, floor, hit<T>(4, 4));
    check(Ray<T>{v<T>(0, 3, 0), v<T>(0, -2, 0)}, floor, hit<T>(2, 2));
    check(Ray<T>{v<T>(0, 3, 0), v<T>(0, -1, 0)}, Plane<T>{v<T>(0, 2, 0), -2}, hit<T>(4, 4));
    check(Ray<T>{v<T>(0, -3, 0), v<T>(5, 1, 7)}, floor, hit<T>(2, 2));   // from below
    check(Ray<T>{v<T>(0, 0, 0), v<T>(1, 0, 0)}, Plane<T>{v<T>(1, 1, 1), 3}, hit<T>(3, 3));
    check(Ray<T>{v<T>(0, 3, 0), v<T>(0, 1, 0)}, floor, miss<T>());        // moving away
    const T inf = std::numeric_limits<T>::infinity();
    check(Ray<T>{v<T>(0, 3, 0), v<T>(0, 1, 0), -inf, inf}, floor, hit<T>(-4, -4));
}

TYPED_TEST(RayPlane, ParallelInAndOffThePlane) {
    using T = TypeParam;
    const T inf = std::numeric_limits<T>::infinity();
    const Plane<T> floor{v<T>(0, 1, 0), -1};
    check(Ray<T>{v<T>(0, -1, 0), v<T>(1, 0, 1)}, floor, hit<T>(0, inf));
    check(Ray<T>{v<T>(0, -1, 0), v<T>(1, -0.0, 1), -2, 7}, floor, hit<T>(-2, 7));
    check(Ray<T>{v<T>(0, -1, 0), v<T>(1, 0, 1), -inf, inf}, floor, hit<T>(-inf, inf));
    check(Ray<T>{v<T>(0, 0, 0), v<T>(1, 0, 0)}, floor, miss<T>());
    check(Ray<T>{v<T>(0, std::nextafter(T(-1), T(0)), 0), v<T>(1, 0, 0)}, floor, miss<T>());
    // oblique plane x + y + z = 3, direction in it: (1,-1,0)
    check(Ray<T>{v<T>(1, 1, 1), v<T>(1, -1, 0), -1, 1}, Plane<T>{v<T>(1, 1, 1), 3}, hit<T>(-1, 1));
}

TYPED_TEST(RayPlane, ClippingByTminTmax) {
    using T = TypeParam;
    const Plane<T> floor{v<T>(0, 1, 0), -1};
    const Vec3<T> o = v<T>(0, 3, 0), d = v<T>(0, -1, 0);  // crossing at t = 4
    check(Ray<T>{o, d, 0, 4}, floor, hit<T>(4, 4));
    check(Ray<T>{o, d, 4, 9}, floor, hit<T>(4, 4));
    check(Ray<T>{o, d, 4, 4}, floor, hit<T>(4, 4));
    check(Ray<T>{o, d, 0, std::nextafter(T(4), T(0))}, floor, miss<T>());
    check(Ray<T>{o, d, std::nextafter(T(4), T(5)), 9}, floor, miss<T>());
}
