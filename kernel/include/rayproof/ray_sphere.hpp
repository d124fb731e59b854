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
//            The common case runs as straight-line code first (sphere_certified_common):
//            the roots estimated in double as the fast mode does, each refined by one
//            Newton step on a double-word q(x) and proven by the signs of q at the
//            candidate float and a neighbour (from the exact expansion q(x + δ) =
//            q(x) + δ(a(2x + δ) + 2b)); a miss proven by a bound on the line's distance
//            from the centre, or by q > 0 with the slope pointing away at an end of the
//            range. It answers for input magnitudes in [2^-300, 2^300] (or 0) and gives
//            the general path's answer bit for bit; everything it cannot prove goes to
//            the general path (sphere_certified). The verdict alone (verdict() in
//            intersect.hpp) comes from a filter of its own, signs only, with no square
//            root, division or root and no range restriction (sphere_verdict_common),
//            else from the full query.
#pragma once

#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/compensated.hpp>
#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/detail/validate.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <utility>

namespace rayproof::detail {

// The caller's sphere (which outlives the query) and its validity, decided once.
template <class T> struct PreparedSphere {
    const Sphere<T>& sphere;
    bool ok;
};
template <class T> RAYPROOF_ALWAYS_INLINE PreparedSphere<T> prepare(const Sphere<T>& s) { return {s, valid(s)}; }

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

template <class T> std::array<double, 3> double3(const Vec3<T>& v) { return {double(v[0]), double(v[1]), double(v[2])}; }

// q(t) = |(o - c) + t d|² - r² at a double t in double-word arithmetic with a proven
// bound (value_at), and its sign when the bound decides (sign_at: 1, -1, or 2; a zero
// is never decided). With the exact splittings (two_sum, two_prod; Higham, ASNA, 4.3):
//   o_j - c_j = s_j + e_j,  t·d_j = P_j + p_j,  s_j + P_j = W_j + y_j,
//   ω_j = fl(fl(y_j + e_j) + p_j),  w_j = W_j + ω_j + ε_j,  |ε_j| <= β_j = gamma(2)(|y_j| + |e_j| + |p_j|),
//   w_j² = W_j² + 2 W_j ω_j + ω_j² + ε_j (2 W_j + 2 ω_j + ε_j),  the last term <= F_j = β_j (2|W_j| + 2|ω_j| + β_j);
//   W_j² = A_j + a_j and r² = R + ρ exactly, A_0 + A_1 + A_2 - R = σ + x_1 + x_2 + x_3 exactly
//   (a cascade of two_sum);
// the small terms τ = (x_1, x_2, x_3, a_j, fl(2 W_j ω_j), fl(ω_j²), -ρ), thirteen in all,
// each product within u of its own value, summed to L with error <= gamma(12)·Σ|τ|;
// v = fl(σ + L). Hence
//   |q(t) - v| <= gamma(13)·Σ|τ| + Σ_j F_j + u|v|/(1 - u),
// and err = 2(gamma(13)·Σ|τ| + Σ F_j) + 2u|v| + 2^-1000 bounds it: the doubling covers
// the roundings of the bound itself. Underflow: a two_prod whose error term is
// subnormal may round it by up to 2^-1075; β_j carries 2^-1070 for p_j, and 2^-1000
// covers a_j, ρ and the small products. Exact while nothing overflows: the two_sum
// cascade is guarded by A_0 + A_1 + A_2 + R <= 2^1000; any other overflow leaves an
// infinite or NaN err, which decides nothing.
class SphereResidual {
public:
    SphereResidual(const std::array<double, 3>& o, const std::array<double, 3>& d, const std::array<double, 3>& c,
                   double radius)
        : d_(d), r2_(two_prod(radius, radius)) {
        for (int j = 0; j < 3; ++j) oc_[j] = two_sum(o[j], -c[j]);
    }
    struct Value {
        double v, err;  // |q(t) - v| <= err; err = +inf when a guard fails
    };
    Value value_at(double t) const {
        constexpr double g2 = gamma<double>(2), g13 = gamma<double>(13), u = unit_roundoff<double>;
        double W[3], om[3], A[3], small = -r2_.lo, abs_small = std::abs(r2_.lo), F = 0;
        for (int j = 0; j < 3; ++j) {
            const Pair p = two_prod(t, d_[j]);
            const Pair x = two_sum(oc_[j].hi, p.hi);
            W[j] = x.hi;
            om[j] = (x.lo + oc_[j].lo) + p.lo;
            const double beta = g2 * (std::abs(x.lo) + std::abs(oc_[j].lo) + std::abs(p.lo)) + 0x1p-1070;
            F += beta * (2 * std::abs(W[j]) + 2 * std::abs(om[j]) + beta);
            const Pair sq = two_prod(W[j], W[j]);
            A[j] = sq.hi;
            const double m = 2 * W[j] * om[j], k = om[j] * om[j];
            small += (sq.lo + m) + k;
            abs_small += (std::abs(sq.lo) + std::abs(m)) + k;
        }
        if (!(A[0] + A[1] + A[2] + r2_.hi <= 0x1p1000)) return {0, std::numeric_limits<double>::infinity()};
        const Pair s1 = two_sum(A[0], A[1]);
        const Pair s2 = two_sum(s1.hi, A[2]);
        const Pair s3 = two_sum(s2.hi, -r2_.hi);
        small += (s1.lo + s2.lo) + s3.lo;
        abs_small += (std::abs(s1.lo) + std::abs(s2.lo)) + std::abs(s3.lo);
        const double v = s3.hi + small;
        return {v, 2 * (g13 * abs_small + F) + 2 * u * std::abs(v) + 0x1p-1000};
    }
    int sign_at(double t) const {
        const Value q = value_at(t);
        if (q.v > q.err) return 1;
        if (q.v < -q.err) return -1;
        return 2;
    }

private:
    Pair oc_[3];
    std::array<double, 3> d_;
    Pair r2_;
};

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

