// rayproof/surface_point.hpp — the point where a ray meets a shape's surface, with a
// per-component bound on its error, and the origin of a secondary ray that leaves the
// surface on a chosen side without any epsilon (the approach of pbrt-v4, sections 6.8.5
// and 6.8.6, written here for the kernel's shapes).
//
//   const Hit<double> h = intersect(ray, shape, certified);
//   const SurfacePoint<double> sp = surface_point(ray, shape, h);
//   const Ray<double> bounce{spawn_origin(sp, +1), reflected_direction};  // t_min = 0
//
// The promise of surface_point(ray, shape, hit), for a hit (Verdict::hit) of any mode:
//     there is a point x exactly on the surface with |p_i - x_i| <= error_i, i = 0, 1, 2,
// where the surface is the sphere |x - c| = r, the plane n·x = offset, and for boxes the
// plane of the entry face hit.face (for the Aabb, x is even on the face itself), and for
// a convex polyhedron the entry plane planes[hit.face]. p is
// the point on the ray at hit.t_enter, o + t·d, pulled onto the surface where the shape
// allows it, so the bound does not depend on how accurate t is: a fast-mode t gives a
// bound as true as a certified one, only larger when t is further off. For the exit
// point, pass reversed(ray) and its hit (its t_enter is -t_exit, its face the exit
// face); for a sphere a Hit whose t_enter is set to the t wanted works as well.
// n is the unit normal of rayproof::normal (outward for solids; for the plane, facing
// the ray's origin side), computed from p for the sphere and for a point sphere the
// direction opposing the ray.
// No surface point: a hit that is not Verdict::hit, a box or polyhedron hit with face -1
// (the ray starts inside: query reversed(ray) for the exit face), or a point or bound that is not
// finite (overflow, or t = ±inf for a ray lying in the plane): error is +inf in every
// component and n is zero.
//
// Each computed bound is rounded upwards: a non-negative expression computed with k
// roundings (sums and products of non-negative terms) is at least its exact value times
// (1 - u)^k, and round_up(x, k) = fl(x·(1 + 2(k+1)u)) brings it back above, by the
// factor (1 - u)^(k+1)·(1 + 2(k+1)u) >= 1. eta, the smallest normal
// T, covers operations whose results fall into the subnormal range (each off by at most
// half the smallest subnormal, in absolute terms) and is added once per bound.
// gamma(n) = n·u/(1 - n·u) bounds n successive roundings (detail/rounding.hpp).
//
// spawn_offset(sp) = Σ|n_i|·error_i, enlarged: every point y of the error box around p
// has |(y - p)·n| <= Σ|n_i|·error_i, so moving p that far along n carries it past the
// plane through x with normal n. n is the computed unit normal (detail::unit_vector in
// normal.hpp; for the sphere made from vs/l, two more roundings), whose components
// differ from the exact unit normal's by at most gamma(6) relative and keep their
// signs, and it enters twice (in the offset and in the direction moved); with a plane
// a·y = h and a residual bound G (G/|a_k| <= error_k), the exact residual at the new
// origin q, on n's side, is at least
//     -G + (1 - u)·dist·Σ|n_i||a_i| >= G·(-1 + (1 + 63u)(1 - u)(1 - gamma(6))^4 - 3u) > 0,
// with dist >= (1 + 63u)(1 - gamma(6))·G/|a| the offset after the roundings of its own
// sum (the factor (1 + 64u), exactly representable, keeps more than 1 + 63u of itself
// through them), and 3u for the components whose fl(dist·n_i) underflows (|n_i| <
// 2^-p). The floor 2^p·eta on dist (2^-969 for double, 2^-102 for float) keeps every
// other product normal and makes the loss of the products in the sum that underflow
// (at most 3·2^-1075) irrelevant. The same inequalities, with the tangent plane of the
// sphere at x, put an origin spawned on the outer side of a sphere strictly outside the
// ball (the ball lies behind each of its tangent planes), and one spawned on the inner
// side strictly behind the tangent plane at x. That puts it inside the ball when the
// sphere is large against the offset and against the spacing of the floats around p,
// but it is not promised (the one-float steps below can move a coordinate sideways by
// more than the radius of a small sphere far from the origin).
// offset_origin(p, n, dist) moves each coordinate by fl(dist·n_i) and one float further
// in the direction of n_i (pbrt-v4's OffsetRayOrigin): the step makes q_i exceed the
// unrounded p_i + fl(dist·n_i) strictly (in the direction of n_i), so (q - p)_i·n_i >
// (1 - u)·dist·n_i² for every n_i != 0 whose product does not underflow, whatever the
// roundings.
// spawn_origin(sp, side) = offset_origin(p, ±n, spawn_offset(sp)): side > 0 the side n
// faces, side < 0 the other one. For a plane or a box face the spawned origin is
// strictly on that side of the surface's plane; for the sphere, see above. Every point
// y of the error box lies strictly behind it: (q - y)·n > 0 for side > 0 (< 0 for
// side < 0). A tracer that queries the kernel again from there may add a margin of its
// own for the mode it uses (a fast or conservative answer may still report the surface
// just left); the certified mode needs none.
// Contraction (detail/eft.hpp): class C1 throughout. Each bound counts separate
// roundings and a fused product rounds once fewer; the point p is taken as computed,
// fused or not; offset_origin's product is rounded() (class C3), so that q_i exceeds
// p_i + fl(dist·n_i) as it promises (fused, it would exceed p_i + dist·n_i, which the
// proof above also accepts, but not always the rounded sum).
// Every bound above counts on round-to-nearest and gradual underflow: each function here
// computes in the default floating-point environment whatever the caller's
// (detail/fp_env.hpp), as the certified and conservative queries do.
#pragma once

