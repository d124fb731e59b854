// crosscheck.cpp — CGAL's exact geometric predicates, constructions and algebraic numbers
// on the same inputs as the oracle, as an independent check of the oracle (and, through
// it, of the kernel) in the tests (see crosscheck.hpp).
//
// CGAL facts this relies on (CGAL 5.5): do_intersect of a Ray_3 or Line_3 with a
// Sphere_3 compares the squared distance to the squared radius (ball semantics), but
// Segment_3/Sphere_3 and Point_3/Sphere_3 test the surface only, so segments and points
// are decided here with bounded_side first. Segment/Ray/Line vs Tetrahedron_3 and
// Iso_cuboid_3 are solid.
#include "exact_number.hpp"

#include <rayproof/oracle/crosscheck.hpp>

#include <CGAL/Aff_transformation_3.h>
#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>
#include <CGAL/Root_of_traits.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/intersections.h>

#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

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

// CGAL's number for a root of a quadratic with rational coefficients: a0 + a1·sqrt(root).
using Root2 = CGAL::Root_of_traits<Q>::Root_of_2;

// The oracle's representation of a Root_of_2 (for comparing answers with operator==):
// a0 + a1·sqrt(root) = a0 + sign(a1)·sqrt(a1²·root); make_root reduces perfect squares.
ExactValue value_of(const Root2& x) {
    if (!x.is_extended() || CGAL::sign(x.a1()) == CGAL::ZERO) return internal::make_rational(x.a0());
    const Q r = x.a1() * x.a1() * x.root();
    return internal::make_root(x.a0(), r, CGAL::sign(x.a1()) == CGAL::POSITIVE ? 1 : -1);
}

template <class T> ExactValue value_of(T t) {
    return std::isinf(t) ? internal::make_infinite(t < 0 ? -1 : 1) : internal::make_rational(to_q(t));
}

template <class T> Exact<T> invalid_answer() {
    Exact<T> e;
    e.verdict = Verdict::invalid;
    return e;
}

// One face of a box: its plane in world coordinates and the inward normal.
struct FacePlane {
    K::Plane_3 plane;
    V3 inward;
};
// The contract's entry face of a ray that enters the box at world point p: the first
// plane in face order that holds p and that the direction enters through.
int entry_face(const std::array<FacePlane, 6>& faces, const P3& p, const V3& d) {
    for (int f = 0; f < 6; ++f)
        if (faces[f].plane.has_on(p) && CGAL::sign(faces[f].inward * d) == CGAL::POSITIVE) return f;
    return 6;
}

// The answer for a box that is the Iso_cuboid_3 `cub` in the frame reached by `to_frame`
// (from world coordinates; `to_world` maps back), with faces `faces` in world coordinates.
template <class T, class ToFrame, class ToWorld>
Exact<T> box_answer(const Ray<T>& ray, const K::Iso_cuboid_3& cub, ToFrame to_frame, ToWorld to_world,
                    const std::array<FacePlane, 6>& faces) {
    Exact<T> e;
    const P3 o = point(ray.origin);
    const V3 d = vec(ray.direction);
    const bool t_min_inside = std::isfinite(ray.t_min) && !cub.has_on_unbounded_side(to_frame(o + d * to_q(ray.t_min)));
    const auto hit = [&](const P3& entry, const Q& t0, const Q& t1) {
        e.verdict = Verdict::hit;
        e.t_enter = internal::make_rational(t0);
        e.t_exit = internal::make_rational(t1);
        e.face = t_min_inside ? -1 : entry_face(faces, entry, d);
        return e;
    };
    return with_range(ray, [&](const auto& obj) -> Exact<T> {
        using O = std::decay_t<decltype(obj)>;
        if constexpr (std::is_same_v<O, P3>) {
            if (!t_min_inside) return e;
            const Q t = to_q(ray.t_min);
            return hit(obj, t, t);
        } else {
            const auto res = CGAL::intersection(to_frame(obj), cub);
            if (!res) return e;
            if (const P3* p = boost::get<P3>(&*res)) {
                const P3 w = to_world(*p);
                const Q t = t_of(ray, w);
                return hit(w, t, t);
            }
            const Seg& s = boost::get<Seg>(*res);
            P3 a = to_world(s.source()), b = to_world(s.target());
            Q ta = t_of(ray, a), tb = t_of(ray, b);
            if (tb < ta) {
                std::swap(a, b);
                std::swap(ta, tb);
            }
            return hit(a, ta, tb);
        }
    });
}

