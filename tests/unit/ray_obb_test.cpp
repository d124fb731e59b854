// Ray vs Obb, hand-computed answers, over float and double and every mode the kernel
// has. Covers: identity axes (agreeing with the Aabb answers), non-unit axes (the slab
// half-width is half_extent/|a_i|), non-orthogonal axes, integer rotated axes
// (3,4,0),(-4,3,0),(0,0,5) with a ray through the centre, a corner hit with the tie
// rule, a ray parallel to a slab (d·a_i == 0 exactly with non-zero components) with its
// origin exactly on that slab plane and just off it, rays from inside, and misses.
#include "unit_support.hpp"

using namespace rayproof;
using namespace rayproof::testing;

template <class T> class RayObb : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(RayObb, Scalars);

namespace {
// The matrix with columns a, b, c (Eigen's comma initializer puts vectors side by side).
template <class T> Mat3<T> cols(Vec3<T> a, Vec3<T> b, Vec3<T> c) { return (Mat3<T>() << a, b, c).finished(); }
template <class T> Obb<T> rotated(Vec3<T> center) {  // half-widths 5 along the unit axes (3,4,0)/5, (-4,3,0)/5, z
    return {center, cols<T>(v<T>(3, 4, 0), v<T>(-4, 3, 0), v<T>(0, 0, 5)), v<T>(25, 25, 25)};
}
}  // namespace

TYPED_TEST(RayObb, IdentityAxesAgreeWithTheAabb) {
    using T = TypeParam;
    const Obb<T> box{v<T>(0, 0, 0), Mat3<T>::Identity(), v<T>(1, 1, 1)};
    check(Ray<T>{v<T>(-4, 0, 0), v<T>(1, 0, 0)}, box, hit<T>(3, 5, 0));
    check(Ray<T>{v<T>(0, 4, 0), v<T>(0, -1, 0)}, box, hit<T>(3, 5, 3));
    check(Ray<T>{v<T>(-3, -3, -3), v<T>(1, 1, 1)}, box, hit<T>(2, 4, 0));
    check(Ray<T>{v<T>(-4, 1, 0), v<T>(1, -0.0, 0)}, box, hit<T>(3, 5, 0));
    check(Ray<T>{v<T>(0, 0, 0), v<T>(0, 0, 1)}, box, hit<T>(0, 1, -1));
    check(Ray<T>{v<T>(-4, 2, 0), v<T>(1, 0, 0)}, box, miss<T>());
}

TYPED_TEST(RayObb, NonUnitAndNonOrthogonalAxesAreUsedAsStored) {
    using T = TypeParam;
    // |2x| <= 2, |y| <= 1, |z| <= 1: the unit cube of half-width 1
    const Obb<T> scaled{v<T>(0, 0, 0), cols<T>(v<T>(2, 0, 0), v<T>(0, 1, 0), v<T>(0, 0, 1)), v<T>(2, 1, 1)};
    check(Ray<T>{v<T>(-4, 0, 0), v<T>(1, 0, 0)}, scaled, hit<T>(3, 5, 0));
    // |x| <= 1, |x + y| <= 1, |z| <= 1: a parallelepiped
    const Obb<T> sheared{v<T>(0, 0, 0), cols<T>(v<T>(1, 0, 0), v<T>(1, 1, 0), v<T>(0, 0, 1)), v<T>(1, 1, 1)};
    check(Ray<T>{v<T>(0, -5, 0), v<T>(0, 1, 0)}, sheared, hit<T>(4, 6, 2));
    check(Ray<T>{v<T>(1, -5, 0), v<T>(0, 1, 0)}, sheared, hit<T>(3, 5, 2));
    check(Ray<T>{v<T>(-5, 0, 0), v<T>(1, 0, 0)}, sheared, hit<T>(4, 6, 0));   // slabs 0 and 1 tie at entry
}

TYPED_TEST(RayObb, RotatedIntegerAxes) {
    using T = TypeParam;
    const Vec3<T> c = v<T>(1, 2, 3);
    const Obb<T> box = rotated(c);
    // along a0 through the centre: (o-c)·a0 = -50, d·a0 = 25 -> t in [1, 3]; d·a1 = d·a2 = 0, origin inside those slabs
    check(Ray<T>{c - v<T>(6, 8, 0), v<T>(3, 4, 0)}, box, hit<T>(1, 3, 0));
    check(Ray<T>{c + v<T>(6, 8, 0), v<T>(-3, -4, 0)}, box, hit<T>(1, 3, 1));
    // through the corner c + (1,-7,0) = c - 5(a0+a1)/5 along (-1,7,0): slabs 0 and 1 both give [2, 4]
    check(Ray<T>{c + v<T>(3, -21, 0), v<T>(-1, 7, 0)}, box, hit<T>(2, 4, 0));
    // parallel to slab 0 (d·a0 = 0), origin exactly on its plane (o-c)·a0 = 25, then just off it
    check(Ray<T>{c + v<T>(11, -2, 0), v<T>(-4, 3, 0)}, box, hit<T>(1, 3, 2));
    check(Ray<T>{c + v<T>(11, -2, 0), v<T>(4, -3, 0)}, box, miss<T>());
    check(Ray<T>{c + v<T>(12, -2, 0), v<T>(-4, 3, 0)}, box, miss<T>());   // (o-c)·a0 = 28 > 25
    check(Ray<T>{c, v<T>(0, 0, 1)}, box, hit<T>(0, 5, -1));               // from the centre: |5z| <= 25
    check(Ray<T>{c + v<T>(100, 0, 0), v<T>(0, 1, 0)}, box, miss<T>());
}