    // sign q(t) from double-word arithmetic with a proven bound (SphereResidual), or 2
    // when that cannot decide. t finite.
    int compensated_sign_at(double t) const {
        return SphereResidual(double3(r_->origin), double3(r_->direction), double3(s_->center), double(s_->radius))
            .sign_at(t);
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

template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> query(const Ray<T>& r, const PreparedSphere<T>& p, certified_t);

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

// Signs of q(t) and of the slope a t + b at a finite t from one plain evaluation and a
// static bound (1, -1, or 2 when the bound cannot decide), with Δ~_j = fl(o_j - c_j):
//     w~_j = fl(Δ~_j + fl(t d_j)),  M_j = |Δ~_j| + |fl(t d_j)|,  |w~_j - w_j| <= gamma(2)·M_j
// (Δ~_j and fl(t d_j) are each within u/(1 - u) of their exact values, the sum one more
// rounding). Then |w~_j² - w_j²| <= |w~_j - w_j|·|w~_j + w_j| <= 2·gamma(2)(1 + gamma(3))·M_j²,
// and the sum of four rounded squares is off by gamma(4)·Σ terms (Higham, ASNA, 3.1):
//     |fl(Σ w~_j² - r²) - q(t)| <= gamma(9)·(Σ M_j² + r²).
// Likewise |fl(Σ d_j w~_j) - (a t + b)| <= (gamma(2) + gamma(3)(1 + u))·Σ|d_j| M_j <= gamma(6)·Σ|d_j| M_j.
// Each threshold is twice the bound evaluated in floating point (the doubling covers the
// few roundings of the bound itself) plus 2^-1000 for underflow (at most 2^-1075 per
// rounding, times at most 3·M_j where a square amplifies it, which for M_j >= 1 the
// relative bound absorbs). A threshold above 2^1000 (an overflow near) decides nothing.
struct SphereCheapSigns {
    int q, slope;
};
RAYPROOF_ALWAYS_INLINE SphereCheapSigns sphere_cheap_signs(const double (&dl)[3], const double (&d)[3], double rad,
                                                           double t) {
    constexpr double eta = 0x1p-1000, g9 = 2 * gamma<double>(9), g6 = 2 * gamma<double>(6);
    double v = -rad * rad, bq = rad * rad, sl = 0, bs = 0;
    for (int j = 0; j < 3; ++j) {
        const double p = t * d[j];
        const double w = dl[j] + p, m = std::abs(dl[j]) + std::abs(p);
        v += w * w;
        bq += m * m;
        sl += d[j] * w;
        bs += std::abs(d[j]) * m;
    }
    const double tq = g9 * bq + eta, ts = g6 * bs + eta;
    SphereCheapSigns out{2, 2};
    if (tq <= 0x1p1000) out.q = v > tq ? 1 : v < -tq ? -1 : 2;
    if (ts <= 0x1p1000) out.slope = sl > ts ? 1 : sl < -ts ? -1 : 2;
    return out;
}

// The straight-line path of the certified mode: the roots estimated as the fast mode
// does (in double), then proven. It answers a miss only when the line's distance from
// the centre certainly exceeds r, or the sphere certainly lies beyond an end of the
// range; a hit only with the signs of q at the estimates' floats and their neighbours
// proven (cheap bound, else double-word), which pins t_enter as the least float g with
// q(g) <= 0 after q(g-) > 0 (q convex: q decreases up to g, so every float below g is
// outside, as the general path's search predicate also says), and t_exit likewise from
// above. Anything else, nothing: the general path answers. Its answers are therefore the
// general path's, bit for bit.
// Distance certificate, with Δ~_j = fl(o_j - c_j), f = fl(b~/a~), P_j = fl(f d_j),
// m~_j = fl(Δ~_j - P_j), n = fl(sqrt(fl(Σ m~_j²))), exact Δ, a, b:
//   |m~_j - (Δ_j - f d_j)| <= gamma(2)(|Δ~_j| + |P_j|), so |Δ - f d| >= n(1 - gamma(3)) - gamma(2)·Σ(|Δ~_j| + |P_j|);
//   |b~ - b| <= gamma(4)·Σ|d_j Δ~_j| and |a~ - a| <= gamma(3)·a give |f - b/a| <= gamma(8)·Σ|d_j Δ~_j|/a~,
//   and by Cauchy-Schwarz ε² = a (f - b/a)² <= (gamma(9)·Σ|Δ~_j|)²;
//   the line's distance l satisfies l² = |Δ - f d|² - ε² >= (|Δ - f d| - ε)², so
//   l >= n - K, K = gamma(3)·n + gamma(2)·Σ(|Δ~_j| + |P_j|) + gamma(9)·Σ|Δ~_j| <= gamma(11)·(n + Σ|Δ~_j| + Σ|P_j|).
// A miss is answered when fl(n - r) > 2·fl(gamma(11)·(...)) + 2^-500: the doubling covers
// the roundings of both sides, 2^-500 the underflow of the squares under the square
// root (at most 3·2^-1075 inside, 2^-535 outside). Valid while every nonzero input
// magnitude (o, c, d, r) lies in [2^-300, 2^300]: then a, b, f and every product stay
// far from overflow and only the squares of m~ and the tiny products can underflow.
// The line o + t·d against the centre, in double, for the straight-line path: Δ~, a~,
// b~, n (the estimate of the line's distance from the centre) and the threshold of the
// distance certificate.
struct SphereLine {
    double d[3], dl[3];
    double rad, a, b, n, cc;
    double threshold;  // 2·fl(gamma(11)·(n + Σ|Δ~_j| + Σ|P_j|)) + 2^-500
    bool in_range;     // every nonzero input magnitude in [2^-300, 2^300]
};
template <class T> RAYPROOF_ALWAYS_INLINE SphereLine sphere_line(const Ray<T>& r, const Sphere<T>& s) {
    constexpr double g11 = 2 * gamma<double>(11), lo_mag = 0x1p-300, hi_mag = 0x1p300;
    SphereLine L;
    L.rad = double(s.radius);
    // The largest input magnitude, and the smallest nonzero one (1 when all are 0).
    auto nonzero_abs = [](double v) { return v == 0 ? 1.0 : std::abs(v); };
    double largest = std::abs(L.rad), smallest = nonzero_abs(L.rad);
    for (int j = 0; j < 3; ++j) {
        const double o = double(r.origin[j]), c = double(s.center[j]);
        L.d[j] = double(r.direction[j]);
        L.dl[j] = o - c;
        largest = std::max(largest, std::max(std::max(std::abs(o), std::abs(c)), std::abs(L.d[j])));
        smallest = std::min(smallest, std::min(std::min(nonzero_abs(o), nonzero_abs(c)), nonzero_abs(L.d[j])));
    }
    L.in_range = largest <= hi_mag && smallest >= lo_mag;
    const double(&d)[3] = L.d;
    const double(&dl)[3] = L.dl;
    L.a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    L.b = d[0] * dl[0] + d[1] * dl[1] + d[2] * dl[2];
    const double f = L.b / L.a;
    double n2 = 0, sum_dl = 0, sum_p = 0, cc = -L.rad * L.rad;
    for (int j = 0; j < 3; ++j) {
        const double p = f * d[j], m = dl[j] - p;
        n2 += m * m;
        sum_dl += std::abs(dl[j]);
        sum_p += std::abs(p);
        cc += dl[j] * dl[j];
    }
    L.cc = cc;
    L.n = std::sqrt(n2);
    L.threshold = g11 * (L.n + sum_dl + sum_p) + 0x1p-500;
    return L;
}

template <class T> RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> sphere_certified_common(const Ray<T>& r,
                                                                                          const Sphere<T>& s) {
    const SphereLine L = sphere_line(r, s);
    if (!L.in_range) return std::nullopt;
    const double(&d)[3] = L.d;
    const double(&dl)[3] = L.dl;
    const double rad = L.rad, a = L.a, b = L.b, n = L.n, cc = L.cc;
    Hit<T> h;
    if (!(n <= rad)) {  // the estimate says the line misses: prove it, or hand over
        if (n - rad > L.threshold) return h;
        return std::nullopt;
    }
    // The roots as the fast mode estimates them: q = -(b + sign(b)·sqrt(disc)), t = q/a, c'/q.
    const double disc = a * ((rad - n) * (rad + n));
    const double qq = -(b + std::copysign(std::sqrt(disc), b));
    double t0 = qq / a, t1 = cc / qq;
    if (t1 < t0) std::swap(t0, t1);
    if (!(std::isfinite(t0) && std::isfinite(t1))) return std::nullopt;

    // Signs at the ends of the range (q(±inf) = +1: it grows without bound).
    const bool min_inf = std::isinf(r.t_min), max_inf = std::isinf(r.t_max);
    const SphereCheapSigns at_min = min_inf ? SphereCheapSigns{1, -1} : sphere_cheap_signs(dl, d, rad, double(r.t_min));
    const SphereCheapSigns at_max = max_inf ? SphereCheapSigns{1, 1} : sphere_cheap_signs(dl, d, rad, double(r.t_max));
    const SphereResidual res(double3(r.origin), double3(r.direction), double3(s.center), rad);
    const int q_min = at_min.q != 2 ? at_min.q : res.sign_at(double(r.t_min));
    const int q_max = at_max.q != 2 ? at_max.q : res.sign_at(double(r.t_max));
    if (q_min == 2 || q_max == 2) return std::nullopt;
    // The sphere certainly behind t_min, or beyond t_max: outside there, moving away
    // (q is convex, so its slope only grows).
    if (q_min > 0 && at_min.slope == 1) return h;
    if (q_max > 0 && at_max.slope < 0) return h;

    // A root estimate x refined and proven: q(x) ≈ v in double-word arithmetic, one
    // Newton step x - v/(2(a x + b)) rounded to T gives the candidate g, and the sign of
    // q at g and at a neighbour y of g comes from the exact expansion of the quadratic,
    //     q(y) = q(x) + δ·σ,  δ = y - x (checked exact),  σ = a(2x + δ) + 2b,
    // evaluated as V = fl(v + fl(δ·σ~)), σ~ = fl(fl(a~·fl(2x + δ)) + 2b~). With
    // |b~ - b| <= gamma(4)·C (C = Σ|d_j Δ~_j|) and |a~ - a| <= gamma(3)·a,
    // |σ~ - σ| <= gamma(7)·(|fl(a~·fl(2x + δ))| + 2C) =: e_σ, so
    //     |V - q(y)| <= err_v + |δ|·e_σ + u|δ σ~| + u|V|/(1 - u),
    // and the sign of V is q(y)'s when |V| exceeds 2(err_v + |δ|(e_σ + u|σ~|)) + 2^-1000
    // (the doubling covers u|V| and the bound's own roundings, 2^-1000 underflow).
    constexpr double g7 = gamma<double>(7), u = unit_roundoff<double>;
    const double cab = std::abs(d[0] * dl[0]) + std::abs(d[1] * dl[1]) + std::abs(d[2] * dl[2]);
    auto refine = [&](double x, T& g) {
        const SphereResidual::Value qx = res.value_at(x);
        g = static_cast<T>(x - qx.v / (2 * (a * x + b)));
        if (g == 0) g = T(0);
        return qx;
    };
    auto sign_near = [&](const SphereResidual::Value& qx, double x, T y) {
        const Pair dd = two_sum(double(y), -x);
        const double del = dd.hi;
        const double xs = 2 * x + del, ax = a * xs, sig = ax + 2 * b;
        const double e_sig = 2 * g7 * (std::abs(ax) + 2 * cab);
        const double V = qx.v + del * sig;
        const double thr = 2 * (qx.err + std::abs(del) * (e_sig + u * std::abs(sig))) + 0x1p-1000;
        if (dd.lo != 0 || !(thr <= 0x1p1000)) return 2;
        return V > thr ? 1 : V < -thr ? -1 : 2;
    };
    auto canonical = [](T x) { return x == 0 ? T(0) : x; };  // step_up(-min) is -0

    T t_enter, t_exit;
    if (q_min <= 0) {
        t_enter = r.t_min;
    } else {
        // q decreases through t0: t_enter = g when q(g-) > 0 >= q(g), g+ when q(g) > 0 >= q(g+).
        T g;
        const SphereResidual::Value qx = refine(t0, g);
        if (!(std::isfinite(g) && g > r.t_min)) return std::nullopt;
        const int sg = sign_near(qx, t0, g);
        if (sg < 0 && g <= r.t_max && sign_near(qx, t0, step_down(g)) == 1) {
            t_enter = g;
        } else if (sg == 1 && step_up(g) <= r.t_max && sign_near(qx, t0, step_up(g)) < 0) {
            t_enter = canonical(step_up(g));
        } else {
            return std::nullopt;
        }
    }
    if (q_max <= 0) {
        t_exit = r.t_max;
    } else {
        // q increases through t1: t_exit = g when q(g) <= 0 < q(g+), g- when q(g-) <= 0 < q(g).
        T g;
        const SphereResidual::Value qx = refine(t1, g);
        if (!(std::isfinite(g) && g < r.t_max)) return std::nullopt;
        const int sg = sign_near(qx, t1, g);
        if (sg < 0 && g >= r.t_min && sign_near(qx, t1, step_up(g)) == 1) {
            t_exit = g;
        } else if (sg == 1 && step_down(g) >= r.t_min && sign_near(qx, t1, step_down(g)) < 0) {
            t_exit = canonical(step_down(g));
        } else {
            return std::nullopt;
        }
    }
    h.verdict = Verdict::hit;
    h.t_enter = t_enter > t_exit ? t_exit : t_enter;
    h.t_exit = t_exit;
    return h;
}

template <class T> [[gnu::noinline, gnu::cold]] Hit<T> sphere_certified_general(const Ray<T>& r, const Sphere<T>& s) {
    return sphere_certified(r, SphereQuadratic<T>(r, s));
}

template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> query(const Ray<T>& r, const PreparedSphere<T>& p, certified_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    return common_or_general(sphere_certified_common(r, p.sphere), [&] { return sphere_certified_general(r, p.sphere); });
}

// The certified verdict alone: a filter of its own, with no square root, no division
// and no root (the full query's straight-line path estimates and proves roots; the
// verdict needs only signs), which also proves the input valid, so nothing is checked
// before it. q is convex with q(±inf) = +inf: an end of the range with q < 0 is inside
// (a hit); an end with q > 0 and the slope pointing away from the range (up at t_min,
// down at t_max) means q > 0 on the whole range (a miss); the slope pointing into the
// range at both ends puts the vertex t* = -b/a strictly inside it, where q(t*) = l² - r²
// (l the line's distance from the centre) has the sign of l - r; and l > r is a miss
// on any range. verdict_declined for the rest (see verdict_or, detail/certified.hpp).
// The ends, t_min in lane 0 and t_max in lane 1, with the bounds of sphere_cheap_signs
// (the same operations, two lanes at once): |fl(Σ w~_j² - r²) - q(t)| <= gamma(9)·(Σ M_j² +
// r²) and |fl(Σ d_j w~_j) - (a t + b)| <= gamma(6)·Σ|d_j| M_j, each threshold twice the
// bound plus 2^-1000; a sum that overflows makes its bound's sum (of terms at least as
// large) +inf, and NaN anywhere compares false, so no sign is taken then. An infinite
// end computes NaN or ±inf (nothing is decided from it) and is taken as q > 0 with the
// slope pointing into the range.
// The line: l² a = |w|², w = Δ × d, so l > r iff S = |w|² > R = r² a, and l < r iff S <
// R (a > 0). Computed: Δ~_j = Δ_j(1 + δ), |δ| <= u; per component the two products A~,
// B~ (e.g. fl(Δ~_y d_z), fl(Δ~_z d_y), each within gamma(2) of the exact product plus
// 2^-1075 for underflow) and w~ = fl(A~ - B~), so with M = |A~| + |B~|,
//     |w~ - w| <= gamma(2)(|Δ_y d_z| + |Δ_z d_y|) + u M + 2^-1074 <= gamma(4) M + 2^-1073;
// |w~| <= M, and summing the squares (three roundings),
//     |S~ - S| <= gamma(3)Σ w~_j² + Σ e_j(2|w~_j| + e_j) + 3·2^-1075 <= gamma(13)Σ M_j² + 2^-1070
// (the cross terms 2^-1072·M_j are below u·M_j² for M_j >= 2^-1018 and below 2^-2000
// otherwise). With a~ = fl(Σ d_j²) >= 2^-1000 (required: its own underflow, at most
// 3·2^-1075, is then far below u·a, so |a~ - a| <= gamma(4)a) and R~ = fl(fl(r·r)·a~),
//     |R~ - R| <= gamma(7)·R~ + 2^-1074·a~ + 2^-1074
// (the 2^-1074·a~ from r·r underflowing). So D~ = fl(S~ - R~) > E proves S > R and
// -D~ > E proves S < R, for E = fl(2·gamma(13)·ΣM~_j² + 2·gamma(7)·R~ + 2^-1072·a~) +
// 2^-1000: the doubling covers the few roundings of E, of ΣM~² (each M~ = fl(|A~| + |B~|))
// and of D~ itself. An overflow makes E +inf (ΣM~² >= S~, R~ itself) and decides nothing.
// Validity: every decision above rests on a finite bound, which an infinite or NaN
// number among o, d, c and r makes +inf or NaN (each Δ_j and d_j is multiplied by
// something in each bound, and 0·inf is NaN), and a~ >= 2^-1000 means d != 0, r >= 0 is
// checked, and t_min <= t_max, t_min < +inf and -t_max < +inf in the lanes as the Aabb
// checks them.
template <class T> RAYPROOF_ALWAYS_INLINE int sphere_verdict_common(const Ray<T>& r, const Sphere<T>& s) {
    using namespace lanes;
    constexpr double eta = 0x1p-1000, g9 = 2 * gamma<double>(9), g6 = 2 * gamma<double>(6),
                     g13 = 2 * gamma<double>(13), g7 = 2 * gamma<double>(7), inf = std::numeric_limits<double>::infinity();
    const double rad = double(s.radius), rr = rad * rad;
    double d[3], dl[3];
    RAYPROOF_UNROLL3
    for (int j = 0; j < 3; ++j) {
        d[j] = double(r.direction[j]);
        dl[j] = double(r.origin[j]) - double(s.center[j]);
    }
    // The line's certificate.
    const double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    double S = 0, MM = 0;
    RAYPROOF_UNROLL3
    for (int j = 0; j < 3; ++j) {
        const int k = (j + 1) % 3, m = (j + 2) % 3;
        const double A = dl[k] * d[m], B = dl[m] * d[k], w = A - B, M = std::abs(A) + std::abs(B);
        S += w * w;
        MM += M * M;
    }
    const double R = rr * a, E = (g13 * MM + g7 * R + 0x1p-1072 * a) + eta, D = S - R;
    const bool line_out = D > E, line_in = -D > E;
    // The ends.
    const D2 t = make(double(r.t_min), double(r.t_max));
    D2 v = splat(-rr), bq = splat(rr), sl = splat(0.0), bs = splat(0.0);
    RAYPROOF_UNROLL3
    for (int j = 0; j < 3; ++j) {
        const D2 dj = splat(d[j]), P = t * dj, W = splat(dl[j]) + P, M = splat(std::abs(dl[j])) + abs(P);
        v = v + W * W;
        bq = bq + M * M;
        sl = sl + dj * W;
        bs = bs + abs(dj) * M;
    }
    const D2 tq = bq * splat(g9) + splat(eta), ts = bs * splat(g6) + splat(eta), out = negate_lane1(sl);
    const M2 infinite = abs(t) == splat(inf);
    const M2 inside = v < -tq, outside = (v > tq) | infinite;
    const M2 away = out > ts, toward = (out < -ts) | infinite;  // the slope at each end
    const D2 ordered = negate_lane1(t);                              // (t_min, -t_max)
    const M2 limits = valid_range_lanes(ordered);
    const bool usable = int(bits(limits) == 3) & int(rad >= 0) & int(a >= 0x1p-1000);
    const bool hit = (bits(inside) != 0) | (int(bits(toward) == 3) & int(line_in));
    const bool miss = int(line_out) | int(bits(outside & away) != 0);
    return usable & (int(hit) | int(miss)) ? int(hit) : verdict_declined;
}

// What the verdict filter declines: the full query's verdict, out of line.
template <class T> [[gnu::noinline, gnu::cold]] Verdict sphere_verdict_declined(const Ray<T>& r, const Sphere<T>& s) {
    return query(r, prepare(s), certified).verdict;
}

// The certified verdict: the filter's (which proves the input valid), else the full
// query's, which validates. The prepared flag is not consulted on the filter's path.
template <class T> RAYPROOF_ALWAYS_INLINE Verdict verdict_query(const Ray<T>& r, const PreparedSphere<T>& p, certified_t) {
    return verdict_or(sphere_verdict_common(r, p.sphere), [&] { return sphere_verdict_declined(r, p.sphere); });
}

}  // namespace rayproof::detail