template <class F> Order order_of(F f, const ExactValue& v) {
    using Kind = ExactValue::Kind;
    constexpr F inf = std::numeric_limits<F>::infinity();
    if (!v.has_value() || std::isnan(f)) return Order::unordered;
    if (v.kind() == Kind::minus_infinity) return f == -inf ? Order::equal : Order::above;
    if (v.kind() == Kind::plus_infinity) return f == inf ? Order::equal : Order::below;
    if (std::isinf(f)) return f < 0 ? Order::below : Order::above;
    const Q x = to_q(f);
    const ExactValue::Impl& im = *v.impl();
    CGAL::Comparison_result c;
    if (v.kind() == Kind::rational) {
        c = CGAL::compare(x, im.p);
    } else {
        const Root2 w(im.p, Q(im.sigma), im.r);
        c = CGAL::opposite(w.compare(x));
    }
    return c == CGAL::SMALLER ? Order::below : c == CGAL::LARGER ? Order::above : Order::equal;
}

}  // namespace

Order compare(float f, const ExactValue& v) { return order_of(f, v); }
Order compare(double f, const ExactValue& v) { return order_of(f, v); }

Order compare(const ExactValue& a, const ExactValue& b) {
    using Kind = ExactValue::Kind;
    if (!a.has_value() || !b.has_value()) return Order::unordered;
    // The infinities by rank: -inf < every finite value < +inf.
    const auto rank = [](Kind k) { return k == Kind::minus_infinity ? -1 : k == Kind::plus_infinity ? 1 : 0; };
    const int ra = rank(a.kind()), rb = rank(b.kind());
    if (ra != rb || ra != 0) return ra < rb ? Order::below : ra > rb ? Order::above : Order::equal;
    // Two finite values as CGAL Root_of_2 numbers, compared across extensions.
    const auto root = [](const ExactValue::Impl& im) {
        return im.kind == Kind::rational ? Root2(im.p) : Root2(im.p, Q(im.sigma), im.r);
    };
    const CGAL::Comparison_result c = CGAL::compare(root(*a.impl()), root(*b.impl()));
    return c == CGAL::SMALLER ? Order::below : c == CGAL::LARGER ? Order::above : Order::equal;
}

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

template <class T> Exact<T> answer(const Ray<T>& ray, const Aabb<T>& box) {
    if (!oracle::valid(ray) || !oracle::valid(box)) return invalid_answer<T>();
    std::array<FacePlane, 6> faces;
    for (int i = 0; i < 3; ++i) {
        Q n[3] = {Q{0}, Q{0}, Q{0}};
        n[i] = 1;
        const V3 e{n[0], n[1], n[2]};
        faces[2 * i] = {K::Plane_3{n[0], n[1], n[2], Q{-to_q(box.lo[i])}}, e};
        faces[2 * i + 1] = {K::Plane_3{n[0], n[1], n[2], Q{-to_q(box.hi[i])}}, -e};
    }
    const auto same = [](const auto& x) { return x; };
    return box_answer(ray, K::Iso_cuboid_3{point(box.lo), point(box.hi)}, same, same, faces);
}

