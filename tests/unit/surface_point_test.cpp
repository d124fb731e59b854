// The embedder helpers of rayproof/surface_point.hpp, decided in exact arithmetic
// (detail::BigDyadic, exact for every finite double and float) on the shared generators'
// cases (general, grazing, near grazing, parallel, on the boundary, extreme, ...) for
// every shape, scalar type and mode:
//   - the error box [p - error, p + error] of surface_point holds a point exactly on the
//     surface (the sphere, the plane, the entry face's plane, a polyhedron's entry
//     plane; for the Aabb p itself lies on the face);
//   - spawn_origin(sp, +1) lies strictly on the side n faces of the surface and
//     spawn_origin(sp, -1) strictly on the other (for the sphere: strictly outside the
//     ball on the outer side), and the whole error box lies strictly behind each;
//   - offset_origin moves every coordinate with n_i != 0 strictly past p_i + dist·n_i·(1 - u);
//   - no surface point (a miss, a box entered from inside) gives an infinite bound and a
//     zero normal.
#include "seeded.hpp"

#include <rayproof/detail/exact.hpp>
#include <rayproof/generators.hpp>
#include <rayproof/rayproof.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

using namespace rayproof;
using B = rayproof::detail::BigDyadic;

namespace {

std::uint64_t base_seed() {
    static const std::uint64_t s = rayproof::testing::env_seed_or(2323);
    return s;
}

template <class T> B ex(T x) { return B(double(x)); }
int sign_of(const B& x) { return x.sign(); }

// Σ|a_i|·e_i and a·p - h exactly.
template <class T> B abs_dot(const Vec3<T>& a, const Vec3<T>& e) {
    B s(0.0);
    for (int i = 0; i < 3; ++i) s = s + ex(std::abs(a[i])) * ex(e[i]);
    return s;
}
template <class T> B affine(const Vec3<T>& a, const Vec3<T>& p, const Vec3<T>& c, T h) {
    B s = -ex(h);
    for (int i = 0; i < 3; ++i) s = s + ex(a[i]) * (ex(p[i]) - ex(c[i]));
    return s;
}

// The error box around p meets the plane a·(x - c) = h: |a·(p - c) - h| <= Σ|a_i| e_i.
template <class T>
::testing::AssertionResult box_meets_plane(const Vec3<T>& a, const Vec3<T>& c, T h, const SurfacePoint<T>& sp) {
    const B r = affine(a, sp.p, c, h), E = abs_dot(a, sp.error);
    if (sign_of(E - r) >= 0 && sign_of(E + r) >= 0) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "the error box misses the plane";
}

// The error box around p meets the sphere |x - c| = r: min |x - c|² <= r² <= max |x - c|²
// over the box, per coordinate.
template <class T> ::testing::AssertionResult box_meets_sphere(const Sphere<T>& s, const SurfacePoint<T>& sp) {
    B lo_sq(0.0), hi_sq(0.0);
    for (int i = 0; i < 3; ++i) {
        const B lo = ex(sp.p[i]) - ex(sp.error[i]), hi = ex(sp.p[i]) + ex(sp.error[i]), c = ex(s.center[i]);
        const B below = lo - c, above = hi - c;  // below <= above
        if (sign_of(below) > 0) lo_sq = lo_sq + below * below;
        if (sign_of(above) < 0) lo_sq = lo_sq + above * above;
        const B far = sign_of(above + below) >= 0 ? above : below;
        hi_sq = hi_sq + far * far;
    }
    const B r2 = ex(s.radius) * ex(s.radius);
    if (sign_of(r2 - lo_sq) >= 0 && sign_of(hi_sq - r2) >= 0) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "the error box misses the sphere";
}

// The side of a point against a face's or a plane's oriented plane: the sign of
// a·(q - c) - h, and the side n faces (the sign of n·a, taken where |a_k| is largest).
template <class T> int facing(const Vec3<T>& a, const Vec3<T>& n) {
    Eigen::Index k = 0;
    a.cwiseAbs().maxCoeff(&k);
    return (n[k] > 0) == (a[k] > 0) ? 1 : -1;
}

struct Counts {
    int hits = 0, checked = 0;
};

// Every point y of the error box lies strictly behind the spawned origin q along the
// side's normal: side·(q - p)·n > Σ|n_i|·error_i, exactly.
template <class T> void box_behind(const SurfacePoint<T>& sp, int side) {
    const Vec3<T> q = spawn_origin(sp, side);
    if (!detail::finite_vec(q)) return;
    B moved(0.0);
    for (int i = 0; i < 3; ++i) moved = moved + (ex(q[i]) - ex(sp.p[i])) * ex(sp.n[i]);
    if (side < 0) moved = -moved;
    EXPECT_GT(sign_of(moved - abs_dot(sp.n, sp.error)), 0) << "side " << side << ": " << q.transpose();
}
template <class T> void boxes_behind(const SurfacePoint<T>& sp) {
    box_behind(sp, +1);
    box_behind(sp, -1);
}

// Every check on one hit.
template <class T> void check(const Ray<T>& r, const Aabb<T>& b, const Hit<T>& h, Counts& n) {
    const SurfacePoint<T> sp = surface_point(r, b, h);
    if (h.face < 0) {
        EXPECT_TRUE(sp.n.isZero());
        EXPECT_TRUE(std::isinf(sp.error[0]) && std::isinf(sp.error[1]) && std::isinf(sp.error[2]));
        return;
    }
    if (!std::isfinite(sp.error[0])) return;
    ++n.checked;
    const int axis = h.face / 2, side = h.face % 2;
    EXPECT_EQ(sp.p[axis], side ? b.hi[axis] : b.lo[axis]);
    for (int j = 0; j < 3; ++j) {
        EXPECT_LE(b.lo[j], sp.p[j]);
        EXPECT_LE(sp.p[j], b.hi[j]);
    }
    EXPECT_TRUE(sp.error.isZero());
    boxes_behind(sp);
    const Vec3<T> out = spawn_origin(sp, +1), in = spawn_origin(sp, -1);
    if (side) {
        EXPECT_GT(out[axis], b.hi[axis]);
        EXPECT_LT(in[axis], b.hi[axis]);
    } else {
        EXPECT_LT(out[axis], b.lo[axis]);
        EXPECT_GT(in[axis], b.lo[axis]);
    }
}

template <class T> void check(const Ray<T>& r, const Obb<T>& b, const Hit<T>& h, Counts& n) {
    const SurfacePoint<T> sp = surface_point(r, b, h);
    if (h.face < 0) {
        EXPECT_TRUE(sp.n.isZero());
        EXPECT_TRUE(std::isinf(sp.error[0]));
        return;
    }
    if (!std::isfinite(sp.error[0]) || !std::isfinite(spawn_offset(sp))) return;
    ++n.checked;
    const int axis = h.face / 2;
    const Vec3<T> a = b.axes.col(axis);
    const T hh = (h.face % 2) ? b.half_extent[axis] : -b.half_extent[axis];
    EXPECT_TRUE(box_meets_plane(a, b.center, hh, sp));
    boxes_behind(sp);
    const int f = facing(a, sp.n);
    const Vec3<T> out = spawn_origin(sp, +1), in = spawn_origin(sp, -1);
    if (!detail::finite_vec(out) || !detail::finite_vec(in)) return;
    EXPECT_EQ(sign_of(affine(a, out, b.center, hh)), f) << "spawned outward: " << out.transpose();
    EXPECT_EQ(sign_of(affine(a, in, b.center, hh)), -f) << "spawned inward: " << in.transpose();
}

template <class T> void check(const Ray<T>& r, const Plane<T>& pl, const Hit<T>& h, Counts& n) {
    const SurfacePoint<T> sp = surface_point(r, pl, h);
    if (!std::isfinite(sp.error[0]) || !std::isfinite(spawn_offset(sp))) return;
    ++n.checked;
    const Vec3<T> zero = Vec3<T>::Zero();
    EXPECT_TRUE(box_meets_plane(pl.normal, zero, pl.offset, sp));
    boxes_behind(sp);
    const int f = facing(pl.normal, sp.n);
    const Vec3<T> front = spawn_origin(sp, +1), back = spawn_origin(sp, -1);
    if (!detail::finite_vec(front) || !detail::finite_vec(back)) return;
    EXPECT_EQ(sign_of(affine(pl.normal, front, zero, pl.offset)), f) << "spawned in front: " << front.transpose();
    EXPECT_EQ(sign_of(affine(pl.normal, back, zero, pl.offset)), -f) << "spawned behind: " << back.transpose();
}

// A polyhedron: no surface point from inside (face -1); otherwise the error box meets
// the entry plane, n is that plane's outward unit normal (normal()), and the spawned
// origins lie strictly outside (+1) and strictly inside (-1) its half-space.
template <class T> void check(const Ray<T>& r, const ConvexPolyhedron<T>& poly, const Hit<T>& h, Counts& n) {
    const SurfacePoint<T> sp = surface_point(r, poly, h);
    if (h.face < 0) {
        EXPECT_TRUE(sp.n.isZero());
        EXPECT_TRUE(std::isinf(sp.error[0]) && std::isinf(sp.error[1]) && std::isinf(sp.error[2]));
        return;
    }
    if (!std::isfinite(sp.error[0]) || !std::isfinite(spawn_offset(sp))) return;
    ++n.checked;
    const Plane<T>& pl = poly.planes[std::size_t(h.face)];
    EXPECT_EQ(sp.n, normal(poly, h, r));
    EXPECT_EQ(facing(pl.normal, sp.n), 1) << "the normal points out of the solid";
    const Vec3<T> zero = Vec3<T>::Zero();
    EXPECT_TRUE(box_meets_plane(pl.normal, zero, pl.offset, sp));
    boxes_behind(sp);
    const Vec3<T> out = spawn_origin(sp, +1), in = spawn_origin(sp, -1);
    if (!detail::finite_vec(out) || !detail::finite_vec(in)) return;
    EXPECT_GT(sign_of(affine(pl.normal, out, zero, pl.offset)), 0) << "spawned outward: " << out.transpose();
    EXPECT_LT(sign_of(affine(pl.normal, in, zero, pl.offset)), 0) << "spawned inward: " << in.transpose();
}

template <class T> B dist2_minus_r2(const Sphere<T>& s, const Vec3<T>& q) {
    B d(0.0);
    for (int i = 0; i < 3; ++i) {
        const B x = ex(q[i]) - ex(s.center[i]);
        d = d + x * x;
    }
    return d - ex(s.radius) * ex(s.radius);
}

template <class T> void check(const Ray<T>& r, const Sphere<T>& s, const Hit<T>& h, Counts& n) {
    const SurfacePoint<T> sp = surface_point(r, s, h);
    if (!std::isfinite(sp.error[0]) || !std::isfinite(spawn_offset(sp))) return;
    ++n.checked;
    EXPECT_TRUE(box_meets_sphere(s, sp));
    boxes_behind(sp);
    if (s.radius == 0) {
        EXPECT_EQ(sp.p, s.center);
    }
    const Vec3<T> out = spawn_origin(sp, +1);
    if (!detail::finite_vec(out)) return;
    EXPECT_GT(sign_of(dist2_minus_r2(s, out)), 0) << "spawned outward: " << out.transpose();
}

// The kernel's shape of a case (a polyhedron case owns its planes).
template <class S> const S& shape_of(const S& s) { return s; }
template <class T> ConvexPolyhedron<T> shape_of(const gen::OwnedPolyhedron<T>& p) { return p.view(); }

constexpr int kCasesPerGenerator = 400;

template <class T, class Shape, class Mode> void check_shape(Mode m) {
    std::mt19937_64 rng = rayproof::testing::rng_for_current_test(base_seed());
    RAYPROOF_SEED_TRACE(base_seed());
    Counts n;
    for (const auto& g : gen::generators<T, Shape>()) {
        for (int i = 0; i < kCasesPerGenerator; ++i) {
            const gen::Case<T, Shape> c = g.make(rng);
            const auto shape = shape_of(c.shape);
            const Hit<T> h = intersect(c.ray, shape, m);
            if (!h) {
                const SurfacePoint<T> sp = surface_point(c.ray, shape, h);
                ASSERT_TRUE(sp.n.isZero());
                ASSERT_TRUE(std::isinf(sp.error[0]) && std::isinf(sp.error[1]) && std::isinf(sp.error[2]));
                continue;
            }
            ++n.hits;
            std::ostringstream what;
            what << mode_name(m) << ' ' << c << ' ' << h;
            SCOPED_TRACE(what.str());
            check(c.ray, shape, h, n);
            // The exit point through the reversed ray.
            const Ray<T> rev = reversed(c.ray);
            const Hit<T> hr = intersect(rev, shape, m);
            if (hr) check(rev, shape, hr, n);
            if (::testing::Test::HasFailure()) return;
        }
    }
    // The cases reach the checks (a guard against a generator change that would leave
    // the test checking nothing).
    EXPECT_GT(n.hits, kCasesPerGenerator);
    EXPECT_GT(n.checked, kCasesPerGenerator / 2);
}

template <class T, class Shape> void check_all_modes() {
    check_shape<T, Shape>(fast);
    check_shape<T, Shape>(conservative);
    check_shape<T, Shape>(certified);
}

}  // namespace

