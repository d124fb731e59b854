// rayproof/detail/ray_sphere_general.hpp — the general path of the certified Ray/Sphere
// query: every decision on exact signs, each tried first on the quadratic's intervals
// (and, for double, on its double-word residual), and t_enter and t_exit found by a
// search over the ordered floats (detail/rounding.hpp). It answers every valid input.
// Every slope sign the intervals leave open comes from one exact vertex, and on a
// tangent line every such sign of q too, and t_enter and t_exit then need no search:
// both are read off the vertex (sphere_tangent_answer, which ray_sphere.hpp's tangent
// shortcut shares). The search starts from exact root estimates where the intervals'
// roots are wide (SphereQuadratic).
#pragma once

#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/detail/ray_sphere_quadratic.hpp>
#include <rayproof/types.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>

namespace rayproof::detail {

// The floats next to t* given a double f and side = sign(f - t*), where t* lies at f
// (side 0) or strictly between f and its double neighbour on the side's side: the
// greatest float of T at or below t* and the least at or above it, zeros as +0 (the
// search's keys do not tell -0 from +0 and give +0). A float of T that is not f lies
// at or beyond f's double neighbours, so beyond t* too.
template <class T> std::pair<T, T> sphere_tangent_floats(double f, int side) {
    const auto plus0 = [](T x) { return x == 0 ? T(0) : x; };
    const T g = narrow<T>(f);
    const double gd = double(g);
    // The position of t* against g: as f's against g where they differ, else side.
    const int s = gd != f ? (gd > f ? 1 : -1) : side;
    if (s == 0) return {plus0(g), plus0(g)};
    if (s > 0) return {plus0(step_down(g)), plus0(g)};  // t* < g
    return {plus0(g), plus0(step_up(g))};                // t* > g
}

// The answer on a tangent line, b² - a c' = 0 exactly, so that q(t) = a (t - t*)², from
// the vertex v (f and side as SphereQuadratic::Vertex): q(g) <= 0 only at g = t*, and the
// slope's sign is that of g - t*. A hit iff t* lies in [t_min, t_max]; then the entry
// search's predicate holds from the least float at or above t*, the exit search's up to
// the greatest at or below it (sphere_tangent_floats), and an end of the range with q <=
// 0 is t* itself, answered as the search answers it (t_enter = t_min, t_exit = t_max).
// None where a neighbour of t* is not finite (beyond the largest float: the search
// answers then).
template <class T, class V> std::optional<Hit<T>> sphere_tangent_answer(const Ray<T>& r, const V& v) {
    const auto at = [&](T t) { return !std::isinf(t) && v.side == 0 && double(t) == v.f; };  // q(t) <= 0
    const bool from_min = at(r.t_min), to_max = at(r.t_max);
    Hit<T> h;
    const bool before = std::isinf(r.t_min) || v.slope_sign(double(r.t_min)) <= 0;  // t_min <= t*
    const bool after = std::isinf(r.t_max) || v.slope_sign(double(r.t_max)) >= 0;   // t* <= t_max
    if (!(before && after)) return h;
    const auto [below, above] = sphere_tangent_floats<T>(v.f, v.side);
    if (!(std::isfinite(below) && std::isfinite(above))) return std::nullopt;
    h.verdict = Verdict::hit;
    h.t_enter = from_min ? r.t_min : above;
    h.t_exit = to_max ? r.t_max : below;
    if (h.t_enter > h.t_exit) h.t_enter = h.t_exit;
    return h;
}

// The certified decisions on a quadratic Q (SphereQuadratic, or a test's wrapper that
// turns the interval filter off to exercise the exact stage alone).
template <class T, class Q> Hit<T> sphere_certified(const Ray<T>& r, const Q& q) {
    RAYPROOF_COUNT_QUERY();
    bool went_exact = false;
    Hit<T> h;
    constexpr T big = std::numeric_limits<T>::max();
    // The double-word residual, built on its first use (most queries need none).
    std::optional<decltype(q.residual())> residual;
    // The vertex, exact, on the first slope its interval leaves undecided (and for a
    // tangent, below).
    std::optional<decltype(q.vertex())> vertex;
    // Whether the discriminant is exactly 0 (a tangent line), decided on the first q
    // sign that needs exact arithmetic: then q(t) = a (t - t*)², whose sign is 0 at t =
    // t* and 1 elsewhere, from the vertex alone.
    int tangent = -1;  // -1: not yet decided
    // sign of q at t (t = ±inf: +1, q grows without bound), and of a t + b (t = ±inf: ±1).
    auto q_sign = [&](T t) {
        if (std::isinf(t)) return 1;
        const int s = q.at(double(t)).certain_sign();
        if (s != 2) return s;
        if constexpr (std::is_same_v<T, double>) {
            if (!residual) residual.emplace(q.residual());
            const int c = residual->sign_at(double(t));
            if (c != 2) return c;
        }
        RAYPROOF_COUNT_EXACT(went_exact);
        if (tangent < 0) tangent = q.sign_discriminant() == 0;
        if (tangent) {
            if (!vertex) vertex.emplace(q.vertex());
            return vertex->side == 0 && double(t) == vertex->f ? 0 : 1;
        }
        return q.sign_at(double(t));
    };
    auto slope_sign = [&](T t) {
        if (std::isinf(t)) return t > 0 ? 1 : -1;
        const int s = q.slope(double(t)).certain_sign();
        if (s != 2) return s;
        if (!vertex) {
            RAYPROOF_COUNT_EXACT(went_exact);
            vertex.emplace(q.vertex());
        }
        return vertex->slope_sign(double(t));
    };
    const int q_min = q_sign(r.t_min), q_max = q_sign(r.t_max);
    bool hit = q_min <= 0 || q_max <= 0;
    if (!hit && slope_sign(r.t_min) < 0 && slope_sign(r.t_max) > 0) {  // vertex strictly inside
        const Interval<double> disc = q.discriminant();
        int sd = disc.certain_sign();
        if (sd == 2) {
            RAYPROOF_COUNT_EXACT(went_exact);
            sd = q.sign_discriminant();
            tangent = sd == 0;
        }
        hit = sd >= 0;
    }
    if (!hit) {
        RAYPROOF_COUNT_FLUSH(went_exact);
        return h;
    }
    h.verdict = Verdict::hit;
    // A tangent line (known once a sign needed exact arithmetic): from the vertex.
    if (tangent == 1) {
        if (!vertex) vertex.emplace(q.vertex());
        if (const std::optional<Hit<T>> t = sphere_tangent_answer(r, *vertex)) {
            RAYPROOF_COUNT_FLUSH(went_exact);
            return *t;
        }
    }
    const auto [r0, r1] = q.roots(q.discriminant());
    // Starts for the search: the intervals' midpoints, or the exact estimates where an
    // interval is wide or unbounded (near a tangent, or far outside the double range),
    // each where it is finite (an entry root beyond -DBL_MAX leaves the exit's estimate
    // good).
    double start0 = r0.mid(), start1 = r1.mid();
    const auto wide = [](const Interval<double>& x) {  // an unbounded interval is wide
        return !(x.hi - x.lo <= 0x1p-40 * (std::abs(x.lo) + std::abs(x.hi))) || !std::isfinite(x.hi - x.lo);
    };
    if (wide(r0) || wide(r1)) {
        const auto [e0, e1] = q.root_estimates();  // each where it is finite
        if (std::isfinite(e0)) start0 = e0;
        if (std::isfinite(e1)) start1 = e1;
    }
    // The key a search (lo, hi] starts from: the guess's, moved inside the range where it
    // lies at or beyond an end (a root estimate just outside the range, an end root
    // estimated as -0 for t_min = 0: first_true gallops only from a key strictly inside,
    // and bisects the whole range else); `none` without a finite guess.
    const auto start_key = [](T guess, std::int64_t lo, std::int64_t hi, std::int64_t none) {
        if (!std::isfinite(guess) || std::uint64_t(hi) - std::uint64_t(lo) < 2) return none;
        return std::clamp(float_key(guess), lo + 1, hi - 1);
    };
    // Search range: the finite part of [t_min, t_max].
    const std::int64_t kmin = float_key(std::max(r.t_min, -big)), kmax = float_key(std::min(r.t_max, big));
    if (q_min <= 0) {
        h.t_enter = r.t_min;
    } else {
        // least g with a g + b >= 0 or q(g) <= 0; false at t_min (outside, vertex beyond).
        auto enter = [&](std::int64_t k) {
            const T g = key_float<T>(k);
            return slope_sign(g) >= 0 || q_sign(g) <= 0;
        };
        const T guess = narrow<T>(start0);
        const std::int64_t lo = float_key(r.t_min) == kmin && !std::isinf(r.t_min) ? kmin : kmin - 1;
        // enter(t_max) holds for a finite t_max (t0 <= t_max); for t_max = inf, t0 may
        // lie beyond the largest float, whose enclosing finite neighbour is answered.
        const bool reached = !std::isinf(r.t_max) || enter(kmax);
        h.t_enter = reached ? key_float<T>(first_true(lo, kmax, start_key(guess, lo, kmax, lo), enter))
                            : big;
    }
    if (q_max <= 0) {
        h.t_exit = r.t_max;
    } else {
        // greatest g with a g + b <= 0 or q(g) <= 0: the predicate "not exit(g)" turns true above t1.
        auto past = [&](std::int64_t k) {
            const T g = key_float<T>(k);
            return !(slope_sign(g) <= 0 || q_sign(g) <= 0);
        };
        const T guess = narrow<T>(start1);
        const std::int64_t hi = float_key(r.t_max) == kmax && !std::isinf(r.t_max) ? kmax : kmax + 1;
        const bool reached = !std::isinf(r.t_min) || !past(kmin);
        h.t_exit = reached ? key_float<T>(first_true(kmin, hi, start_key(guess, kmin, hi, hi), past) - 1)
                           : -big;
    }
    if (h.t_enter > h.t_exit) h.t_enter = h.t_exit;
    RAYPROOF_COUNT_FLUSH(went_exact);
    return h;
}


// disc_sign: sign(b² - a c') where the caller decided it already (SphereQuadratic), else 2.
template <class T>
[[gnu::noinline, gnu::cold]] Hit<T> sphere_certified_general(const Ray<T>& r, const Sphere<T>& s, int disc_sign = 2) {
    return sphere_certified(r, SphereQuadratic<T>(r, s, disc_sign));
}

}  // namespace rayproof::detail
