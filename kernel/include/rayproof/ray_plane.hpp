// rayproof/ray_plane.hpp — ray against plane.
//
// Shape:     the surface { p : n·p == offset } (a plane, not a half-space).
// Query:     the ray crosses it at the single t = (offset - n·o) / (n·d) when n·d != 0:
//            hit iff t_min <= t <= t_max, t_enter = t_exit = t. When n·d == 0 the ray is
//            parallel: it lies in the plane (hit on its whole range, t_enter = t_min,
//            t_exit = t_max) iff n·o == offset, otherwise it misses. face is always -1.
// Algorithm: direct evaluation (Ericson, Real-Time Collision Detection, 5.3.1).
// Degenerate cases: a ray lying in the plane; a parallel ray off the plane; a crossing
//            exactly at t_min or t_max; nearly parallel rays, where n·d is tiny and the
//            rounded t is large and unreliable.
// Modes:     fast — num = offset - n·o has error <= gamma(4)·(|offset| + Σ|n_i o_i|) and
//            den = n·d <= gamma(3)·Σ|n_i d_i|; when den is of the order of its own error
//            bound, even its sign (and so the verdict) is unknown. Measured, not promised.
//            conservative — num and den in interval arithmetic with outward rounding
//            (in double for both scalar types); the sign of den, and whether a parallel
//            ray lies in the plane, are decided exactly when the intervals hold zero;
//            t is the interval quotient, unbounded on one side when |den| may be tiny.
//            certified — the intervals decide what they separate; otherwise exact
//            arithmetic (detail/exact.hpp): sign(den) and sign(num) are degree 2, the
//            position of t against t_min/t_max sign(num - t_min·den)·sign(den) degree
//            3; t is rounded faithfully first from double-word num and den with proven
//            bounds (detail/compensated.hpp: 7 and 6 exact terms; for float the
//            faithful double rounded to nearest), next from the interval when it lies
//            strictly between the neighbours of its midpoint, else exactly.
//            The common case runs as straight-line code first (plane_certified_common):
//            the sign of den and the position of t against t_min and t_max from the same
//            double-word sums and their bounds, no intervals; what it cannot decide goes
//            to the general path (plane_certified), which rounds t the same way first,
//            so the two answer alike bit for bit.
#pragma once

#include <rayproof/detail/compensated.hpp>
#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/detail/slab_certified.hpp>
#include <rayproof/detail/validate.hpp>

