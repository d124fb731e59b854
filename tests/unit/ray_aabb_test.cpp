// Ray vs Aabb, hand-computed answers, over float and double and every mode the kernel
// has (see unit_support.hpp for what each mode is held to). Covers: the cube of side s
// centred at the origin for several s (powers of two and not), rays along each axis in
// both directions and with non-unit directions, rays parallel to a face inside, outside
// and exactly on the slab plane with +0 and -0 components, rays from inside, corner and
// edge hits with the lowest-axis tie rule, a single-point touch of an edge, misses,
// t_min/t_max clipping (touching at exactly t_max, starting exactly at the exit), flat
// boxes and t_min = -inf.
#include "unit_support.hpp"

#include <cmath>
#include <limits>

using namespace rayproof;
using namespace rayproof::testing;

template <class T> class RayAabb : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(RayAabb, Scalars);

namespace {
template <class T> Aabb<T> cube(T s) { return {Vec3<T>::Constant(-s / 2), Vec3<T>::Constant(s / 2)}; }
template <class T> Vec3<T> axis(int a, T len = 1) {
    Vec3<T> e = Vec3<T>::Zero();
    e[a] = len;
    return e;
}
const double sides[] = {2, 1, 3, 0.5, 0x1p-20, 0x1p20};
}  // namespace

TYPED_TEST(RayAabb, AlongEachAxisBothDirections) {
    using T = TypeParam;
    for (double sd : sides) {
        const T s = T(sd), h = s / 2;
        for (int a = 0; a < 3; ++a)
            for (int sign : {+1, -1})
                for (T len : {T(1), T(2), T(0.25)}) {
                    // origin 4h before the centre, moving towards it: planes at 3h and 5h (in units of |d|).
                    const Ray<T> r{axis<T>(a, T(-sign) * 4 * h), axis<T>(a, T(sign) * len)};
                    check(r, cube(s), hit<T>(3 * h / len, 5 * h / len, 2 * a + (sign < 0 ? 1 : 0)));
                    // pointing away from the box
                    const Ray<T> away{axis<T>(a, T(-sign) * 4 * h), axis<T>(a, T(-sign) * len)};
                    check(away, cube(s), miss<T>());
                }
    }
}

TYPED_TEST(RayAabb, ParallelToAFaceInsideOnAndOutsideWithSignedZeros) {
    using T = TypeParam;
    const T zero = T(0), nzero = -T(0);
    for (double sd : sides) {
        const T s = T(sd), h = s / 2;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                if (a == b) continue;
                for (T dz : {zero, nzero}) {
                    Vec3<T> d = Vec3<T>::Zero();
                    d[a] = 1;
                    d[3 - a - b] = dz;
                    d[b] = dz;
                    for (T ob : {T(0), h, -h, std::nextafter(h, T(1e30)), std::nextafter(-h, T(-1e30)), 3 * h}) {
                        Vec3<T> o = Vec3<T>::Zero();
                        o[a] = -4 * h;
                        o[b] = ob;
                        const bool inside = -h <= ob && ob <= h;  // the closed slab: the plane itself is inside
                        check(Ray<T>{o, d}, cube(s), inside ? hit<T>(3 * h, 5 * h, 2 * a) : miss<T>());
                    }
                }
            }
    }
}

TYPED_TEST(RayAabb, FromInside) {
    using T = TypeParam;
    const T h = 1;
    for (int a = 0; a < 3; ++a) {
        check(Ray<T>{Vec3<T>::Zero(), axis<T>(a)}, cube(T(2)), hit<T>(0, h, -1));
        check(Ray<T>{Vec3<T>::Zero(), axis<T>(a, -1)}, cube(T(2)), hit<T>(0, h, -1));
        // origin on a face, leaving: the point at t_min is in the closed box
        check(Ray<T>{axis<T>(a, h), axis<T>(a)}, cube(T(2)), hit<T>(0, 0, -1));
        // the whole line: t_min = -inf makes the entry face the lo side
        const T inf = std::numeric_limits<T>::infinity();
        check(Ray<T>{axis<T>(a, 10), axis<T>(a), -inf, inf}, cube(T(2)), hit<T>(-11, -9, 2 * a));
    }
}

