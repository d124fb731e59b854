// Every invalid-input class of the contract, for every shape, over float and double, in
// every mode the kernel has: each must answer Verdict::invalid (never a crash, never an
// exception). Also the allowed exceptions (t_min = -inf, t_max = +inf, radius 0,
// radius -0, flat boxes, t_min == t_max, a near-singular but independent Obb) must
// not be reported invalid.
#include "unit_support.hpp"

#include <cmath>
#include <limits>
#include <vector>

using namespace rayproof;
using namespace rayproof::testing;

template <class T> class Validate : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Validate, Scalars);

namespace {

template <class T> std::vector<T> non_finite() {
    return {std::numeric_limits<T>::quiet_NaN(), -std::numeric_limits<T>::quiet_NaN(),
            std::numeric_limits<T>::infinity(), -std::numeric_limits<T>::infinity()};
}

template <class T, class Shape, class Mode> void expect_invalid_in(const Ray<T>& r, const Shape& s, Mode m) {
    const Hit<T> h = intersect(r, s, m);
    EXPECT_EQ(h.verdict, Verdict::invalid) << mode_name(m) << ": " << r << " vs " << s << " gave " << h;
    EXPECT_FALSE(bool(h));
}
template <class T, class Shape> void expect_invalid(const Ray<T>& r, const Shape& s) {
    expect_invalid_in(r, s, fast);
    if constexpr (Answerable<T, Shape, conservative_t>) expect_invalid_in(r, s, conservative);
    if constexpr (Answerable<T, Shape, certified_t>) expect_invalid_in(r, s, certified);
}
template <class T, class Shape, class Mode> void expect_valid_in(const Ray<T>& r, const Shape& s, Mode m) {
    EXPECT_NE(intersect(r, s, m).verdict, Verdict::invalid) << mode_name(m) << ": " << r << " vs " << s;
}
template <class T, class Shape> void expect_valid(const Ray<T>& r, const Shape& s) {
    expect_valid_in(r, s, fast);
    if constexpr (Answerable<T, Shape, conservative_t>) expect_valid_in(r, s, conservative);
    if constexpr (Answerable<T, Shape, certified_t>) expect_valid_in(r, s, certified);
}

template <class T> Ray<T> good_ray() { return {v<T>(-4, 0.5, 0.25), v<T>(1, 0, 0)}; }
template <class T> Aabb<T> good_box() { return {v<T>(-1, -1, -1), v<T>(1, 1, 1)}; }
template <class T> Obb<T> good_obb() { return {v<T>(0, 0, 0), Mat3<T>::Identity(), v<T>(1, 1, 1)}; }
template <class T> Plane<T> good_plane() { return {v<T>(1, 0, 0), 0}; }
template <class T> Sphere<T> good_sphere() { return {v<T>(0, 0, 0), 1}; }

// Every ray-side invalid class, against one shape.
template <class T, class Shape> void bad_rays_against(const Shape& s) {
    for (T x : non_finite<T>())
        for (int i = 0; i < 3; ++i) {
            Ray<T> r = good_ray<T>();
            r.origin[i] = x;
            expect_invalid(r, s);
            r = good_ray<T>();
            r.direction[i] = x;
            expect_invalid(r, s);
        }
    const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
    for (T tmin : {nan, inf}) {
        Ray<T> r = good_ray<T>();
        r.t_min = tmin;
        expect_invalid(r, s);
    }
    for (T tmax : {nan, -inf}) {
        Ray<T> r = good_ray<T>();
        r.t_max = tmax;
        expect_invalid(r, s);
    }
    Ray<T> r = good_ray<T>();
    r.t_min = 2;
    r.t_max = 1;
    expect_invalid(r, s);
    r.t_min = std::nextafter(T(1), T(2));
    expect_invalid(r, s);
    for (T z0 : {T(0), -T(0)})
        for (T z1 : {T(0), -T(0)}) {
            r = good_ray<T>();
            r.direction = Vec3<T>(z0, z1, -T(0));
            expect_invalid(r, s);
        }
    // the allowed exceptions
    r = good_ray<T>();
    r.t_min = -inf;
    r.t_max = inf;
    expect_valid(r, s);
    r.t_min = r.t_max = T(3);
    expect_valid(r, s);
    r.direction = Vec3<T>(std::numeric_limits<T>::denorm_min(), 0, 0);
    expect_valid(r, s);
}

}  // namespace

TYPED_TEST(Validate, BadRaysAgainstEveryShape) {
    using T = TypeParam;
    bad_rays_against<T>(good_box<T>());
    bad_rays_against<T>(good_obb<T>());
    bad_rays_against<T>(good_plane<T>());
    bad_rays_against<T>(good_sphere<T>());
}

