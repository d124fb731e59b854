// normal(shape, hit, ray): exact unit axis vectors from the face id for boxes (every
// face, both sides, corners resolved by the tie rule), normalized stored columns for
// Obb, the radial direction for spheres, the side facing the ray for planes, the entry
// plane's outward unit normal for convex polyhedra, and the
// zero vector when there is no entry face (ray starting inside) or no hit. reversed()
// gives the exit face of a ray that starts inside.
#include "unit_support.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

using namespace rayproof;
using namespace rayproof::testing;

template <class T> class Normal : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Normal, Scalars);

TYPED_TEST(Normal, BoxFacesAreExactAxes) {
    using T = TypeParam;
    const Aabb<T> box{v<T>(-1, -1, -1), v<T>(1, 1, 1)};
    for (int a = 0; a < 3; ++a)
        for (int s : {-1, 1}) {
            Vec3<T> o = Vec3<T>::Zero(), d = Vec3<T>::Zero();
            o[a] = T(4 * s);
            d[a] = T(-s);
            const Ray<T> r{o, d};
            const Hit<T> h = intersect(r, box, fast);
            ASSERT_TRUE(h);
            Vec3<T> expected = Vec3<T>::Zero();
            expected[a] = T(s);
            EXPECT_EQ(normal(box, h, r), expected) << r;
        }
    const Ray<T> inside{v<T>(0, 0, 0), v<T>(0, 1, 0)};
    const Hit<T> h = intersect(inside, box, fast);
    EXPECT_EQ(normal(box, h, inside), Vec3<T>::Zero());
    const Ray<T> back = reversed(Ray<T>{inside.origin, inside.direction, T(0), T(100)});
    const Hit<T> exit = intersect(back, box, fast);
    ASSERT_TRUE(exit);
    EXPECT_EQ(exit.face, 3);                                        // the +y face the original leaves by
    EXPECT_EQ(-exit.t_enter, T(1));
    EXPECT_EQ(normal(box, exit, back), v<T>(0, 1, 0));
    const Ray<T> away{v<T>(0, 4, 0), v<T>(0, 1, 0)};
    EXPECT_EQ(normal(box, intersect(away, box, fast), away), Vec3<T>::Zero());
}

// A polyhedron: the entry plane's stored normal made unit, pointing out (here a box
// tilted in its planes' scale: normals 2·e_i and -3·e_i), zero from inside and on a miss.
TYPED_TEST(Normal, PolyhedronUsesTheEntryPlane) {
    using T = TypeParam;
    const Plane<T> planes[6] = {{v<T>(-3, 0, 0), T(3)}, {v<T>(2, 0, 0), T(2)}, {v<T>(0, -3, 0), T(3)},
                                {v<T>(0, 2, 0), T(2)},  {v<T>(0, 0, -3), T(3)}, {v<T>(0, 0, 2), T(2)}};
    const ConvexPolyhedron<T> poly{planes};
    const Aabb<T> box{v<T>(-1, -1, -1), v<T>(1, 1, 1)};
    for (int a = 0; a < 3; ++a)
        for (int s : {-1, 1}) {
            Vec3<T> o = Vec3<T>::Zero(), d = Vec3<T>::Zero();
            o[a] = T(4 * s);
            d[a] = T(-s);
            const Ray<T> r{o, d};
            const Hit<T> h = intersect(r, poly, certified);
            ASSERT_TRUE(h);
            EXPECT_EQ(h.face, 2 * a + (s > 0));
            EXPECT_EQ(normal(poly, h, r), normal(box, intersect(r, box, certified), r)) << r;
        }
    const Ray<T> inside{v<T>(0, 0, 0), v<T>(0, 1, 0)};
    EXPECT_EQ(normal(poly, intersect(inside, poly, certified), inside), Vec3<T>::Zero());
    const Ray<T> away{v<T>(0, 4, 0), v<T>(0, 1, 0)};
    EXPECT_EQ(normal(poly, intersect(away, poly, certified), away), Vec3<T>::Zero());
}

TYPED_TEST(Normal, ObbUsesTheNormalizedColumn) {
    using T = TypeParam;
    Mat3<T> rot;
    rot << 3, -4, 0, 4, 3, 0, 0, 0, 5;
    const Obb<T> box{v<T>(0, 0, 0), rot, v<T>(25, 25, 25)};
    const Ray<T> r{v<T>(-6, -8, 0), v<T>(3, 4, 0)};
    const Hit<T> h = intersect(r, box, fast);
    ASSERT_TRUE(h);
    ASSERT_EQ(h.face, 0);
    const Vec3<T> n = normal(box, h, r);
    EXPECT_NEAR(double(n[0]), -0.6, 2 * double(std::numeric_limits<T>::epsilon()));
    EXPECT_NEAR(double(n[1]), -0.8, 2 * double(std::numeric_limits<T>::epsilon()));
    EXPECT_EQ(n[2], T(0));
}

