// rayproof/detail/ray_sphere_general.hpp — the general path of the certified Ray/Sphere
// query: every decision on exact signs, each tried first on the quadratic's intervals
// (and, for double, on its double-word residual), and t_enter and t_exit found by a
// search over the ordered floats (detail/rounding.hpp). It answers every valid input.
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

namespace rayproof::detail {

// The certified decisions on a quadratic Q (SphereQuadratic, or a test's wrapper that
// turns the interval filter off to exercise the exact stage alone).
template <class T, class Q> Hit<T> sphere_certified(const Ray<T>& r, const Q& q) {
    RAYPROOF_COUNT_QUERY();
    bool went_exact = false;
    Hit<T> h;
    constexpr T big = std::numeric_limits<T>::max();
    // The double-word residual, built on its first use (most queries need none).
    std::optional<decltype(q.residual())> residual;
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
        return q.sign_at(double(t));
    };
    // The vertex, exact, on the first slope its interval leaves undecided.
    std::optional<decltype(q.vertex())> vertex;
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
        }
        hit = sd >= 0;
    }
    if (!hit) {
        RAYPROOF_COUNT_FLUSH(went_exact);
        return h;
    }
    h.verdict = Verdict::hit;
    const auto [r0, r1] = q.roots(q.discriminant());
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
        const T guess = narrow<T>(r0.mid());
        const std::int64_t lo = float_key(r.t_min) == kmin && !std::isinf(r.t_min) ? kmin : kmin - 1;
        // enter(t_max) holds for a finite t_max (t0 <= t_max); for t_max = inf, t0 may
        // lie beyond the largest float, whose enclosing finite neighbour is answered.
        const bool reached = !std::isinf(r.t_max) || enter(kmax);
        h.t_enter = reached ? key_float<T>(first_true(lo, kmax, std::isfinite(guess) ? float_key(guess) : lo, enter))
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
        const T guess = narrow<T>(r1.mid());
        const std::int64_t hi = float_key(r.t_max) == kmax && !std::isinf(r.t_max) ? kmax : kmax + 1;
        const bool reached = !std::isinf(r.t_min) || !past(kmin);
        h.t_exit = reached ? key_float<T>(first_true(kmin, hi, std::isfinite(guess) ? float_key(guess) : hi, past) - 1)
                           : -big;
    }
    if (h.t_enter > h.t_exit) h.t_enter = h.t_exit;
    RAYPROOF_COUNT_FLUSH(went_exact);
    return h;
}


template <class T> [[gnu::noinline, gnu::cold]] Hit<T> sphere_certified_general(const Ray<T>& r, const Sphere<T>& s) {
    return sphere_certified(r, SphereQuadratic<T>(r, s));
}

}  // namespace rayproof::detail