TYPED_TEST(RayAabb, CornersAndEdgesTieToTheLowestAxis) {
    using T = TypeParam;
    const Aabb<T> box = cube(T(2));  // h = 1
    check(Ray<T>{v<T>(-3, -3, -3), v<T>(1, 1, 1)}, box, hit<T>(2, 4, 0));
    check(Ray<T>{v<T>(3, 3, 3), v<T>(-1, -1, -1)}, box, hit<T>(2, 4, 1));
    check(Ray<T>{v<T>(0, 3, 3), v<T>(0, -1, -1)}, box, hit<T>(2, 4, 3));   // edge x-parallel: axes 1,2 tie
    check(Ray<T>{v<T>(-3, -3, 0), v<T>(1, 1, 0)}, box, hit<T>(2, 4, 0));   // edge z-parallel
    check(Ray<T>{v<T>(-3, 1, 1), v<T>(1, 0, 0)}, box, hit<T>(2, 4, 0));    // along an edge
    check(Ray<T>{v<T>(-3, -1, 1), v<T>(1, -0.0, 0)}, box, hit<T>(2, 4, 0));
    // touching the edge x = y = 1 in a single point: in through y = hi, out through x = hi at once
    check(Ray<T>{v<T>(0, 2, 0), v<T>(1, -1, 0)}, box, hit<T>(1, 1, 3));
    // just beside that edge: a miss
    check(Ray<T>{v<T>(0, std::nextafter(T(2), T(3)), 0), v<T>(1, -1, 0)}, box, miss<T>());
    // a single corner point
    check(Ray<T>{v<T>(0, 2, 2), v<T>(1, -1, -1)}, box, hit<T>(1, 1, 3));
}

TYPED_TEST(RayAabb, ClippingByTminTmax) {
    using T = TypeParam;
    const Aabb<T> box = cube(T(2));
    const Vec3<T> o = v<T>(-4, 0, 0), d = v<T>(1, 0, 0);  // box on t in [3, 5]
    check(Ray<T>{o, d, 0, 3}, box, hit<T>(3, 3, 0));                               // touches at t_max
    check(Ray<T>{o, d, 0, std::nextafter(T(3), T(0))}, box, miss<T>());            // stops just short
    check(Ray<T>{o, d, 2, 4}, box, hit<T>(3, 4, 0));
    check(Ray<T>{o, d, 4, 10}, box, hit<T>(4, 5, -1));                              // starts inside
    check(Ray<T>{o, d, 3, 10}, box, hit<T>(3, 5, -1));                              // starts on the face
    check(Ray<T>{o, d, 5, 10}, box, hit<T>(5, 5, -1));                              // starts on the exit
    check(Ray<T>{o, d, std::nextafter(T(5), T(6)), 10}, box, miss<T>());           // starts just past it
    check(Ray<T>{o, d, 4, 4}, box, hit<T>(4, 4, -1));                               // a single point inside
}

TYPED_TEST(RayAabb, FlatBoxesAndMisses) {
    using T = TypeParam;
    const Aabb<T> flat{v<T>(-1, -1, 0), v<T>(1, 1, 0)};
    check(Ray<T>{v<T>(0, 0, -3), v<T>(0, 0, 1)}, flat, hit<T>(3, 3, 4));
    check(Ray<T>{v<T>(0, 0, 3), v<T>(0, 0, -1)}, flat, hit<T>(3, 3, 5));
    check(Ray<T>{v<T>(-3, 0, 0), v<T>(1, 0, 0)}, flat, hit<T>(2, 4, 0));          // inside the flat slab
    check(Ray<T>{v<T>(-3, 0, T(0x1p-20)), v<T>(1, 0, 0)}, flat, miss<T>());
    const Aabb<T> point{v<T>(1, 2, 3), v<T>(1, 2, 3)};
    check(Ray<T>{v<T>(0, 0, 0), v<T>(1, 2, 3)}, point, hit<T>(1, 1, 0));
    check(Ray<T>{v<T>(0, 0, 0), v<T>(1, 2, 4)}, point, miss<T>());
    check(Ray<T>{v<T>(-3, 2, 0), v<T>(1, 0, 0)}, cube(T(2)), miss<T>());
}
