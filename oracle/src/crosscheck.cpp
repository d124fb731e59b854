// crosscheck.cpp — CGAL's exact geometric predicates on the same inputs as the oracle, as
// an independent check of the oracle in its tests (see crosscheck.hpp).
//
// CGAL facts this relies on (CGAL 5.5): do_intersect of a Ray_3 or Line_3 with a
// Sphere_3 compares the squared distance to the squared radius (ball semantics), but
// Segment_3/Sphere_3 and Point_3/Sphere_3 test the surface only, so segments and points
// are decided here with bounded_side first. Segment/Ray/Line vs Tetrahedron_3 and
// Iso_cuboid_3 are solid.
#include "exact_number.hpp"

#include <rayproof/oracle/crosscheck.hpp>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/intersections.h>

#include <array>
#include <cmath>

namespace rayproof::oracle::crosscheck {

namespace {

using K = CGAL::Simple_cartesian<Q>;
using P3 = K::Point_3;
using V3 = K::Vector_3;
using Seg = K::Segment_3;
using Ray3 = K::Ray_3;
using Line = K::Line_3;
using internal::to_q;

template <class T> P3 point(const Vec3<T>& v) { return P3{to_q(v[0]), to_q(v[1]), to_q(v[2])}; }
template <class T> V3 vec(const Vec3<T>& v) { return V3{to_q(v[0]), to_q(v[1]), to_q(v[2])}; }

// The ray's parameter range as a CGAL object: a point (t_min == t_max), a segment, a ray
// (one infinite end) or a line; f is called with it.
template <class T, class F> auto with_range(const Ray<T>& r, F&& f) {
    const P3 o = point(r.origin);
    const V3 d = vec(r.direction);
    const bool lo_inf = std::isinf(r.t_min), hi_inf = std::isinf(r.t_max);
    if (!lo_inf && !hi_inf) {
        const P3 a = o + d * to_q(r.t_min);
        if (r.t_min == r.t_max) return f(a);
        const P3 b = o + d * to_q(r.t_max);
        return f(Seg{a, b});
    }
    if (!lo_inf) return f(Ray3{o + d * to_q(r.t_min), d});
    if (!hi_inf) return f(Ray3{o + d * to_q(r.t_max), -d});
    return f(Line{o, d});
}

// t of a point on the ray's line: (p - o)·d / (d·d).
template <class T> Q t_of(const Ray<T>& r, const P3& p) {
    const V3 d = vec(r.direction);
    const Q num = (p - point(r.origin)) * d;
    const Q den = d * d;
    return num / den;
}

Verdict as_verdict(bool b) { return b ? Verdict::hit : Verdict::miss; }

}  // namespace

template <class T> std::optional<Verdict> verdict(const Ray<T>& ray, const Aabb<T>& box) {
    if (!oracle::valid(ray) || !oracle::valid(box)) return std::nullopt;
    const K::Iso_cuboid_3 cub{point(box.lo), point(box.hi)};
    return with_range(ray, [&](const auto& obj) { return as_verdict(CGAL::do_intersect(obj, cub)); });
}

template <class T> std::optional<Verdict> verdict(const Ray<T>& ray, const Plane<T>& plane) {
    if (!oracle::valid(ray) || !oracle::valid(plane)) return std::nullopt;
    const K::Plane_3 pl{to_q(plane.normal[0]), to_q(plane.normal[1]), to_q(plane.normal[2]), Q{-to_q(plane.offset)}};
    return with_range(ray, [&](const auto& obj) { return as_verdict(CGAL::do_intersect(obj, pl)); });
}

template <class T> std::optional<Verdict> verdict(const Ray<T>& ray, const Sphere<T>& sphere) {
    if (!oracle::valid(ray) || !oracle::valid(sphere)) return std::nullopt;
    const Q r = to_q(sphere.radius);
    const K::Sphere_3 sp{point(sphere.center), Q{r * r}};
    const auto in_ball = [&](const P3& p) { return sp.bounded_side(p) != CGAL::ON_UNBOUNDED_SIDE; };
    return with_range(ray, [&](const auto& obj) {
        using O = std::decay_t<decltype(obj)>;
        if constexpr (std::is_same_v<O, P3>)
            return as_verdict(in_ball(obj));
        else if constexpr (std::is_same_v<O, Seg>)
            return as_verdict(in_ball(obj.source()) || in_ball(obj.target()) || CGAL::do_intersect(obj, sp));
        else
            return as_verdict(CGAL::do_intersect(obj, sp));
    });
}

template <class T> std::optional<Verdict> verdict(const Ray<T>& ray, const Obb<T>& box) {
    if (!oracle::valid(ray) || !oracle::valid(box)) return std::nullopt;
    if (box.half_extent[0] == 0 || box.half_extent[1] == 0 || box.half_extent[2] == 0) return std::nullopt;
    // Corners c + M·(s∘h) with M = A^-T (A the stored axes as columns, s in {-1, 1}³), so
    // that (corner - c)·a_i = s_i·h_i exactly.
    std::array<std::array<Q, 3>, 3> a;  // a[i][k]: component k of axis i
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) a[i][k] = to_q(box.axes(k, i));
    // A^-T = cof(A)/det(A) where rows of A^T are the axes: the dual basis b_i with
    // b_i·a_j = δ_ij is b_0 = (a_1 × a_2)/det, etc.
    const auto cross = [](const std::array<Q, 3>& u, const std::array<Q, 3>& v) {
        return std::array<Q, 3>{Q{u[1] * v[2] - u[2] * v[1]}, Q{u[2] * v[0] - u[0] * v[2]}, Q{u[0] * v[1] - u[1] * v[0]}};
    };
    const std::array<std::array<Q, 3>, 3> cr = {cross(a[1], a[2]), cross(a[2], a[0]), cross(a[0], a[1])};
    const Q det = a[0][0] * cr[0][0] + a[0][1] * cr[0][1] + a[0][2] * cr[0][2];
    const P3 c = point(box.center);
    std::array<P3, 8> corner;
    for (int m = 0; m < 8; ++m) {
        Q off[3] = {Q{0}, Q{0}, Q{0}};
        for (int i = 0; i < 3; ++i) {
            const Q h = to_q(box.half_extent[i]);
            const Q sh = (m >> i & 1) ? h : Q{-h};
            for (int k = 0; k < 3; ++k) off[k] += sh * cr[i][k] / det;
        }
        corner[m] = P3{c.x() + off[0], c.y() + off[1], c.z() + off[2]};
    }
    // Kuhn triangulation: one tetrahedron per permutation of the axes.
    static constexpr int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    bool any = false;
    for (const auto& p : perms) {
        const int v1 = 1 << p[0], v2 = v1 | (1 << p[1]);
        const K::Tetrahedron_3 tet{corner[0], corner[v1], corner[v2], corner[7]};
        any = with_range(ray, [&](const auto& obj) {
            using O = std::decay_t<decltype(obj)>;
            if constexpr (std::is_same_v<O, P3>)
                return !tet.has_on_unbounded_side(obj);
            else
                return bool(CGAL::do_intersect(obj, tet));
        });
        if (any) break;
    }
    return as_verdict(any);
}