TYPED_TEST(Validate, Aabb) {
    using T = TypeParam;
    const Ray<T> r = good_ray<T>();
    for (T x : non_finite<T>())
        for (int i = 0; i < 3; ++i) {
            Aabb<T> b = good_box<T>();
            b.lo[i] = x;
            expect_invalid(r, b);
            b = good_box<T>();
            b.hi[i] = x;
            expect_invalid(r, b);
        }
    for (int i = 0; i < 3; ++i) {
        Aabb<T> b = good_box<T>();
        b.lo[i] = std::nextafter(b.hi[i], T(2));
        expect_invalid(r, b);
        b.lo[i] = b.hi[i];  // flat: valid
        expect_valid(r, b);
    }
}

TYPED_TEST(Validate, Sphere) {
    using T = TypeParam;
    const Ray<T> r = good_ray<T>();
    for (T x : non_finite<T>()) {
        for (int i = 0; i < 3; ++i) {
            Sphere<T> s = good_sphere<T>();
            s.center[i] = x;
            expect_invalid(r, s);
        }
        Sphere<T> s = good_sphere<T>();
        s.radius = x;
        expect_invalid(r, s);
    }
    for (T rad : {T(-1), -std::numeric_limits<T>::denorm_min(), -std::numeric_limits<T>::max()})
        expect_invalid(r, Sphere<T>{v<T>(0, 0, 0), rad});
    expect_valid(r, Sphere<T>{v<T>(0, 0, 0), T(0)});
    expect_valid(r, Sphere<T>{v<T>(0, 0, 0), -T(0)});
}

TYPED_TEST(Validate, Plane) {
    using T = TypeParam;
    const Ray<T> r = good_ray<T>();
    for (T x : non_finite<T>()) {
        for (int i = 0; i < 3; ++i) {
            Plane<T> p = good_plane<T>();
            p.normal[i] = x;
            expect_invalid(r, p);
        }
        Plane<T> p = good_plane<T>();
        p.offset = x;
        expect_invalid(r, p);
    }
    expect_invalid(r, Plane<T>{v<T>(0, 0, 0), 1});
    expect_invalid(r, Plane<T>{Vec3<T>(-T(0), T(0), -T(0)), 0});
    expect_valid(r, Plane<T>{Vec3<T>(0, 0, std::numeric_limits<T>::denorm_min()), 0});
}

TYPED_TEST(Validate, Obb) {
    using T = TypeParam;
    const Ray<T> r = good_ray<T>();
    for (T x : non_finite<T>()) {
        for (int i = 0; i < 3; ++i) {
            Obb<T> b = good_obb<T>();
            b.center[i] = x;
            expect_invalid(r, b);
            b = good_obb<T>();
            b.half_extent[i] = x;
            expect_invalid(r, b);
        }
        for (int k = 0; k < 9; ++k) {
            Obb<T> b = good_obb<T>();
            b.axes.data()[k] = x;
            expect_invalid(r, b);
        }
    }
    for (int i = 0; i < 3; ++i) {
        Obb<T> b = good_obb<T>();
        b.half_extent[i] = -std::numeric_limits<T>::denorm_min();
        expect_invalid(r, b);
        b.half_extent[i] = T(0);  // flat: valid
        expect_valid(r, b);
    }
    Mat3<T> m;
    m << 1, 2, 3, 4, 5, 9, 7, 8, 15;  // column 2 = column 0 + column 1
    expect_invalid(r, Obb<T>{v<T>(0, 0, 0), m, v<T>(1, 1, 1)});
    expect_invalid(r, Obb<T>{v<T>(0, 0, 0), Mat3<T>(m * T(0x1p-60)), v<T>(1, 1, 1)});
    expect_invalid(r, Obb<T>{v<T>(0, 0, 0), Mat3<T>(m * T(0x1p60)), v<T>(1, 1, 1)});
    Mat3<T> zero_col = Mat3<T>::Identity();
    zero_col.col(1).setZero();
    expect_invalid(r, Obb<T>{v<T>(0, 0, 0), zero_col, v<T>(1, 1, 1)});
    Mat3<T> twin = Mat3<T>::Identity();
    twin.col(2) = twin.col(0);
    expect_invalid(r, Obb<T>{v<T>(0, 0, 0), twin, v<T>(1, 1, 1)});
    // independent, though the determinant is far below the rounding error of its terms
    Mat3<T> near = m;
    near(2, 2) = std::nextafter(T(15), T(16));
    expect_valid(r, Obb<T>{v<T>(0, 0, 0), near, v<T>(1, 1, 1)});
    // independent with a determinant that underflows when computed naively
    const T tiny = std::numeric_limits<T>::denorm_min();
    expect_valid(r, Obb<T>{v<T>(0, 0, 0), Mat3<T>(Mat3<T>::Identity() * tiny), v<T>(1, 1, 1)});
    if constexpr (std::is_same_v<T, double>)
        expect_invalid(r, Obb<T>{v<T>(0, 0, 0), Mat3<T>(m * T(0x1p-1060)), v<T>(1, 1, 1)});
}
