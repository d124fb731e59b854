// rayproof/ray_sphere.hpp — ray against sphere.
//
// Shape:     the closed ball { p : |p - c| <= r } (radius 0 is the single point c).
// Query:     with Δ = o - c, the squared distance q(t) = |Δ + t d|² - r² = a t² + 2 b t + c'
//            (a = d·d, b = d·Δ, c' = Δ·Δ - r²) is <= 0 exactly on [t0, t1], the roots
//            t0,1 = (-b ∓ sqrt(b² - a c'))/a; the answer is [t0, t1] ∩ [t_min, t_max].
//            face is always -1.
// Algorithm: the numerically careful quadratic (pbrt-v4, section 6.8.2; Haines et al.,
//            "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems, ch. 7):
//            the discriminant as b² - a c' = a·(r² - |Δ - (b/a) d|²) = a·(r - l)(r + l) with
//            l = |Δ - (b/a) d| the distance from c to the line, which avoids the
//            cancellation of b² - a c' for far or small spheres; the near root as
//            q/a and the far one as c'/q with q = -(b + sign(b)·sqrt(disc)), so neither
//            root subtracts nearly equal numbers.
// Degenerate cases: tangent rays (disc == 0, t0 == t1), radius 0, origin inside or on the
//            sphere, the sphere behind the origin, b == 0 with a tangent at t = 0.
// Modes:     fast — l carries a relative error of a few gamma(n) of |Δ|, so for a ray
//            passing at distance ~r from the centre, the verdict is uncertain within
//            about gamma(8)·|Δ| of tangency; measured, not promised.
//            conservative — the same formulas in interval arithmetic with outward
//            rounding (in double for both scalar types): the discriminant as
//            a·(r - l)(r + l), l = |Δ - (b/a) d|, and the roots from q = -(b + sign(b)·√disc)
//            when the sign of b is certain (the naive (-b ∓ √disc)/a otherwise). A
//            discriminant interval reaching 0 counts as a hit: never a false miss.
//            certified — decisions on exact signs, each tried first on intervals:
//            q(t) = a t² + 2 b t + c' is convex with its vertex at t* = -b/a, so on
//            [t_min, t_max] its minimum is at t_min when a·t_min + b >= 0, at t_max when
//            a·t_max + b <= 0, and at t* otherwise, where its sign is that of -(b² - a c').
//            hit iff that minimum is <= 0. t_enter is t_min when q(t_min) <= 0, else the
//            smaller root t0, found as the least float g with a·g + b >= 0 or q(g) <= 0
//            (a predicate that is false below t0 and true from t0 on): t0 lies in
//            (pred g, g], so g is t0 faithfully rounded (and t0 itself when q(g) == 0).
//            t_exit likewise from above. The search starts at the interval root and
//            gallops then bisects over the ordered floats (at most ~2·64 predicate
//            evaluations, usually 2). Exact signs: q(g) is degree 4, b² - a c' degree 4,
//            a·g + b degree 3 (detail/exact.hpp). For double, a q(g) the interval cannot
//            sign (near a root its enclosure holds 0) is tried next in double-word
//            arithmetic with a proven bound (compensated_sign_at), then exactly.
#pragma once

#include <rayproof/detail/compensated.hpp>
#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/detail/slab_certified.hpp>
#include <rayproof/detail/validate.hpp>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <utility>