template <class T> std::optional<Interval> interval(const Ray<T>& ray, const Aabb<T>& box) {
    if (!oracle::valid(ray) || !oracle::valid(box)) return std::nullopt;
    const K::Iso_cuboid_3 cub{point(box.lo), point(box.hi)};
    return with_range(ray, [&](const auto& obj) -> std::optional<Interval> {
        using O = std::decay_t<decltype(obj)>;
        if constexpr (std::is_same_v<O, P3>) {
            if (cub.has_on_unbounded_side(obj)) return std::nullopt;
            const ExactValue t = internal::make_rational(to_q(ray.t_min));
            return Interval{t, t};
        } else {
            const auto res = CGAL::intersection(obj, cub);
            if (!res) return std::nullopt;
            Q t0, t1;
            if (const P3* p = boost::get<P3>(&*res)) {
                t0 = t1 = t_of(ray, *p);
            } else {
                const Seg& s = boost::get<Seg>(*res);
                t0 = t_of(ray, s.source());
                t1 = t_of(ray, s.target());
                if (t1 < t0) std::swap(t0, t1);
            }
            return Interval{internal::make_rational(t0), internal::make_rational(t1)};
        }
    });
}

template <class T> std::optional<Interval> interval(const Ray<T>& ray, const Plane<T>& plane) {
    if (!oracle::valid(ray) || !oracle::valid(plane)) return std::nullopt;
    const K::Plane_3 pl{to_q(plane.normal[0]), to_q(plane.normal[1]), to_q(plane.normal[2]), Q{-to_q(plane.offset)}};
    const auto whole = [&]() {
        const auto end = [](T t) {
            return std::isinf(t) ? internal::make_infinite(t < 0 ? -1 : 1) : internal::make_rational(to_q(t));
        };
        return Interval{end(ray.t_min), end(ray.t_max)};
    };
    return with_range(ray, [&](const auto& obj) -> std::optional<Interval> {
        using O = std::decay_t<decltype(obj)>;
        if constexpr (std::is_same_v<O, P3>) {
            if (!pl.has_on(obj)) return std::nullopt;
            return whole();
        } else {
            const auto res = CGAL::intersection(obj, pl);
            if (!res) return std::nullopt;
            if (const P3* p = boost::get<P3>(&*res)) {
                const ExactValue t = internal::make_rational(t_of(ray, *p));
                return Interval{t, t};
            }
            return whole();  // the range lies in the plane
        }
    });
}

#define RAYPROOF_CROSSCHECK_INSTANTIATE(T)                                                   \
    template std::optional<Verdict> verdict<T>(const Ray<T>&, const Aabb<T>&);               \
    template std::optional<Verdict> verdict<T>(const Ray<T>&, const Obb<T>&);                \
    template std::optional<Verdict> verdict<T>(const Ray<T>&, const Plane<T>&);              \
    template std::optional<Verdict> verdict<T>(const Ray<T>&, const Sphere<T>&);             \
    template std::optional<Interval> interval<T>(const Ray<T>&, const Aabb<T>&);             \
    template std::optional<Interval> interval<T>(const Ray<T>&, const Plane<T>&);
RAYPROOF_CROSSCHECK_INSTANTIATE(float)
RAYPROOF_CROSSCHECK_INSTANTIATE(double)
#undef RAYPROOF_CROSSCHECK_INSTANTIATE

}  // namespace rayproof::oracle::crosscheck