template <class T> Exact<T> answer(const Ray<T>& ray, const Obb<T>& box) {
    if (!oracle::valid(ray) || !oracle::valid(box)) return invalid_answer<T>();
    const P3 c = point(box.center);
    std::array<V3, 3> a;
    std::array<Q, 3> ac;  // a_i·c
    for (int i = 0; i < 3; ++i) {
        a[i] = vec(Vec3<T>(box.axes.col(i)));
        ac[i] = a[i] * (c - CGAL::ORIGIN);
    }
    // The box frame: p'_i = a_i·p - a_i·c = (p - c)·a_i, where the box is |p'_i| <= h_i.
    const K::Aff_transformation_3 to_box{a[0].x(), a[0].y(), a[0].z(), Q{-ac[0]},  //
                                         a[1].x(), a[1].y(), a[1].z(), Q{-ac[1]},  //
                                         a[2].x(), a[2].y(), a[2].z(), Q{-ac[2]}};
    const K::Aff_transformation_3 to_world = to_box.inverse();
    std::array<FacePlane, 6> faces;
    P3 lo, hi;
    {
        Q l[3], u[3];
        for (int i = 0; i < 3; ++i) {
            const Q h = to_q(box.half_extent[i]);
            // side 0: a_i·p = a_i·c - h_i (inward +a_i); side 1: a_i·p = a_i·c + h_i (inward -a_i).
            faces[2 * i] = {K::Plane_3{a[i].x(), a[i].y(), a[i].z(), Q{h - ac[i]}}, a[i]};
            faces[2 * i + 1] = {K::Plane_3{a[i].x(), a[i].y(), a[i].z(), Q{Q{-h} - ac[i]}}, -a[i]};
            l[i] = -h;
            u[i] = h;
        }
        lo = P3{l[0], l[1], l[2]};
        hi = P3{u[0], u[1], u[2]};
    }
    return box_answer(
        ray, K::Iso_cuboid_3{lo, hi}, [&](const auto& x) { return x.transform(to_box); },
        [&](const P3& p) { return p.transform(to_world); }, faces);
}

template <class T> Exact<T> answer(const Ray<T>& ray, const Plane<T>& plane) {
    if (!oracle::valid(ray) || !oracle::valid(plane)) return invalid_answer<T>();
    Exact<T> e;
    const auto iv = interval(ray, plane);
    if (!iv) return e;
    e.verdict = Verdict::hit;
    e.t_enter = iv->t_enter;
    e.t_exit = iv->t_exit;
    return e;
}

template <class T> Exact<T> answer(const Ray<T>& ray, const Sphere<T>& sphere) {
    const auto v = verdict(ray, sphere);
    if (!v) return invalid_answer<T>();
    Exact<T> e;
    if (*v != Verdict::hit) return e;
    e.verdict = Verdict::hit;
    const P3 o = point(ray.origin), c = point(sphere.center);
    const V3 d = vec(ray.direction), delta = o - c;
    const Q r = to_q(sphere.radius);
    const K::Sphere_3 sp{c, Q{r * r}};
    const auto in_ball = [&](T t) {
        return std::isfinite(t) && sp.bounded_side(o + d * to_q(t)) != CGAL::ON_UNBOUNDED_SIDE;
    };
    // |o + t·d - c|² = r²: (d·d)·t² + 2(d·Δ)·t + (Δ·Δ - r²) = 0, two real roots on a hit
    // (the line meets the ball); none are made when that fails, so the answer disagrees.
    const Q qa = d * d, qb = Q{2} * (d * delta), qc = Q{delta * delta - r * r};
    if (CGAL::sign(Q{qb * qb - Q{4} * qa * qc}) == CGAL::NEGATIVE) return e;
    e.t_enter = in_ball(ray.t_min) ? value_of(ray.t_min) : value_of(CGAL::make_root_of_2(qa, qb, qc, true));
    e.t_exit = in_ball(ray.t_max) ? value_of(ray.t_max) : value_of(CGAL::make_root_of_2(qa, qb, qc, false));
    return e;
}