namespace rayproof::detail {

template <class T> struct PreparedSphere {
    Sphere<T> sphere;
    bool ok;
};
template <class T> PreparedSphere<T> prepare(const Sphere<T>& s) { return {s, valid(s)}; }

template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> query(const Ray<T>& r, const PreparedSphere<T>& p, fast_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    const Vec3<T>& d = r.direction;
    const Vec3<T> delta = r.origin - p.sphere.center;
    const T rad = p.sphere.radius;
    const T a = d.squaredNorm();
    const T b = d.dot(delta);
    const T l = (delta - (b / a) * d).norm();
    Hit<T> h;
    const T disc = a * ((rad - l) * (rad + l));
    if (!(disc >= 0)) return h;
    const T q = -(b + std::copysign(std::sqrt(disc), b));
    T t0, t1;
    if (q == 0) {  // b == 0 and disc == 0: tangent at t = -b/a = 0
        t0 = t1 = T(0);
    } else {
        const T c = delta.squaredNorm() - rad * rad;
        t0 = q / a;
        t1 = c / q;
        if (t1 < t0) std::swap(t0, t1);
    }
    // Squares that overflow or underflow T (|d|² beyond the range, say) leave NaN here:
    // fast mode answers miss then (it promises nothing; the other modes are exact there).
    if (std::isnan(t0) || std::isnan(t1) || t0 > r.t_max || t1 < r.t_min) return h;
    h.verdict = Verdict::hit;
    h.t_enter = std::max(t0, r.t_min);
    h.t_exit = std::min(t1, r.t_max);
    return h;
}

// The quadratic q(t) = |Δ + t d|² - r² of a ray and a sphere, with interval enclosures
// of its pieces and exact signs on demand.
template <class T> class SphereQuadratic {
public:
    using I = Interval<double>;
    SphereQuadratic(const Ray<T>& r, const Sphere<T>& s) : r_(&r), s_(&s) {
        I a(0.0), b(0.0), dd(0.0);
        for (int j = 0; j < 3; ++j) {
            delta_[j] = I(double(r.origin[j])) - I(double(s.center[j]));
            const I d(double(r.direction[j]));
            a = a + sqr(d);
            b = b + d * delta_[j];
            dd = dd + sqr(delta_[j]);
        }
        a_ = a;
        b_ = b;
        c_ = dd - sqr(I(double(s.radius)));
    }
    const I& a() const { return a_; }
    const I& b() const { return b_; }
    const I& c() const { return c_; }

    // Enclosure of the discriminant b² - a c' = a (r - l)(r + l), l = |Δ - (b/a) d|.
    I discriminant() const {
        const I f = b_ / a_;
        I l2(0.0);
        for (int j = 0; j < 3; ++j) l2 = l2 + sqr(delta_[j] - f * I(double(r_->direction[j])));
        const I l = sqrt_nonneg(l2), rad(double(s_->radius));
        return a_ * ((rad - l) * (rad + l));
    }
    // Enclosures of the two roots, given the discriminant's enclosure (hi >= 0).
    std::pair<I, I> roots(const I& disc) const {
        const I sq = sqrt_nonneg(disc);
        if (b_.lo > 0 || b_.hi < 0) {
            const I q = b_.lo > 0 ? -(b_ + sq) : sq - b_;  // no cancellation: same signs
            if (!q.contains_zero()) {
                const I r1 = q / a_, r2 = c_ / q;
                return b_.lo > 0 ? std::pair{r1, r2} : std::pair{r2, r1};
            }
        }
        return {(-b_ - sq) / a_, (sq - b_) / a_};
    }
    I at(double t) const {  // q(t)
        const I ti(t);
        I s(0.0);
        for (int j = 0; j < 3; ++j) s = s + sqr(delta_[j] + ti * I(double(r_->direction[j])));
        return s - sqr(I(double(s_->radius)));
    }
    I slope(double t) const { return a_ * I(t) + b_; }  // a t + b, half the derivative

    // sign q(t) from double-word arithmetic with a proven bound (detail/compensated.hpp),
    // or 2 when that cannot decide (q(t) == 0 never is). t finite.
    // w_j = (o_j - c_j) + t·d_j is held exactly by four terms (two_sum, two_prod) and
    // summed to W_j + ω_j with |w_j - W_j - ω_j| <= β_j; then
    // w_j² = W_j² + 2 W_j ω_j + ε_j, |ε_j| <= ω_j² + β_j (2|W_j| + 2|ω_j| + β_j), and
    // Σ (W_j² + 2 W_j ω_j) - r² is a CompensatedSum of exact products (bound B). The
    // value v = fl(hi + lo) is within u|v| of hi + lo; a sign is answered when |v|
    // exceeds 2(B + Σ_j bound(ε_j)) + 2^-1020: the doubling covers u and the relative
    // error of evaluating the bound (about gamma(12)), 2^-1020 its underflow.
    int compensated_sign_at(double t) const {
        CompensatedSum q;
        double err = 0;
        for (int j = 0; j < 3; ++j) {
            CompensatedSum w;
            const Pair oc = two_sum(double(r_->origin[j]), -double(s_->center[j]));
            w.add(oc.hi);
            w.add(oc.lo);
            w.add_product(t, double(r_->direction[j]));
            if (!w.ok()) return 2;
            const double W = w.hi(), om = w.lo(), beta = w.bound();
            q.add_product(W, W);
            q.add_product(2 * W, om);
            err += om * om + beta * (2 * std::abs(W) + 2 * std::abs(om) + beta);
        }
        const double rad = s_->radius;
        q.add_product(-rad, rad);
        if (!q.ok()) return 2;
        const double threshold = 2 * (q.bound() + err) + 0x1p-1020;
        const double v = q.hi() + q.lo();
        if (!(threshold <= 0x1p1000)) return 2;
        if (v > threshold) return 1;
        if (v < -threshold) return -1;
        return 2;
    }

    // Exact signs.
    int sign_at(double t) const {  // sign q(t), t finite
        return exact_sign([&](auto tag) {
            using E = typename decltype(tag)::type;
            const E et(t);
            E s(0.0);
            for (int j = 0; j < 3; ++j) {
                const E v = E(double(r_->origin[j])) - E(double(s_->center[j])) + et * E(double(r_->direction[j]));
                s = s + v * v;
            }
            const E rad(double(s_->radius));
            return s - rad * rad;
        });
    }
    int sign_slope(double t) const {  // sign(a t + b), t finite
        return exact_sign([&](auto tag) {
            using E = typename decltype(tag)::type;
            return ea<E>() * E(t) + eb<E>();
        });
    }
    int sign_discriminant() const {  // sign(b² - a c')
        return exact_sign([&](auto tag) {
            using E = typename decltype(tag)::type;
            const E b = eb<E>();
            E c(0.0);
            for (int j = 0; j < 3; ++j) {
                const E dj = E(double(r_->origin[j])) - E(double(s_->center[j]));
                c = c + dj * dj;
            }
            const E rad(double(s_->radius));
            c = c - rad * rad;
            return b * b - ea<E>() * c;
        });
    }

private:
    template <class E> E ea() const {
        E s(0.0);
        for (int j = 0; j < 3; ++j) s = s + E(double(r_->direction[j])) * E(double(r_->direction[j]));
        return s;
    }
    template <class E> E eb() const {
        E s(0.0);
        for (int j = 0; j < 3; ++j)
            s = s + E(double(r_->direction[j])) * (E(double(r_->origin[j])) - E(double(s_->center[j])));
        return s;
    }
    bool safe() const {
        return expansion_safe(r_->origin) && expansion_safe(r_->direction) && expansion_safe(s_->center) &&
               expansion_safe(s_->radius);
    }
    template <class F> int exact_sign(F&& value) const {
        return *with_exact(safe(), [&](auto tag) -> std::optional<int> {
            const auto v = value(tag);
            if (v.overflowed()) return std::nullopt;
            return v.sign();
        });
    }
    const Ray<T>* r_;
    const Sphere<T>* s_;
    I delta_[3], a_, b_, c_;
};

template <class T> Hit<T> query(const Ray<T>& r, const PreparedSphere<T>& p, certified_t);

template <class T> Hit<T> query(const Ray<T>& r, const PreparedSphere<T>& p, conservative_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    const SphereQuadratic<T> q(r, p.sphere);
    if (!(q.a().lo > 0)) {
        // a = |d|² underflowed (|d| below about 2^-537): the interval formulas divide by
        // an interval holding 0. Rare enough to take the certified answer and widen each
        // faithfully rounded end by one step, which encloses the exact interval.
        Hit<T> h = query(r, p, certified_t{});
        if (h.verdict == Verdict::hit) {
            if (h.t_enter != r.t_min) h.t_enter = std::max(step_down(h.t_enter), r.t_min);
            if (h.t_exit != r.t_max) h.t_exit = std::min(step_up(h.t_exit), r.t_max);
        }
        return h;
    }
    Hit<T> h;
    const Interval<double> disc = q.discriminant();
    if (disc.hi < 0) return h;  // certainly no real root (NaN ends never decide a miss)
    const auto [t0, t1] = q.roots(disc);
    const double lo = std::isnan(t0.lo) ? double(r.t_min) : std::max(t0.lo, double(r.t_min));
    const double hi = std::isnan(t1.hi) ? double(r.t_max) : std::min(t1.hi, double(r.t_max));
    if (!(lo <= hi)) return h;
    h.verdict = Verdict::hit;
    h.t_enter = round_down_to<T>(lo);
    h.t_exit = round_up_to<T>(hi);
    return h;
}

// Floats as ordered integers (-0 and +0 share key 0), for searching over the floats.
template <class T> std::int64_t float_key(T x) {
    if constexpr (std::is_same_v<T, double>) {
        const std::int64_t b = std::bit_cast<std::int64_t>(x);
        return b < 0 ? -(b & INT64_MAX) : b;
    } else {
        const std::int32_t b = std::bit_cast<std::int32_t>(x);
        return b < 0 ? -std::int64_t(b & INT32_MAX) : std::int64_t(b);
    }
}
template <class T> T key_float(std::int64_t k) {
    if constexpr (std::is_same_v<T, double>) {
        return k < 0 ? -std::bit_cast<double>(-k) : std::bit_cast<double>(k);
    } else {
        return k < 0 ? -std::bit_cast<float>(std::int32_t(-k)) : std::bit_cast<float>(std::int32_t(k));
    }
}

// The least key in (lo, hi] where a monotone predicate (false ... false true ... true)
// turns true, given pred(lo) false and pred(hi) true, starting the search near `guess`.
// Key differences are taken in unsigned arithmetic: hi - lo can exceed INT64_MAX.
template <class P> std::int64_t first_true(std::int64_t lo, std::int64_t hi, std::int64_t guess, P&& pred) {
    if (guess > lo && guess < hi) {  // gallop outwards from the guess, then bisect
        if (pred(guess)) {
            hi = guess;
            for (std::int64_t step = 1; step < (std::int64_t(1) << 62) && std::uint64_t(step) < std::uint64_t(hi) - std::uint64_t(lo);
                 step *= 2) {
                if (!pred(hi - step)) {
                    lo = hi - step;
                    break;
                }
                hi -= step;
            }
        } else {
            lo = guess;
            for (std::int64_t step = 1; step < (std::int64_t(1) << 62) && std::uint64_t(step) < std::uint64_t(hi) - std::uint64_t(lo);
                 step *= 2) {
                if (pred(lo + step)) {
                    hi = lo + step;
                    break;
                }
                lo += step;
            }
        }
    }
    // hi - lo may exceed INT64_MAX (keys of opposite signs): differences in unsigned.
    while (std::uint64_t(hi) - std::uint64_t(lo) > 1) {
        const std::int64_t m = lo + std::int64_t((std::uint64_t(hi) - std::uint64_t(lo)) / 2);
        if (pred(m))
            hi = m;
        else
            lo = m;
    }
    return hi;
}

// The certified decisions on a quadratic Q (SphereQuadratic, or a test's wrapper that
// turns the interval filter off to exercise the exact stage alone).
template <class T, class Q> Hit<T> sphere_certified(const Ray<T>& r, const Q& q) {
    RAYPROOF_COUNT_QUERY();
    bool went_exact = false;
    Hit<T> h;
    constexpr T big = std::numeric_limits<T>::max();
    // sign of q at t (t = ±inf: +1, q grows without bound), and of a t + b (t = ±inf: ±1).
    auto q_sign = [&](T t) {
        if (std::isinf(t)) return 1;
        const int s = q.at(double(t)).certain_sign();
        if (s != 2) return s;
        if constexpr (std::is_same_v<T, double>) {
            const int c = q.compensated_sign_at(double(t));
            if (c != 2) return c;
        }
        RAYPROOF_COUNT_EXACT(went_exact);
        return q.sign_at(double(t));
    };
    auto slope_sign = [&](T t) {
        if (std::isinf(t)) return t > 0 ? 1 : -1;
        const int s = q.slope(double(t)).certain_sign();
        if (s != 2) return s;
        RAYPROOF_COUNT_EXACT(went_exact);
        return q.sign_slope(double(t));
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
        const T guess = static_cast<T>(r0.mid());
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
        const T guess = static_cast<T>(r1.mid());
        const std::int64_t hi = float_key(r.t_max) == kmax && !std::isinf(r.t_max) ? kmax : kmax + 1;
        const bool reached = !std::isinf(r.t_min) || !past(kmin);
        h.t_exit = reached ? key_float<T>(first_true(kmin, hi, std::isfinite(guess) ? float_key(guess) : hi, past) - 1)
                           : -big;
    }
    if (h.t_enter > h.t_exit) h.t_enter = h.t_exit;
    RAYPROOF_COUNT_FLUSH(went_exact);
    return h;
}

template <class T> Hit<T> query(const Ray<T>& r, const PreparedSphere<T>& p, certified_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    return sphere_certified(r, SphereQuadratic<T>(r, p.sphere));
}

}  // namespace rayproof::detail