TEST(SurfacePoint, AabbFloat) { check_all_modes<float, Aabb<float>>(); }
TEST(SurfacePoint, AabbDouble) { check_all_modes<double, Aabb<double>>(); }
TEST(SurfacePoint, ObbFloat) { check_all_modes<float, Obb<float>>(); }
TEST(SurfacePoint, ObbDouble) { check_all_modes<double, Obb<double>>(); }
TEST(SurfacePoint, PlaneFloat) { check_all_modes<float, Plane<float>>(); }
TEST(SurfacePoint, PlaneDouble) { check_all_modes<double, Plane<double>>(); }
TEST(SurfacePoint, SphereFloat) { check_all_modes<float, Sphere<float>>(); }
TEST(SurfacePoint, SphereDouble) { check_all_modes<double, Sphere<double>>(); }
TEST(SurfacePoint, PolyhedronFloat) { check_all_modes<float, gen::OwnedPolyhedron<float>>(); }
TEST(SurfacePoint, PolyhedronDouble) { check_all_modes<double, gen::OwnedPolyhedron<double>>(); }

// A far small sphere: the certified hit point, reprojected, carries a bound of the size
// of the centre's rounding, and still meets the sphere.
TEST(SurfacePoint, FarSmallSphereStillMeetsTheSurface) {
    const Sphere<double> s{Vec3<double>(0x1p40, -0x1p40 / 3, 1e6), 1e-3};
    const Ray<double> r{Vec3<double>(0, 0, 0), s.center};
    const Hit<double> h = intersect(r, s, certified);
    ASSERT_TRUE(h);
    const SurfacePoint<double> sp = surface_point(r, s, h);
    ASSERT_TRUE(std::isfinite(sp.error[0]));
    EXPECT_TRUE(box_meets_sphere(s, sp));
    EXPECT_GT(sign_of(dist2_minus_r2(s, spawn_origin(sp, +1))), 0);
    // Within a few ulps of the centre's magnitude: not a loose bound.
    EXPECT_LT(sp.error.maxCoeff(), 64 * std::numeric_limits<double>::epsilon() * 0x1p40);
}