namespace {

// An extreme t of the polyhedron's points on the ray's range, by linear programming over
// the point and its parameter: variables (p_0, p_1, p_2, t), free but for t_min <= t <=
// t_max where those are finite; p - t·d = o; n_k·p <= offset_k for every plane; the
// objective t (`sense` +1: its minimum) or -t (-1: its maximum). CGAL's exact simplex
// (QP_solver) over Gmpq decides it: nullopt when infeasible (a miss), ±inf when
// unbounded, else the optimum.
template <class T> std::optional<ExactValue> lp_extreme(const Ray<T>& ray, const ConvexPolyhedron<T>& poly, int sense) {
    CGAL::Quadratic_program<Q> lp(CGAL::SMALLER, false, Q{0}, false, Q{0});
    for (int i = 0; i < 3; ++i) {
        lp.set_a(i, i, Q{1});
        lp.set_a(3, i, Q{-to_q(ray.direction[i])});
        lp.set_b(i, to_q(ray.origin[i]));
        lp.set_r(i, CGAL::EQUAL);
    }
    for (std::size_t k = 0; k < poly.planes.size(); ++k) {
        const int row = 3 + int(k);
        for (int i = 0; i < 3; ++i) lp.set_a(i, row, to_q(poly.planes[k].normal[i]));
        lp.set_b(row, to_q(poly.planes[k].offset));
        lp.set_r(row, CGAL::SMALLER);
    }
    if (std::isfinite(ray.t_min)) lp.set_l(3, true, to_q(ray.t_min));
    if (std::isfinite(ray.t_max)) lp.set_u(3, true, to_q(ray.t_max));
    lp.set_c(3, Q{sense});
    const CGAL::Quadratic_program_solution<Q> s = CGAL::solve_linear_program(lp, Q{});
    if (s.is_infeasible()) return std::nullopt;
    if (s.is_unbounded()) return internal::make_infinite(-sense);
    const auto v = s.objective_value();  // a CGAL::Quotient<Q>
    const Q opt = v.numerator() / v.denominator();
    return internal::make_rational(sense > 0 ? opt : Q{-opt});
}

}  // namespace

template <class T> Exact<T> answer(const Ray<T>& ray, const ConvexPolyhedron<T>& poly) {
    if (!oracle::valid(ray) || !oracle::valid(poly)) return invalid_answer<T>();
    Exact<T> e;
    const std::optional<ExactValue> lo = lp_extreme(ray, poly, 1);
    if (!lo) return e;
    const std::optional<ExactValue> hi = lp_extreme(ray, poly, -1);
    if (!hi) return e;  // (never: the two programs have the same feasible set)
    e.verdict = Verdict::hit;
    e.t_enter = *lo;
    e.t_exit = *hi;
    // The face: -1 when t_enter is t_min (or -inf); otherwise the first plane, in index
    // order, that holds the entry point and whose outward normal the direction points
    // against (negative scalar product).
    if (lo->kind() == ExactValue::Kind::rational && !(std::isfinite(ray.t_min) && lo->impl()->p == to_q(ray.t_min))) {
        const P3 entry = point(ray.origin) + vec(ray.direction) * lo->impl()->p;
        const V3 d = vec(ray.direction);
        e.face = int(poly.planes.size());  // no plane qualifies: never, for a consistent answer
        for (std::size_t k = 0; k < poly.planes.size(); ++k) {
            const Plane<T>& pl = poly.planes[k];
            const K::Plane_3 plane{to_q(pl.normal[0]), to_q(pl.normal[1]), to_q(pl.normal[2]), Q{-to_q(pl.offset)}};
            if (plane.has_on(entry) && CGAL::sign(plane.orthogonal_vector() * d) == CGAL::NEGATIVE) {
                e.face = int(k);
                break;
            }
        }
    }
    return e;
}

#define RAYPROOF_CROSSCHECK_INSTANTIATE(T)                                                   \
    template std::optional<Verdict> verdict<T>(const Ray<T>&, const Aabb<T>&);               \
    template std::optional<Verdict> verdict<T>(const Ray<T>&, const Obb<T>&);                \
    template std::optional<Verdict> verdict<T>(const Ray<T>&, const Plane<T>&);              \
    template std::optional<Verdict> verdict<T>(const Ray<T>&, const Sphere<T>&);             \
    template std::optional<Interval> interval<T>(const Ray<T>&, const Aabb<T>&);             \
    template std::optional<Interval> interval<T>(const Ray<T>&, const Plane<T>&);            \
    template Exact<T> answer<T>(const Ray<T>&, const Aabb<T>&);                              \
    template Exact<T> answer<T>(const Ray<T>&, const Obb<T>&);                               \
    template Exact<T> answer<T>(const Ray<T>&, const Plane<T>&);                             \
    template Exact<T> answer<T>(const Ray<T>&, const Sphere<T>&);                            \
    template Exact<T> answer<T>(const Ray<T>&, const ConvexPolyhedron<T>&);
RAYPROOF_CROSSCHECK_INSTANTIATE(float)
RAYPROOF_CROSSCHECK_INSTANTIATE(double)
#undef RAYPROOF_CROSSCHECK_INSTANTIATE

}  // namespace rayproof::oracle::crosscheck
