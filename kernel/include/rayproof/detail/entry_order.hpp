// rayproof/detail/entry_order.hpp — the exact order of two certified entries of one ray.
//
// Question:  for two certified hits ha, hb of the same ray (ha = intersect(ray, a,
//            certified), hb likewise), the sign of e_a − e_b, e_x the EXACT t_enter of
//            primitive x (docs/semantics.md, "Closest hit over many primitives").
// Filter:    a certified t_enter is faithful: the exact value e lies strictly between the
//            float's two neighbours, or equals the float. So e_a < step_up(ta) and
//            e_b > step_down(tb): step_up(ta) <= step_down(tb) proves e_a < e_b from two
//            floats. It answers every pair but equal or adjacent floats.
// Exact:     the rest is decided from the exact entries, each one of
//              at t_min  the point at t_min is in the shape: face == -1 for boxes and
//                        polyhedra; a plane hit with n·d == 0 exactly (the ray lies in it);
//                        a sphere whose entry root is <= t_min (decided exactly: the point
//                        at t_min is in the ball, |o + t_min·d − c|^2 <= r^2, degree 4);
//              quotient  num/den, as the kernel's certified paths form them:
//                          Aabb face 2i+s:  (p − o_i)/d_i, p = lo_i (s = 0) or hi_i (s = 1);
//                          Obb face 2i+s:   (∓h_i − Σ_j a_ji (o_j − c_j)) / Σ_j a_ji d_j
//                                           (−h_i for s = 0; ray_obb.hpp);
//                          polyhedron face k, and a plane crossed:
//                                           (offset − n·o)/(n·d) (ray_polyhedron.hpp);
//              root      the smaller root of a t^2 + 2 b t + c = 0, a = d·d, b = d·(o − c),
//                        c = |o − c|^2 − r^2: (−b − √D)/a with D = b^2 − a c >= 0 (the ball
//                        is hit, exactly), a > 0.
//            Pairs: t_min against a quotient, sign(num − t_min·den)·sign(den) (degree 3); two
//            quotients by cross multiplication (degree 4); anything against a root reduces
//            to the sign of A + B·√D (sign_sqrt: by the signs of A and B, else by A^2 vs
//            B^2·D): t_min − root = (t_min·a + b + √D)/a (degree 6 squared), quotient − root
//            = (num·a + den·b + den·√D)/(a·den) (degree 8 squared for Obb and polyhedra).
//            Two roots of one ray share a: r1 − r2 = (X + √D2 − √D1)/a with X = b2 − b1;
//            the sign of L = X + √D2 first, then, when L > 0, L^2 − D1 = (X^2 + D2 − D1) +
//            2X·√D2 (degree 8 squared). Every value is a polynomial in the inputs with
//            integer coefficients; degree 8 lies beyond BigDyadic's documented capacity
//            (7), so the exact type is Shewchuk's Expansion first (exact unless flagged)
//            and BigDyadic8 (detail/exact.hpp, capacity derived for degree 8) on a flag or
//            outside expansion_safe.
// Degenerate: t_min = −inf (only at t_min entries of unbounded shapes: a polyhedron or a
//            plane containing the whole ray): two such are equal, one is below every finite
//            entry. A t_enter rounded to ±max or ±inf by overflow is still ordered exactly.
// Error bound: none; the answer is exact.
#pragma once

#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/prepared_ray.hpp>
#include <rayproof/ray_polyhedron.hpp>
#include <rayproof/types.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <type_traits>
#include <variant>

namespace rayproof {
// A scene primitive. ConvexPolyhedron does not own its planes: the caller keeps them alive.
template <class T> using Primitive = std::variant<Aabb<T>, Obb<T>, Sphere<T>, ConvexPolyhedron<T>, Plane<T>>;
}  // namespace rayproof