// offset_origin: every coordinate with n_i != 0 ends strictly beyond p_i + fl(dist·n_i),
// exactly decided, at the edges of the range too.
TEST(SurfacePoint, OffsetOriginMovesStrictlyPastTheDistance) {
    std::mt19937_64 rng = rayproof::testing::rng_for_current_test(base_seed());
    RAYPROOF_SEED_TRACE(base_seed());
    for (int k = 0; k < 20000; ++k) {
        Vec3<double> p, n;
        for (int i = 0; i < 3; ++i) {
            p[i] = gen::wide_value<double>(rng) * 0x1p-4;
            n[i] = gen::uniform<double>(rng, -1, 1);
        }
        if (k % 7 == 0) n[k % 3] = 0;
        n = detail::unit_vector(n);
        const double dist = std::abs(gen::wide_value<double>(rng)) * 0x1p-8;
        const Vec3<double> q = offset_origin(p, n, dist);
        for (int i = 0; i < 3; ++i) {
            SCOPED_TRACE(::testing::Message() << std::hexfloat << "p " << p[i] << " n " << n[i] << " dist " << dist);
            if (!std::isfinite(q[i])) continue;
            if (n[i] == 0) {
                EXPECT_EQ(q[i], p[i]);
                continue;
            }
            // (q - p)·sign(n) > |fl(dist·n_i)| >= (1 - u)·dist·|n_i|
            const B moved = (ex(q[i]) - ex(p[i])) * B(n[i] > 0 ? 1.0 : -1.0);
            EXPECT_GT(sign_of(moved - ex(std::abs(dist * n[i]))), 0);
        }
    }
}

TEST(SurfacePoint, ExactPointsNeedNoOffset) {
    const Aabb<double> b{Vec3<double>(-1, -1, -1), Vec3<double>(1, 1, 1)};
    const Ray<double> r{Vec3<double>(-4, 0.25, 0.5), Vec3<double>(1, 0, 0)};
    const Hit<double> h = intersect(r, b, certified);
    const SurfacePoint<double> sp = surface_point(r, b, h);
    EXPECT_EQ(sp.p, Vec3<double>(-1, 0.25, 0.5));
    EXPECT_EQ(sp.n, Vec3<double>(-1, 0, 0));
    EXPECT_EQ(spawn_offset(sp), 0x1p-969);  // the floor: no error to clear
    EXPECT_EQ(spawn_origin(sp, +1), Vec3<double>(std::nextafter(-1.0, -2.0), 0.25, 0.5));
    EXPECT_EQ(spawn_origin(sp, -1), Vec3<double>(std::nextafter(-1.0, 0.0), 0.25, 0.5));
    static_assert(noexcept(surface_point(r, b, h)));
    static_assert(noexcept(spawn_origin(sp, 1)));
}
