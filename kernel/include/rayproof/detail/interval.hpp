// rayproof/detail/interval.hpp — interval arithmetic with outward rounding, the error
// model of the conservative mode and the filter of the certified mode for the
// oriented box, the plane and the sphere.
//
// Every operation computes its floating-point result(s) round-to-nearest, then moves
// each end one representable value outward. Round-to-nearest is off by at most half
// an ulp of the result, one step outward covers it (also for subnormal results and
// overflow, where the step goes to ±inf), so [lo, hi] always contains the exact
// result of the exact operation applied to any reals in the operand intervals (pbrt-v4
// section 6.8.1 "Interval"; Moore, "Interval Analysis", 1966).
// Contraction (detail/eft.hpp): class C1. Every end passes through step_down or step_up
// (integer operations on the bits), so no product reaches an addition unrounded; mid()
// (lo/2 + hi/2, a product by 1/2 to the compiler) is only a candidate that
// faithful_from_enclosure checks against the ends.
#pragma once

#include <rayproof/detail/rounding.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rayproof::detail {

// A closed interval [lo, hi] of reals, lo <= hi, ends possibly ±inf.
template <class T> struct Interval {
    T lo, hi;

    Interval() = default;
    constexpr explicit Interval(T x) : lo(x), hi(x) {}
    constexpr Interval(T l, T h) : lo(l), hi(h) {}

    T mid() const { return lo / 2 + hi / 2; }
    bool contains(T x) const { return lo <= x && x <= hi; }
    bool contains_zero() const { return lo <= 0 && 0 <= hi; }
    // Sign when certain: +1 / -1 when the interval lies strictly on one side of zero,
    // 0 when it is the single point 0, and 2 when zero is inside but not alone.
    int certain_sign() const {
        if (lo > 0) return 1;
        if (hi < 0) return -1;
        if (lo == 0 && hi == 0) return 0;
        return 2;
    }
};

template <class T> Interval<T> operator+(Interval<T> a, Interval<T> b) {
    return {step_down(a.lo + b.lo), step_up(a.hi + b.hi)};
}
template <class T> Interval<T> operator-(Interval<T> a, Interval<T> b) {
    return {step_down(a.lo - b.hi), step_up(a.hi - b.lo)};
}
template <class T> Interval<T> operator-(Interval<T> a) { return {-a.hi, -a.lo}; }

// An infinite end stands for an overflowed finite value (step_down never gives +inf,
// step_up never -inf), so a product with an exact 0 end is 0, never 0·inf = NaN.
template <class T> T end_product(T x, T y) { return (x == 0 || y == 0) ? T(0) : x * y; }

template <class T> Interval<T> operator*(Interval<T> a, Interval<T> b) {
    const T p0 = end_product(a.lo, b.lo), p1 = end_product(a.lo, b.hi), p2 = end_product(a.hi, b.lo),
            p3 = end_product(a.hi, b.hi);
    return {step_down(std::min(std::min(p0, p1), std::min(p2, p3))),
            step_up(std::max(std::max(p0, p1), std::max(p2, p3)))};
}

// a·[y, y]: the same interval as a * Interval<T>(y), from two end products (the other
// two repeat them).
template <class T> Interval<T> times_point(Interval<T> a, T y) {
    const T p0 = end_product(a.lo, y), p2 = end_product(a.hi, y);
    return {step_down(std::min(p0, p2)), step_up(std::max(p0, p2))};
}

// Division by an interval that does not contain zero. An overflowed end over another
// (inf/inf) bounds nothing: the whole line is returned then.
template <class T> Interval<T> operator/(Interval<T> a, Interval<T> b) {
    const T q0 = a.lo / b.lo, q1 = a.lo / b.hi, q2 = a.hi / b.lo, q3 = a.hi / b.hi;
    if (std::isnan(q0) || std::isnan(q1) || std::isnan(q2) || std::isnan(q3))
        return {-std::numeric_limits<T>::infinity(), std::numeric_limits<T>::infinity()};
    return {step_down(std::min(std::min(q0, q1), std::min(q2, q3))),
            step_up(std::max(std::max(q0, q1), std::max(q2, q3)))};
}

// a / [d, d]: the same interval as a / Interval<T>(d), with two quotients instead of
// four (the other two repeat them).
template <class T> Interval<T> divide_by_point(Interval<T> a, T d) {
    const T q0 = a.lo / d, q2 = a.hi / d;
    if (std::isnan(q0) || std::isnan(q2)) return {-std::numeric_limits<T>::infinity(), std::numeric_limits<T>::infinity()};
    return {step_down(std::min(q0, q2)), step_up(std::max(q0, q2))};
}

// x² (tighter than x·x when x straddles zero).
template <class T> Interval<T> sqr(Interval<T> a) {
    const T l = std::abs(a.lo), h = std::abs(a.hi);
    if (a.lo <= 0 && 0 <= a.hi) return {T(0), step_up(std::max(l, h) * std::max(l, h))};
    const T m = std::min(l, h), M = std::max(l, h);
    return {step_down(m * m), step_up(M * M)};
}

// sqrt of the non-negative part.
template <class T> Interval<T> sqrt_nonneg(Interval<T> a) {
    const T l = a.lo > 0 ? step_down(std::sqrt(a.lo)) : T(0);
    return {std::max(l, T(0)), step_up(std::sqrt(std::max(a.hi, T(0))))};
}

template <class T> bool is_finite(Interval<T> a) { return std::isfinite(a.lo) && std::isfinite(a.hi); }

// Bound of the quotient n/d given the exact sign of d (nonzero) when d's interval may
// still hold zero: d lies in (0, d.hi] (or [d.lo, 0)), so n/d is unbounded on the side
// n's sign allows, or everywhere when n's sign is unknown too.
inline Interval<double> divide_signed(Interval<double> n, Interval<double> d, int sden) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    if (!d.contains_zero()) return n / d;
    if (sden < 0) {
        n = -n;
        d = -d;
    }
    if (n.lo > 0) return {step_down(n.lo / d.hi), inf};
    if (n.hi < 0) return {-inf, step_up(n.hi / d.hi)};
    return {-inf, inf};
}

}  // namespace rayproof::detail