namespace rayproof::detail {

// The float filter: -1 / +1 when the faithful values ta, tb alone order the exact ones,
// 0 when they cannot (equal or adjacent floats).
template <class T> int compare_entry_filter(T ta, T tb) {
    if (step_up(ta) <= step_down(tb)) return -1;
    if (step_up(tb) <= step_down(ta)) return +1;
    return 0;
}

// The sign of A + B·√D, D >= 0, exact. When A and B have opposite signs the sum has the
// sign of A exactly when |A| > |B|·√D, i.e. A^2 > B^2·D.
template <class E> std::optional<int> sign_sqrt(const E& A, const E& B, const E& D) {
    if (any_overflowed(A, B, D)) return std::nullopt;
    const int sa = A.sign(), sb = D.sign() == 0 ? 0 : B.sign();
    if (sb == 0) return sa;
    if (sa == 0 || sa == sb) return sa == 0 ? sb : sa;
    const E s = A * A - B * B * D;
    if (s.overflowed()) return std::nullopt;
    return s.sign() * sa;
}

enum class EntryKind { at_t_min, quotient, root };

// One exact entry: at t_min; num/den; or the root (−b − √D)/a (fields num = b, den = D).
template <class E> struct ExactEntry {
    EntryKind kind = EntryKind::at_t_min;
    E num, den, a;
};

template <class E> using Exact3 = std::array<E, 3>;
template <class E, class T> Exact3<E> exact3(const Vec3<T>& v) { return {E(v[0]), E(v[1]), E(v[2])}; }
template <class E> E dot3(const Exact3<E>& x, const Exact3<E>& y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; }

template <class E, class T> std::optional<ExactEntry<E>> quotient_entry(E num, E den) {
    if (any_overflowed(num, den)) return std::nullopt;
    return ExactEntry<E>{EntryKind::quotient, std::move(num), std::move(den), E()};
}

// The exact entry of a certified hit h of the ray against p (nullopt: an expansion flag).
template <class E, class T>
std::optional<ExactEntry<E>> exact_entry(const Ray<T>& r, const Primitive<T>& p, const Hit<T>& h) {
    using Entry = ExactEntry<E>;
    const Exact3<E> o = exact3<E>(r.origin), d = exact3<E>(r.direction);
    if (const auto* b = std::get_if<Aabb<T>>(&p)) {
        if (h.face < 0) return Entry{};
        const int i = h.face / 2;
        const T bound = h.face % 2 == 0 ? b->lo[i] : b->hi[i];
        return quotient_entry<E, T>(E(bound) - o[i], d[i]);
    }
    if (const auto* b = std::get_if<Obb<T>>(&p)) {
        if (h.face < 0) return Entry{};
        const int i = h.face / 2;
        const E he(b->half_extent[i]);
        E num = h.face % 2 == 0 ? -he : he, den;
        for (int j = 0; j < 3; ++j) {
            const E a(b->axes(j, i));
            num -= a * (o[j] - E(b->center[j]));
            den += a * d[j];
        }
        return quotient_entry<E, T>(num, den);
    }
    if (const auto* c = std::get_if<ConvexPolyhedron<T>>(&p)) {
        if (h.face < 0) return Entry{};
        const Plane<T>& q = c->planes[std::size_t(h.face)];
        const Exact3<E> n = exact3<E>(q.normal);
        return quotient_entry<E, T>(E(q.offset) - dot3(n, o), dot3(n, d));
    }
    if (const auto* q = std::get_if<Plane<T>>(&p)) {
        const Exact3<E> n = exact3<E>(q->normal);
        E den = dot3(n, d);
        if (den.overflowed()) return std::nullopt;
        if (den.sign() == 0) return Entry{};  // the ray lies in the plane: t_enter = t_min
        return quotient_entry<E, T>(E(q->offset) - dot3(n, o), den);
    }
    const Sphere<T>& s = std::get<Sphere<T>>(p);
    const Exact3<E> oc{o[0] - E(s.center[0]), o[1] - E(s.center[1]), o[2] - E(s.center[2])};
    const E rr = E(s.radius) * E(s.radius);
    if (std::isfinite(r.t_min)) {  // the point at t_min in the ball: the entry is t_min
        const E t(r.t_min);
        const Exact3<E> x{oc[0] + t * d[0], oc[1] + t * d[1], oc[2] + t * d[2]};
        const E q = dot3(x, x) - rr;
        if (q.overflowed()) return std::nullopt;
        if (q.sign() <= 0) return Entry{};
    }
    E a = dot3(d, d), b = dot3(d, oc);
    E D = b * b - a * (dot3(oc, oc) - rr);
    if (any_overflowed(a, b, D)) return std::nullopt;
    return Entry{EntryKind::root, std::move(b), std::move(D), std::move(a)};
}

// sign(e_x − e_y) for two exact entries of the ray with lower end t_min.
template <class E, class T>
std::optional<int> compare_exact_entries(const ExactEntry<E>& x, const ExactEntry<E>& y, T t_min) {
    using K = EntryKind;
    if (x.kind == K::at_t_min && y.kind == K::at_t_min) return 0;
    if (y.kind == K::at_t_min) {
        const std::optional<int> s = compare_exact_entries(y, x, t_min);
        if (!s) return std::nullopt;
        return -*s;
    }
    if (x.kind == K::at_t_min) {
        if (!std::isfinite(t_min)) return -1;  // −inf below every finite entry
        if (y.kind == K::quotient) {
            const E s = y.num - E(t_min) * y.den;  // sign(y − t_min) = sign(num − t_min·den)·sign(den)
            if (s.overflowed()) return std::nullopt;
            return -s.sign() * y.den.sign();
        }
        // t_min − root = (t_min·a + b + √D)/a, a > 0.
        return sign_sqrt(E(t_min) * y.a + y.num, E(1.0), y.den);
    }
    if (x.kind == K::quotient && y.kind == K::quotient) {
        const E s = x.num * y.den - y.num * x.den;
        if (s.overflowed()) return std::nullopt;
        return s.sign() * x.den.sign() * y.den.sign();
    }
    if (x.kind == K::root && y.kind == K::quotient) {
        const std::optional<int> s = compare_exact_entries(y, x, t_min);
        if (!s) return std::nullopt;
        return -*s;
    }
    if (x.kind == K::quotient) {  // y a root: (num·a + den·b + den·√D)/(a·den)
        const std::optional<int> s = sign_sqrt(x.num * y.a + x.den * y.num, x.den, y.den);
        if (!s) return std::nullopt;
        return *s * x.den.sign();
    }
    // Two roots, one a: sign(X + √D_y − √D_x) with X = b_y − b_x.
    const E X = y.num - x.num;
    const std::optional<int> l = sign_sqrt(X, E(1.0), y.den);
    if (!l) return std::nullopt;
    if (*l < 0) return -1;
    if (*l == 0) return x.den.sign() > 0 ? -1 : 0;
    // L > 0: sign(L − √D_x) = sign(L^2 − D_x) = sign((X^2 + D_y − D_x) + 2X·√D_y).
    return sign_sqrt(X * X + y.den - x.den, X + X, y.den);
}

// Every input the exact entry of h reads lies in expansion_safe's range.
template <class T> bool entry_expansion_safe(const Primitive<T>& p, const Hit<T>& h) {
    return std::visit(
        [&](const auto& s) -> bool {
            using S = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<S, Aabb<T>>) return expansion_safe(s.lo) && expansion_safe(s.hi);
            else if constexpr (std::is_same_v<S, Obb<T>>)
                return expansion_safe(s.center) && expansion_safe(s.axes) && expansion_safe(s.half_extent);
            else if constexpr (std::is_same_v<S, Sphere<T>>) return expansion_safe(s.center) && expansion_safe(s.radius);
            else if constexpr (std::is_same_v<S, Plane<T>>) return expansion_safe(s.normal) && expansion_safe(s.offset);
            else {
                if (h.face < 0) return true;
                const Plane<T>& q = s.planes[std::size_t(h.face)];
                return expansion_safe(q.normal) && expansion_safe(q.offset);
            }
        },
        p);
}

