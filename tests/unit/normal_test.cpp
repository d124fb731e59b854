// normal(shape, hit, ray): exact unit axis vectors from the face id for boxes (every
// face, both sides, corners resolved by the tie rule), normalized stored columns for
// Obb, the radial direction for spheres, the side facing the ray for planes, and the
// zero vector when there is no entry face (ray starting inside) or no hit. reversed()
// gives the exit face of a ray that starts inside.
#include "unit_support.hpp"

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