#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/fp_env.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/normal.hpp>
#include <rayproof/types.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>

namespace rayproof {

template <class T> struct SurfacePoint {
    Vec3<T> p = Vec3<T>::Zero();      // the point
    Vec3<T> error = Vec3<T>::Zero();  // |p_i - x_i| <= error_i for a point x on the surface
    Vec3<T> n = Vec3<T>::Zero();      // the unit normal there (zero: no surface point)
};

namespace detail {

template <class T> inline constexpr T eta_v = std::numeric_limits<T>::min();

// fl(x·(1 + 2(k+1)u)) for x >= 0 computed with k roundings of non-negative terms: at
// least the exact value (header comment). The factor is a float: 2(k+1) < 2^(p-1).
template <class T> [[nodiscard]] T round_up(T x, int k) noexcept {
    return x * (T(1) + T(2 * (k + 1)) * unit_roundoff<T>);
}

template <class T> [[nodiscard]] SurfacePoint<T> no_surface_point(const Vec3<T>& p) noexcept {
    SurfacePoint<T> sp;
    sp.p = p;
    sp.error = Vec3<T>::Constant(std::numeric_limits<T>::infinity());
    sp.n = Vec3<T>::Zero();
    return sp;
}

template <class T> [[nodiscard]] bool finite_vec(const Vec3<T>& v) noexcept {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

// The point of the ray at t, p_i = fl(o_i + fl(t·d_i)), as every shape starts from it.
template <class T> [[nodiscard]] Vec3<T> ray_point(const Ray<T>& r, T t) noexcept {
    Vec3<T> p;
    for (int i = 0; i < 3; ++i) p[i] = r.origin[i] + t * r.direction[i];
    return p;
}

// A point p off a plane a·x = h (a != 0), given a bound G on |a·p - h|: the plane point
// x = p - ((a·p - h)/a_k)·e_k, k the axis of the largest |a_k|, differs from p in
// coordinate k alone, by |a·p - h|/|a_k| <= G/|a_k|. Rounded up: fl(G/|a_k|) is at least
// (G/|a_k|)(1 - u), or G/|a_k| less half the smallest subnormal d when it falls into the
// subnormal range; round_up covers the first, the added d the second (an addition in
// the subnormal range is exact, and one to a normal number cannot fall below it).
template <class T> [[nodiscard]] Vec3<T> residual_error(const Vec3<T>& a, T G) noexcept {
    Eigen::Index k = 0;
    a.cwiseAbs().maxCoeff(&k);
    Vec3<T> e = Vec3<T>::Zero();
    e[k] = round_up(G / std::abs(a[k]), 1) + std::numeric_limits<T>::denorm_min();
    return e;
}

// The bound G on |a·p - h| from its computed value g = fl(fl(fl(a_0 p'_0 + a_1 p'_1) +
// a_2 p'_2) - h): three products and three sums, each term at most five roundings from
// its exact value (Higham, ASNA, 3.1, with h as a fourth term), so |g - (a·p' - h)| <=
// gamma(5)·(Σ|a_j p'_j| + |h|) measured on the exact terms, <= gamma(6)·S with S the
// same sum of the computed |products| (each within u of its exact one), plus three
// half subnormals for products in the subnormal range. G = |g| + that, rounded up:
// S takes three roundings, gamma(6)·S one more, the sum with |g| and eta two more.
// p' is p itself (plane) or fl(p - c) (Obb); for the Obb, fl(p_j - c_j) is within u of
// p_j - c_j, one more rounding per term: gamma(7) replaces gamma(6).
template <class T> [[nodiscard]] T residual_bound(T g, T S, int roundings) noexcept {
    return round_up((std::abs(g) + gamma<T>(roundings) * S) + eta_v<T>, 6);
}

}  // namespace detail

namespace detail {

// Aabb: p is the ray's point with the face's coordinate set to the face's lo or hi and
// the other two clamped into the face's rectangle: p lies exactly on the face, x = p and
// the error is 0 (exact operations only).
template <class T>
[[nodiscard]] SurfacePoint<T> surface_point_body(const Ray<T>& r, const Aabb<T>& b, const Hit<T>& h) noexcept {
    Vec3<T> p = detail::ray_point(r, h.t_enter);
    if (h.verdict != Verdict::hit || h.face < 0 || h.face > 5) return detail::no_surface_point(p);
    const int axis = h.face / 2;
    p[axis] = (h.face % 2) ? b.hi[axis] : b.lo[axis];
    for (int j = 0; j < 3; ++j)
        if (j != axis) p[j] = std::clamp(p[j], b.lo[j], b.hi[j]);
    if (!detail::finite_vec(p)) return detail::no_surface_point(p);
    SurfacePoint<T> sp;
    sp.p = p;
    sp.error = Vec3<T>::Zero();
    sp.n = normal(b, h, r);
    return sp;
}

// Obb: p is the ray's point; with a the face's column and h = ±half_extent, the face's
// plane is a·(x - c) = h, and the bound comes a posteriori from the residual
// g = fl(a·fl(p - c) - h) (detail::residual_bound, gamma(7)).
template <class T>
[[nodiscard]] SurfacePoint<T> surface_point_body(const Ray<T>& r, const Obb<T>& b, const Hit<T>& h) noexcept {
    const Vec3<T> p = detail::ray_point(r, h.t_enter);
    if (h.verdict != Verdict::hit || h.face < 0 || h.face > 5) return detail::no_surface_point(p);
    const int axis = h.face / 2;
    const Vec3<T> a = b.axes.col(axis);
    const T hh = (h.face % 2) ? b.half_extent[axis] : -b.half_extent[axis];
    const Vec3<T> pc = p - b.center;
    const T g = ((a[0] * pc[0] + a[1] * pc[1]) + a[2] * pc[2]) - hh;
    const T S = ((std::abs(a[0] * pc[0]) + std::abs(a[1] * pc[1])) + std::abs(a[2] * pc[2])) + std::abs(hh);
    SurfacePoint<T> sp;
    sp.p = p;
    sp.error = detail::residual_error(a, detail::residual_bound(g, S, 7));
    sp.n = normal(b, h, r);
    if (!detail::finite_vec(sp.error) || !detail::finite_vec(p)) return detail::no_surface_point(p);
    return sp;
}

// Plane: p is the ray's point; the bound comes a posteriori from the residual
// g = fl(n·p - offset) (detail::residual_bound, gamma(6)).
template <class T>
[[nodiscard]] SurfacePoint<T> surface_point_body(const Ray<T>& r, const Plane<T>& pl, const Hit<T>& h) noexcept {
    const Vec3<T> p = detail::ray_point(r, h.t_enter);
    if (h.verdict != Verdict::hit) return detail::no_surface_point(p);
    const Vec3<T>& a = pl.normal;
    const T g = ((a[0] * p[0] + a[1] * p[1]) + a[2] * p[2]) - pl.offset;
    const T S = ((std::abs(a[0] * p[0]) + std::abs(a[1] * p[1])) + std::abs(a[2] * p[2])) + std::abs(pl.offset);
    SurfacePoint<T> sp;
    sp.p = p;
    sp.error = detail::residual_error(a, detail::residual_bound(g, S, 6));
    sp.n = normal(pl, h, r);
    if (!detail::finite_vec(sp.error) || !detail::finite_vec(p)) return detail::no_surface_point(p);
    return sp;
}

// ConvexPolyhedron: the plane's surface point on the entry plane planes[face] (the same
// point and bound), with the polyhedron's outward normal (normal.hpp).
template <class T>
[[nodiscard]] SurfacePoint<T> surface_point_body(const Ray<T>& r, const ConvexPolyhedron<T>& poly,
                                                 const Hit<T>& h) noexcept {
    if (h.verdict != Verdict::hit || h.face < 0 || std::size_t(h.face) >= poly.planes.size())
        return detail::no_surface_point(detail::ray_point(r, h.t_enter));
    SurfacePoint<T> sp = surface_point_body(r, poly.planes[std::size_t(h.face)], h);
    if (!sp.n.isZero()) sp.n = normal(poly, h, r);
    return sp;
}

// Sphere: the ray's point p0 projected radially onto the sphere (pbrt-v4 6.8.5). With
// v = fl(p0 - c) (v = -d when p0 rounds onto the centre) scaled exactly by a power of two
// to vs, its largest component in [1/2, 1) (a component scaled into the subnormal range
// loses bits, which does not matter: the derivation takes vs as computed), the exact
// x = c + r·vs/|vs| lies on the sphere, and p is computed as s = fl(Σ vs_j²) (gamma(3)
// relative; squares below 2^-1022 are far below u·s >= u/4), l = fl(sqrt(s)), w_i =
// fl(fl(vs_i/l)·r), p_i = fl(c_i + w_i). w_i is within gamma(5)·|r·vs_i/|vs|| of
// r·vs_i/|vs| (1.5 + 1 + 1 + 1 roundings), plus r·2^-1075 and 2^-1075 where the
// quotient or the product falls into the subnormal range. So |p_i - x_i| <= u|c_i + w_i|
// + gamma(5)/(1 - gamma(5))·|w_i| + (r + 1)·2^-1075·(1 + u) <= gamma(7)·(|c_i| + |w_i|) +
// eta·(r + 2); computed with five roundings, rounded up. A point sphere (r = 0) is its
// centre: p = c, error 0. n is vs/l made unit (detail::unit_vector, normal.hpp), not w,
// which can be subnormal for a tiny sphere.
template <class T>
[[nodiscard]] SurfacePoint<T> surface_point_body(const Ray<T>& r, const Sphere<T>& s, const Hit<T>& h) noexcept {
    const Vec3<T> p0 = detail::ray_point(r, h.t_enter);
    if (h.verdict != Verdict::hit) return detail::no_surface_point(p0);
    SurfacePoint<T> sp;
    if (s.radius == 0) {
        sp.p = s.center;
        sp.error = Vec3<T>::Zero();
        sp.n = detail::unit_vector<T>(-r.direction);
        return sp;
    }
    Vec3<T> v = p0 - s.center;
    T m = v.cwiseAbs().maxCoeff();
    if (!(m > 0) || !std::isfinite(m)) {
        v = -r.direction;
        m = v.cwiseAbs().maxCoeff();
    }
    int e = 0;
    (void)std::frexp(m, &e);
    Vec3<T> vs;
    for (int i = 0; i < 3; ++i) vs[i] = std::ldexp(v[i], -e);
    const T l = std::sqrt((vs[0] * vs[0] + vs[1] * vs[1]) + vs[2] * vs[2]);
    Vec3<T> q, w;
    for (int i = 0; i < 3; ++i) {
        q[i] = vs[i] / l;
        w[i] = q[i] * s.radius;
    }
    sp.p = s.center + w;
    const T floor = detail::eta_v<T> * (s.radius + T(2));
    for (int i = 0; i < 3; ++i)
        sp.error[i] = detail::round_up(detail::gamma<T>(7) * (std::abs(s.center[i]) + std::abs(w[i])) + floor, 5);
    sp.n = detail::unit_vector(q);
    if (!detail::finite_vec(sp.p) || !detail::finite_vec(sp.error) || !detail::finite_vec(sp.n) || sp.n.isZero())
        return detail::no_surface_point(p0);
    return sp;
}

// The distance to move p along n so that the whole error box lies behind: Σ|n_i|·error_i
// times (1 + 64u), and at least the floor 2^p·eta (header comment); +inf without a
// surface point.
template <class T> [[nodiscard]] T spawn_offset_body(const SurfacePoint<T>& sp) noexcept {
    if (sp.n.isZero()) return std::numeric_limits<T>::infinity();
    constexpr T floor = detail::eta_v<T> * (T(2) / std::numeric_limits<T>::epsilon());  // 2^p·eta
    const T sum = (std::abs(sp.n[0]) * sp.error[0] + std::abs(sp.n[1]) * sp.error[1]) + std::abs(sp.n[2]) * sp.error[2];
    return std::max(sum * (T(1) + T(64) * detail::unit_roundoff<T>), floor);
}

// p moved by at least (1 - u)·dist along n: q_i = fl(p_i + fl(dist·n_i)), then one float
// further in the direction of n_i (coordinates with n_i == 0 stay), so (q - p)_i·n_i >
// (1 - u)·dist·n_i² (header comment).
template <class T> [[nodiscard]] Vec3<T> offset_origin_body(const Vec3<T>& p, const Vec3<T>& n, T dist) noexcept {
    Vec3<T> q;
    for (int i = 0; i < 3; ++i) {
        q[i] = p[i] + detail::rounded(dist * n[i]);
        if (n[i] > 0)
            q[i] = detail::step_up(q[i]);
        else if (n[i] < 0)
            q[i] = detail::step_down(q[i]);
    }
    return q;
}


}  // namespace detail

// ---- The public forms: each body above, in the default floating-point environment.

template <class T, class Shape>
    requires is_shape_v<Shape, T>
[[nodiscard]] SurfacePoint<T> surface_point(const Ray<T>& r, const Shape& s, const Hit<T>& h) noexcept {
    return detail::in_default_fp_env(
        [](const Ray<T>& ray, const Shape& shape, const Hit<T>& hit) noexcept {
            return detail::surface_point_body(ray, shape, hit);
        },
        r, s, h);
}

template <class T> [[nodiscard]] T spawn_offset(const SurfacePoint<T>& sp) noexcept {
    return detail::in_default_fp_env([](const SurfacePoint<T>& p) noexcept { return detail::spawn_offset_body(p); }, sp);
}

template <class T> [[nodiscard]] Vec3<T> offset_origin(const Vec3<T>& p, const Vec3<T>& n, T dist) noexcept {
    return detail::in_default_fp_env(
        [](const Vec3<T>& point, const Vec3<T>& dir, const T& d) noexcept { return detail::offset_origin_body(point, dir, d); },
        p, n, dist);
}

// The origin of a secondary ray leaving sp: side > 0 on the side n faces, side < 0 on
// the other (header comment for what is promised). Not finite without a surface point.
template <class T> [[nodiscard]] Vec3<T> spawn_origin(const SurfacePoint<T>& sp, int side) noexcept {
    return detail::in_default_fp_env(
        [](const SurfacePoint<T>& p, const int& sd) noexcept {
            return detail::offset_origin_body(p.p, sd > 0 ? Vec3<T>(p.n) : Vec3<T>(-p.n), detail::spawn_offset_body(p));
        },
        sp, side);
}

}  // namespace rayproof