TYPED_TEST(Normal, SphereAndPlane) {
    using T = TypeParam;
    const Sphere<T> ball{v<T>(1, 1, 1), 5};
    const Ray<T> r{v<T>(-9, 1, 1), v<T>(1, 0, 0)};
    EXPECT_EQ(normal(ball, intersect(r, ball, fast), r), v<T>(-1, 0, 0));
    const Ray<T> tangent{v<T>(-7, 1, 0) + v<T>(1, 1, 1), v<T>(4, 3, 0)};
    const Vec3<T> nt = normal(ball, intersect(tangent, ball, fast), tangent);
    EXPECT_NEAR(double(nt[0]), -0.6, 4 * double(std::numeric_limits<T>::epsilon()));
    EXPECT_NEAR(double(nt[1]), 0.8, 4 * double(std::numeric_limits<T>::epsilon()));
    const Plane<T> floor{v<T>(0, 2, 0), -2};
    const Ray<T> down{v<T>(0, 3, 0), v<T>(0, -1, 0)}, up{v<T>(0, -3, 0), v<T>(0, 1, 0)};
    EXPECT_EQ(normal(floor, intersect(down, floor, fast), down), v<T>(0, 1, 0));
    EXPECT_EQ(normal(floor, intersect(up, floor, fast), up), v<T>(0, -1, 0));
    const Ray<T> miss_ray{v<T>(0, 3, 0), v<T>(0, 1, 0)};
    EXPECT_EQ(normal(floor, intersect(miss_ray, floor, fast), miss_ray), Vec3<T>::Zero());
}

// normal() is a unit vector, |n| = 1 within a few ulps, at every magnitude the scalar
// type has: planes whose normal is 2^k or 1.5·2^k (subnormal to near the largest float),
// Obbs whose stored axes are scaled alike, spheres of radius 2^k, and point spheres hit by
// a direction of 2^k (the fallback, the direction opposing the ray). The length is
// measured in long double, so the test's own rounding is far below the tolerance: four
// units in the last place of 1, the gamma(4) of unit_vector with room for the final sum.
template <class T> void expect_unit(const Vec3<T>& n, const std::string& what) {
    const long double len = std::sqrt(static_cast<long double>(n[0]) * n[0] + static_cast<long double>(n[1]) * n[1] +
                                      static_cast<long double>(n[2]) * n[2]);
    EXPECT_LE(std::fabs(len - 1.0L), 4.0L * std::numeric_limits<T>::epsilon()) << what << ": |n| = " << double(len)
                                                                               << ", n = " << n.transpose();
}

TYPED_TEST(Normal, UnitAtEveryMagnitude) {
    using T = TypeParam;
    using L = std::numeric_limits<T>;
    int planes = 0, obbs = 0, spheres = 0, points = 0;
    for (int k = L::min_exponent - L::digits; k <= L::max_exponent - 2; ++k)
        for (const T m : {T(1), T(1.5)}) {
            const T s = std::ldexp(m, k);
            std::ostringstream scale;
            scale << "scale " << std::hexfloat << double(s);
            const std::string at = scale.str();
            // A plane x = 0 with normal (s, 0, 0) or (s, s, 0), the ray coming from +x.
            for (const Vec3<T>& nrm : {v<T>(1, 0, 0), v<T>(1, 1, 0)}) {
                const Plane<T> pl{Vec3<T>(nrm * s), T(0)};
                const Ray<T> r{v<T>(1, 0.25, 0.5), v<T>(-1, 0, 0)};
                const Hit<T> h = intersect(r, pl, certified);
                if (!h) continue;
                const Vec3<T> n = normal(pl, h, r);
                expect_unit(n, "plane, " + at);
                EXPECT_GT(n[0], T(0)) << "plane normal faces the ray, " << at;
                ++planes;
            }
            // An Obb whose axes are s·I and half extents s: the cube |p_i| <= 1.
            const Obb<T> box{Vec3<T>::Zero(), Mat3<T>(Mat3<T>::Identity() * s), v<T>(s, s, s)};
            const Ray<T> into{v<T>(4, 0.25, 0.5), v<T>(-1, 0, 0)};
            const Hit<T> hb = intersect(into, box, certified);
            if (hb) {
                const Vec3<T> n = normal(box, hb, into);
                expect_unit(n, "obb, " + at);
                EXPECT_GT(n[0], T(0)) << "obb entry face +x, " << at;
                ++obbs;
            }
            // A sphere of radius s at the origin, entered from +x.
            const Sphere<T> ball{Vec3<T>::Zero(), s};
            const Ray<T> toward{v<T>(1, 0, 0) * (T(3) * s), v<T>(-1, 0, 0)};
            const Hit<T> hs = intersect(toward, ball, certified);
            if (hs && std::isfinite(toward.origin[0])) {
                const Vec3<T> n = normal(ball, hs, toward);
                expect_unit(n, "sphere, " + at);
                EXPECT_GT(n[0], T(0)) << "sphere normal outward, " << at;
                ++spheres;
            }
            // A point sphere hit by the direction (-s, 0, 0) at t = 1: the fallback.
            const Sphere<T> point{Vec3<T>::Zero(), T(0)};
            const Ray<T> at_point{v<T>(1, 0, 0) * s, v<T>(-1, 0, 0) * s};
            const Hit<T> hp = intersect(at_point, point, certified);
            if (hp) {
                const Vec3<T> n = normal(point, hp, at_point);
                expect_unit(n, "point sphere, " + at);
                EXPECT_GT(n[0], T(0)) << "point sphere normal opposes the ray, " << at;
                ++points;
            }
        }
    // Most magnitudes must really have been reached: every shape answers hit over the
    // whole finite range but where its setup itself overflows.
    const int span = 2 * (L::max_exponent - 1 - L::min_exponent + L::digits);
    EXPECT_GE(planes, 2 * span - 8) << "plane cases reached";
    EXPECT_GE(obbs, span - 8) << "obb cases reached";
    EXPECT_GE(spheres, span - 8) << "sphere cases reached";
    EXPECT_GE(points, span - 8) << "point sphere cases reached";
}