namespace rayproof::detail {

template <class T> struct PreparedPlane {
    Plane<T> plane;
    bool ok;
};
template <class T> PreparedPlane<T> prepare(const Plane<T>& p) { return {p, valid(p)}; }

template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> query(const Ray<T>& r, const PreparedPlane<T>& p, fast_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    const T den = p.plane.normal.dot(r.direction);
    const T num = p.plane.offset - p.plane.normal.dot(r.origin);
    Hit<T> h;
    if (den == 0) {
        if (num == 0) {
            h.verdict = Verdict::hit;
            h.t_enter = r.t_min;
            h.t_exit = r.t_max;
        }
        return h;
    }
    const T t = num / den;
    if (r.t_min <= t && t <= r.t_max) {
        h.verdict = Verdict::hit;
        h.t_enter = h.t_exit = t;
    }
    return h;
}

// num = offset - n·o and den = n·d as double-word sums of exact terms (7 and 6, see
// detail/compensated.hpp), for doubles and for floats alike (floats are doubles exactly).
struct PlaneSums {
    CompensatedSum num, den;
};
template <class T> RAYPROOF_ALWAYS_INLINE PlaneSums plane_sums(const Ray<T>& r, const Plane<T>& p) {
    PlaneSums s;
    s.num.add(double(p.offset));
    for (int j = 0; j < 3; ++j) {
        s.num.add_product(-double(p.normal[j]), double(r.origin[j]));
        s.den.add_product(double(p.normal[j]), double(r.direction[j]));
    }
    return s;
}
// t = num/den faithfully rounded to T from the double-word sums, given sign(den), or
// nothing. For float the faithfully rounded double is rounded to the nearest float: t
// lies within one double ulp of it, so within less than a float ulp of that float, which
// is therefore one of the two floats enclosing t (and t itself when t is a float).
template <class T> RAYPROOF_ALWAYS_INLINE std::optional<T> plane_compensated_faithful(const PlaneSums& s, int sden) {
    const std::optional<double> c = compensated_faithful_quotient(s.num, s.den, sden);
    if (!c) return std::nullopt;
    const T t = static_cast<T>(*c);
    if (!std::isfinite(t)) return std::nullopt;
    return t;
}
template <class T> std::optional<T> plane_compensated_faithful(const Ray<T>& r, const Plane<T>& p, int sden) {
    return plane_compensated_faithful<T>(plane_sums(r, p), sden);
}

// The crossing t = num/den, num = offset - n·o, den = n·d, with interval enclosures
// and the exact values on demand.
template <class T> class PlaneCrossing {
public:
    PlaneCrossing(const Ray<T>& r, const Plane<T>& p) : r_(&r), p_(&p) {
        Interval<double> n(double(p.offset)), d(0.0);
        for (int j = 0; j < 3; ++j) {
            const Interval<double> nj(double(p.normal[j]));
            n = n - nj * Interval<double>(double(r.origin[j]));
            d = d + nj * Interval<double>(double(r.direction[j]));
        }
        num_ = n;
        den_ = d;
        const int s = d.certain_sign();
        sden_ = s != 2 ? s : den_sign_exact();
    }
    int den_sign() const { return sden_; }
    // parallel ray: does it lie in the plane (num == 0)?
    bool in_plane() const {
        const int s = num_.certain_sign();
        if (s != 2) return s == 0;
        return in_plane_exact();
    }
    // The same decisions without the interval filter (the exact stage alone).
    int den_sign_exact() const {
        return exact_sign([&](auto tag) { return den<typename decltype(tag)::type>(); });
    }
    bool in_plane_exact() const {
        return exact_sign([&](auto tag) { return num<typename decltype(tag)::type>(); }) == 0;
    }
    Interval<double> enclose() const { return divide_signed(num_, den_, sden_); }
    // t faithfully rounded to T, given its enclosure t (den_sign() != 0): from
    // double-word num and den first (the straight-line path's rounding, see
    // plane_compensated_faithful); next from the enclosure when it pins one float; else
    // exactly (went_exact is then set).
    T faithful(const Interval<double>& t, bool& went_exact) const {
        if (const std::optional<T> c = plane_compensated_faithful(*r_, *p_, sden_)) return *c;
        if (const std::optional<T> f = faithful_from_enclosure<T>(t)) return *f;
        RAYPROOF_COUNT_EXACT(went_exact);
        return exact_faithful<T>(*this, 0, 0);
    }
    // Interface of the slab frames, for exact_compare / exact_faithful (axis 0 only).
    template <class E> E num(int = 0, int = 0) const {
        E s(double(p_->offset));
        for (int j = 0; j < 3; ++j) s = s - E(double(p_->normal[j])) * E(double(r_->origin[j]));
        return s;
    }
    template <class E> E den(int = 0) const {
        E s(0.0);
        for (int j = 0; j < 3; ++j) s = s + E(double(p_->normal[j])) * E(double(r_->direction[j]));
        return s;
    }
    bool safe() const {
        return expansion_safe(r_->origin) && expansion_safe(r_->direction) && expansion_safe(p_->normal) &&
               expansion_safe(p_->offset);
    }

private:
    template <class F> int exact_sign(F&& value) const {
        return *with_exact(safe(), [&](auto tag) -> std::optional<int> {
            const auto v = value(tag);
            if (v.overflowed()) return std::nullopt;
            return v.sign();
        });
    }
    const Ray<T>* r_;
    const Plane<T>* p_;
    Interval<double> num_, den_;
    int sden_;
};

// A ray parallel to the plane (n·d == 0 exactly) lies in it, and hits on its whole
// range, or misses; every mode decides this the same way (exactly).
template <class T, class X> Hit<T> parallel_answer(const Ray<T>& r, const X& x) {
    Hit<T> h;
    if (x.in_plane()) {
        h.verdict = Verdict::hit;
        h.t_enter = r.t_min;
        h.t_exit = r.t_max;
    }
    return h;
}

template <class T> Hit<T> query(const Ray<T>& r, const PreparedPlane<T>& p, conservative_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    const PlaneCrossing<T> x(r, p.plane);
    Hit<T> h;
    if (x.den_sign() == 0) return parallel_answer(r, x);
    const Interval<double> t = x.enclose();
    const double lo = std::max(t.lo, double(r.t_min)), hi = std::min(t.hi, double(r.t_max));
    if (!(lo <= hi)) return h;
    h.verdict = Verdict::hit;
    h.t_enter = round_down_to<T>(lo);
    h.t_exit = round_up_to<T>(hi);
    return h;
}

// The certified decisions on a crossing X (PlaneCrossing, or a test's wrapper that
// turns the interval filter off to exercise the exact stage alone).
template <class T, class X> Hit<T> plane_certified(const Ray<T>& r, const X& x) {
    RAYPROOF_COUNT_QUERY();
    bool went_exact = false;
    Hit<T> h;
    if (x.den_sign() == 0) return parallel_answer(r, x);
    const Interval<double> t = x.enclose();
    const SlabRef crossing{0, 0, 0};
    // t_min <= t ?
    bool after_min;
    if (t.lo >= double(r.t_min)) {
        after_min = true;
    } else if (t.hi < double(r.t_min)) {
        after_min = false;
    } else {
        RAYPROOF_COUNT_EXACT(went_exact);
        after_min = exact_compare(x, crossing, SlabRef{-1, 0, double(r.t_min)}) >= 0;
    }
    bool before_max = false;
    if (after_min) {
        if (t.hi <= double(r.t_max)) {
            before_max = true;
        } else if (t.lo > double(r.t_max)) {
            before_max = false;
        } else {
            RAYPROOF_COUNT_EXACT(went_exact);
            before_max = exact_compare(x, crossing, SlabRef{-1, 0, double(r.t_max)}) <= 0;
        }
    }
    if (after_min && before_max) {
        h.verdict = Verdict::hit;
        h.t_enter = h.t_exit = x.faithful(t, went_exact);
    }
    RAYPROOF_COUNT_FLUSH(went_exact);
    return h;
}

// The straight-line path of the certified mode: every decision from the double-word
// sums, no intervals. sign(den) when |fl(hi + lo)| > 2·bound (|den - fl(hi + lo)| <=
// bound + u|fl(hi + lo)|); t against t_min and t_max by the sign of num - t_min·den
// (residual_sign, proven bound) times sign(den); t by compensated_faithful_quotient.
// Anything undecided (a nearly parallel ray, t within the bounds of an end of the
// range, a guard of the sums), nothing: the general path answers. The general path
// tries the same faithful rounding first, so the two agree bit for bit.
template <class T> RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> plane_certified_common(const Ray<T>& r,
                                                                                         const Plane<T>& p) {
    const PlaneSums s = plane_sums(r, p);
    if (!s.num.ok() || !s.den.ok()) return std::nullopt;
    const double bn = s.num.bound(), bd = s.den.bound(), dv = s.den.hi() + s.den.lo();
    if (!(std::abs(dv) > 2 * bd)) return std::nullopt;
    const int sden = dv > 0 ? 1 : -1;
    Hit<T> h;
    if (!std::isinf(r.t_min)) {  // t >= t_min?
        const int c = residual_sign(s.num, s.den, bn, bd, double(r.t_min));
        if (c == 2) return std::nullopt;
        if (c != sden) return h;
    }
    if (!std::isinf(r.t_max)) {  // t <= t_max?
        const int c = residual_sign(s.num, s.den, bn, bd, double(r.t_max));
        if (c == 2) return std::nullopt;
        if (c == sden) return h;
    }
    const std::optional<T> t = plane_compensated_faithful<T>(s, sden);
    if (!t) return std::nullopt;
    h.verdict = Verdict::hit;
    h.t_enter = h.t_exit = *t;
    return h;
}

template <class T> [[gnu::noinline, gnu::cold]] Hit<T> plane_certified_general(const Ray<T>& r, const Plane<T>& p) {
    return plane_certified(r, PlaneCrossing<T>(r, p));
}

template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> query(const Ray<T>& r, const PreparedPlane<T>& p, certified_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    return common_or_general(plane_certified_common(r, p.plane), [&] { return plane_certified_general(r, p.plane); });
}

}  // namespace rayproof::detail
