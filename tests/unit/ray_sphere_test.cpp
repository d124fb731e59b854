// Ray vs Sphere (closed ball), hand-computed answers, over float and double and every
// mode the kernel has. Covers: through the centre, exact tangents (axis-aligned and a
// 3-4-5 triangle), one ulp off a tangent, origin inside, origin on the sphere leaving
// and entering, the sphere behind the origin (t_min = -inf too), a point sphere
// (radius 0), non-unit directions, t_min/t_max clipping, and a far small sphere.
#include "unit_support.hpp"

#include <limits>

using namespace rayproof;
using namespace rayproof::testing;

template <class T> class RaySphere : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(RaySphere, Scalars);

TYPED_TEST(RaySphere, ThroughTangentAndBeside) {
    using T = TypeParam;
    const Sphere<T> ball{v<T>(0, 0, 0), 5};
    check(Ray<T>{v<T>(-10, 0, 0), v<T>(1, 0, 0)}, ball, hit<T>(5, 15));
    check(Ray<T>{v<T>(-10, 0, 0), v<T>(2, 0, 0)}, ball, hit<T>(2.5, 7.5));
    check(Ray<T>{v<T>(-10, 5, 0), v<T>(1, 0, 0)}, ball, hit<T>(10, 10));
    check(Ray<T>{v<T>(-10, std::nextafter(T(5), T(6)), 0), v<T>(1, 0, 0)}, ball, miss<T>());
    check(Ray<T>{v<T>(-7, 1, 0), v<T>(4, 3, 0)}, ball, hit<T>(1, 1));          // tangent at (-3, 4, 0)
    check(Ray<T>{v<T>(-7, 1, 0) + v<T>(1, 2, 3), v<T>(4, 3, 0)}, Sphere<T>{v<T>(1, 2, 3), 5}, hit<T>(1, 1));
    check(Ray<T>{v<T>(-10, 6, 0), v<T>(1, 0, 0)}, ball, miss<T>());
}

TYPED_TEST(RaySphere, OriginInsideOnAndBehind) {
    using T = TypeParam;
    const T inf = std::numeric_limits<T>::infinity();
    const Sphere<T> ball{v<T>(0, 0, 0), 5};
    check(Ray<T>{v<T>(0, 0, 0), v<T>(1, 0, 0)}, ball, hit<T>(0, 5));
    check(Ray<T>{v<T>(5, 0, 0), v<T>(1, 0, 0)}, ball, hit<T>(0, 0));          // on the sphere, leaving
    check(Ray<T>{v<T>(5, 0, 0), v<T>(-1, 0, 0)}, ball, hit<T>(0, 10));        // on the sphere, entering
    check(Ray<T>{v<T>(10, 0, 0), v<T>(1, 0, 0)}, ball, miss<T>());
    check(Ray<T>{v<T>(10, 0, 0), v<T>(1, 0, 0), -inf, inf}, ball, hit<T>(-15, -5));
}

TYPED_TEST(RaySphere, PointSphereAndClipping) {
    using T = TypeParam;
    const Sphere<T> point{v<T>(1, 2, 3), 0};
    check(Ray<T>{v<T>(0, 0, 0), v<T>(1, 2, 3)}, point, hit<T>(1, 1));
    check(Ray<T>{v<T>(0, 0, 0), v<T>(1, 2, 4)}, point, miss<T>());
    const Sphere<T> ball{v<T>(0, 0, 0), 5};
    const Vec3<T> o = v<T>(-10, 0, 0), d = v<T>(1, 0, 0);
    check(Ray<T>{o, d, 0, 5}, ball, hit<T>(5, 5));
    check(Ray<T>{o, d, 0, std::nextafter(T(5), T(0))}, ball, miss<T>());
    check(Ray<T>{o, d, 6, 7}, ball, hit<T>(6, 7));
    check(Ray<T>{o, d, 15, 20}, ball, hit<T>(15, 15));
    check(Ray<T>{o, d, std::nextafter(T(15), T(16)), 20}, ball, miss<T>());
}

TYPED_TEST(RaySphere, FarSmallSphere) {
    using T = TypeParam;
    const T far = T(0x1p12), r = T(0x1p-8);   // far ± r needs 21 bits: exact in float and double
    const Sphere<T> speck{v<T>(far, 0, 0), r};
    check(Ray<T>{v<T>(0, 0, 0), v<T>(1, 0, 0)}, speck, hit<T>(far - r, far + r));
    check(Ray<T>{v<T>(0, r, 0), v<T>(1, 0, 0)}, speck, hit<T>(far, far));     // tangent
    check(Ray<T>{v<T>(0, 2 * r, 0), v<T>(1, 0, 0)}, speck, miss<T>());
}