// The exact stage of compare_entry: sign(e_a − e_b) decided exactly, for any pair of
// certified hits of the ray (the filter is not consulted). nullopt only past BigDyadic8's
// capacity, which the degree-8 polynomials of finite inputs never reach (tested at mixed
// extreme exponents).
template <class T>
std::optional<int> compare_entry_exact(const PreparedRay<T>& ray, const Primitive<T>& a, const Hit<T>& ha,
                                       const Primitive<T>& b, const Hit<T>& hb) {
    const Ray<T>& r = ray.ray();
    const bool safe = expansion_safe(r.origin) && expansion_safe(r.direction) &&
                      (!std::isfinite(r.t_min) || expansion_safe(r.t_min)) && entry_expansion_safe(a, ha) &&
                      entry_expansion_safe(b, hb);
    return with_exact<kDefaultExpansionCap, BigDyadic8>(safe, [&](auto tag) -> std::optional<int> {
        using E = typename decltype(tag)::type;
        const std::optional<ExactEntry<E>> x = exact_entry<E>(r, a, ha), y = exact_entry<E>(r, b, hb);
        if (!x || !y) return std::nullopt;
        return compare_exact_entries(*x, *y, r.t_min);
    });
}

// sign(e_a − e_b) for two certified hits ha, hb of the same ray against a and b: the
// float filter, else the exact stage.
template <class T>
int compare_entry(const PreparedRay<T>& ray, const Primitive<T>& a, const Hit<T>& ha, const Primitive<T>& b,
                  const Hit<T>& hb) {
    if (const int s = compare_entry_filter(ha.t_enter, hb.t_enter)) return s;
    if (const std::optional<int> s = compare_entry_exact(ray, a, ha, b, hb)) return *s;
    // Unreachable within BigDyadic8's capacity; the floats' order is the best answer left.
    return ha.t_enter < hb.t_enter ? -1 : hb.t_enter < ha.t_enter ? +1 : 0;
}

}  // namespace rayproof::detail
