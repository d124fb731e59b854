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
//            conservative — in the pbrt-v4 manner first (plane_conservative_common):
//            num and den in plain double with the static bounds gamma(4)·Σ|terms| of
//            the certified filter, t~ = fl(num·fl(1/den)) widened by a bound derived
//            from them (at the code), when den is far from its bound (|den| >= 2^20
//            times it); for float input the same in float first (|den| >= 2^10 times
//            its bound), which answers where it lies inside or outside [t_min, t_max]
//            (else the double one). Otherwise (parallel and nearly parallel rays,
//            overflow): num and den in interval arithmetic with outward rounding (in
//            double for both scalar types); the sign of den, and whether a parallel ray
//            lies in the plane, are decided exactly when the intervals hold zero; t is
//            the interval quotient, unbounded on one side when |den| may be tiny.
//            certified — for float input, the conservative enclosure first: it decides
//            the verdict where it lies inside or outside [t_min, t_max], and gives t
//            rounded to the nearest float where both its ends round to one
//            (plane_nearest_float: on general-position input the double enclosure is far
//            narrower than a float step). Then straight-line code (plane_certified_common
//            on plane_pin): num and den as double-word sums of exact products in two
//            lanes, with bounds that are 0 when the sums are exact; t pinned between the
//            two neighbours of a candidate by a proven bound on the residual num - c·den
//            (detail/compensated.hpp) (then t against t_min and t_max is decided by
//            comparing c with them, and c is t faithfully rounded; for float the faithful
//            double rounded to nearest); a rough enclosure of t for nearly parallel rays
//            that miss; exact zeros (t == 0, a ray in or parallel to the plane) when the
//            sums are exact. No interval, and one branch (one more on the input's range,
//            taken only by input outside it). What it cannot decide goes to
//            the general path (plane_certified), which first pins double input outside
//            the pin's range (exponents beyond about ±450) on the input rescaled by
//            powers of two (plane_pin_rescaled); then intervals decide what they separate,
//            otherwise exact arithmetic (detail/exact.hpp): sign(den) and sign(num) are
//            degree 2, the position of t against t_min/t_max
//            sign(num - t_min·den)·sign(den) degree 3, each taken first from fixed-size
//            sums of error-free products (detail/affine_quotients.hpp, shared with the
//            oriented box), on the input rescaled by powers of two where it is outside
//            the Expansion type's range; t is rounded as the straight-line
//            path rounds it, by plane_nearest_float (float) and plane_pin first (so the two paths
//            answer alike bit for bit), next from the interval when it lies strictly
//            between the neighbours of its midpoint, else exactly. Before all this a
//            plain floating-point filter with derived bounds (plane_verdict_common)
//            decides the verdict where it can: verdict() answers from it alone, the full
//            query takes its misses.
#pragma once

#include <rayproof/detail/affine_quotients.hpp>
#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/compensated.hpp>
#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/detail/lanes.hpp>
#include <rayproof/detail/prepared.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/detail/validate.hpp>
#include <rayproof/prepared_ray.hpp>

#include <cmath>
#include <limits>

namespace rayproof::detail {

template <class T> using PreparedPlane = Prepared<Plane<T>>;  // detail/prepared.hpp

// Fast mode in full: the validity rules checked one by one, then the crossing with the
// parallel case decided on den == 0. What plane_fast_common declines, out of line.
template <class T> [[gnu::noinline, gnu::cold]] Hit<T> plane_fast_general(const Ray<T>& r, const Plane<T>& p) {
    if (!valid(p) || !valid(r)) return invalid_hit<T>();
    const T den = p.normal.dot(r.direction);
    const T num = p.offset - p.normal.dot(r.origin);
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

// Fast mode's common case: the same num, den and t, with the validity rules folded into
// one probe. num + den is finite only when every number of the plane and of the ray's
// origin and direction is finite (an infinite or NaN one makes its product with a
// normal component, or the offset, infinite or NaN: 0·inf is NaN), and den != 0 means
// neither the normal nor the direction is the zero vector (and the ray is not
// parallel). The range rules are three comparisons. A parallel ray, an overflow and
// invalid input go to plane_fast_general, which answers them by the contract's rules.
template <class T> RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> plane_fast_common(const Ray<T>& r, const Plane<T>& p) {
    const T den = p.normal.dot(r.direction);
    const T num = p.offset - p.normal.dot(r.origin);
    const T sum = num + den;
    if (!(int(sum - sum == 0) & int(den != 0) & int(valid_range(r)))) [[unlikely]]
        return std::nullopt;
    const T t = num / den;
    return hit_when(bool(int(r.t_min <= t) & int(t <= r.t_max)), t, t);
}

template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Hit<T> query(const R& ray, const PreparedPlane<T>& p, fast_t) {
    if constexpr (is_prepared_ray_v<R>)
        if (!p.ok || !valid(ray)) return invalid_hit<T>();
    const Ray<T>& r = ray_of(ray);
    return common_or_fallback(plane_fast_common(r, p.shape), [&, &s = p.shape] { return plane_fast_general(r, s); });
}

// The crossing t = N/D (N = offset - n·o, D = n·d): pinned between two adjacent doubles
// by detail/compensated.hpp (quotient_sums with the offset and the three products n_i·o_i
// in lane 0 and n_i·d_i in lane 1, then pin_quotient), with two more claims from the same
// sums, no interval and one jump (on the input's range). The certified straight-line
// path decides everything from it, and the general path rounds t with it first, so the
// two agree bit for bit.
// Range: n_i, o_i and d_i each 0 or of magnitude in [2^-450, 2^490], offset 0 or in
// [2^-450, 2^1000] (quotient_sums' conditions); double input outside it is pinned
// rescaled (plane_pin_rescaled) on the general path.
// Rough enclosure, for a t far from c's neighbours' reach (a nearly parallel ray, whose
// t the sums' bounds cannot pin to one ulp): when |c_N| + b_N <= 2^-20|s_N| and |c_D| +
// b_D < 2^-20|s_D|, N = s_N(1 + a) and D = s_D(1 + b) with |a|, |b| <= 2^-20(1 + u), and
// q = fl(s_N/s_D) = (s_N/s_D)(1 + e), |e| <= u, so t/q = (1 + a)/((1 + b)(1 + e)) lies
// within 2^-18 of 1: t is in [q - fl(2^-17|q|), q + fl(2^-17|q|)] rounded (each end's
// rounding is far below the 2^-18|q| of slack; |q| finite, checked), and D != 0.
// Exact zeros: D != 0 when |s_D| > 2·b_D (|D| >= (1 - u)|s_D| - b_D), and likewise N;
// D == 0 when b_D == 0 and s_D == 0 (the sum is then exact), and likewise N. So N == 0
// with D != 0 is t == 0 exactly, and D == 0 is a parallel ray: in the plane when N == 0,
// off it when N != 0.
struct PlanePin {
    double c;
    bool pinned;  // t lies strictly between c's two neighbours
    double rough_lo, rough_hi;
    bool rough;
    bool zero;      // t == 0 exactly (N == 0, D != 0)
    bool lying;     // D == 0 and N == 0: the ray lies in the plane (if n and d are nonzero)
    bool parallel;  // D == 0 and N != 0: parallel, off the plane
    bool ranged;    // the inputs were in range (else nothing above is claimed)
};
// The pin from the pairs a_j = (-n_j, n_j) and b_j = (o_j, d_j) and the offset f, as
// doubles. Input outside the range claims nothing and is not summed (its products would
// be subnormal, a microcode assist each): one jump, on input that rarely is.
RAYPROOF_ALWAYS_INLINE PlanePin plane_pin_of(double f, const lanes::D2 (&a)[3], const lanes::D2 (&b)[3]) {
    using namespace lanes;
    const M2 inputs = in_range(a[0]) & in_range(a[1]) & in_range(a[2]) & in_range(b[0]) & in_range(b[1]) &
                      in_range(b[2]) & in_range(make(f, 0.0), make(0x1p1000, 0.0));
    if (bits(inputs) != 3) [[unlikely]]
        return PlanePin{};
    const QuotientSums s = quotient_sums(make(f, 0.0), a, b, inputs);
    const PinnedQuotient x = pin_quotient(s);
    // The rough enclosure.
    const double nh = lane0(s.hi), nl = lane0(s.lo), dh = lane1(s.hi), dl = lane1(s.lo), bn = lane0(s.bound),
                 bd = lane1(s.bound);
    const double q = nh / dh, pad = 0x1p-17 * std::abs(q);
    const bool rough = int(s.ok) & int(std::abs(nl) + bn <= 0x1p-20 * std::abs(nh)) &
                       int(std::abs(dl) + bd < 0x1p-20 * std::abs(dh)) & int(pad <= std::numeric_limits<double>::max());
    // Exact zeros (bit 0: N, bit 1: D): z proven zero, nz proven nonzero.
    const int z = bits((s.bound == splat(0.0)) & (s.hi == splat(0.0))), nz = bits(abs(s.hi) > s.bound + s.bound);
    const bool zero = int(s.ok) & z & (nz >> 1), lying = int(s.ok) & int(z == 3), parallel = int(s.ok) & (z >> 1) & nz;
    return {x.c, x.pinned, q - pad, q + pad, rough, zero, lying, parallel, true};
}

// Double input outside the range above (a plane or ray scaled far up or down, as the
// exponent-range generators make them): the same pin on the input scaled by powers of
// two, n by 2^-kn, o by 2^-ko, d by 2^-kd and the offset by 2^-(kn + ko), k the exponent
// of each vector's largest component (ko from the offset when o = 0). Then N' = N·2^-(kn
// + ko) and D' = D·2^-(kn + kd), so t' = t·2^(kd - ko), and the zeros and signs of N and
// D are those of N' and D'. Each scaling is exact where its result is a normal double or
// 0 (times_pow2); a nonzero value that would become 0 declines, and a subnormal one is
// outside the range, so the pin claims nothing from inexact values. Back: c =
// c'·2^(ko - kd) is exact, and t strictly between the neighbours of c' means t strictly
// between those of c, when both are normal (|c'|, |c| >= 2^-1021, finite: the scaling
// maps adjacent normal doubles to adjacent doubles); otherwise nothing is pinned. The
// rough ends likewise, kept where both stay normal and finite. Out of line: only such
// input pays for it.
[[gnu::noinline]] inline PlanePin plane_pin_rescaled(const Ray<double>& r, const Plane<double>& p) {
    PlanePin none{};
    const double f = p.offset, n[3] = {p.normal[0], p.normal[1], p.normal[2]},
                 o[3] = {r.origin[0], r.origin[1], r.origin[2]}, d[3] = {r.direction[0], r.direction[1], r.direction[2]};
    const double all[10] = {n[0], n[1], n[2], o[0], o[1], o[2], d[0], d[1], d[2], f};
    for (const double v : all)
        if (!std::isfinite(v)) return none;
    const auto top = [](const double (&v)[3]) {
        const double a0 = std::abs(v[0]), a1 = std::abs(v[1]), a2 = std::abs(v[2]);
        const double m = a0 > a1 ? (a0 > a2 ? a0 : a2) : (a1 > a2 ? a1 : a2);
        return m == 0 ? std::optional<int>() : std::optional<int>(binary_exponent(m));
    };
    const std::optional<int> tn = top(n), to = top(o), td = top(d);
    if (!tn || !td) return none;  // n or d zero: invalid, the general path says so
    const int kn = *tn, kd = *td, ko = to ? *to : (f != 0 ? binary_exponent(f) - kn : 0);
    if (std::abs(ko) > 2044 || std::abs(kn + ko) > 2044) return none;
    bool lost = false;
    const auto scale = [&](double v, int k) {
        const double w = times_pow2(v, k);
        lost |= (w == 0) != (v == 0);
        return w;
    };
    double n2[3], o2[3], d2[3];
    for (int j = 0; j < 3; ++j) {
        n2[j] = scale(n[j], -kn);
        o2[j] = scale(o[j], -ko);
        d2[j] = scale(d[j], -kd);
    }
    const double f2 = scale(f, -(kn + ko));
    if (lost) return none;
    lanes::D2 a[3], b[3];
    for (int j = 0; j < 3; ++j) {
        a[j] = lanes::make(-n2[j], n2[j]);
        b[j] = lanes::make(o2[j], d2[j]);
    }
    PlanePin x = plane_pin_of(f2, a, b);
    const int back = ko - kd;
    if (std::abs(back) > 2044) {
        x.pinned = x.rough = false;
        return x;
    }
    constexpr double low = 0x1p-1021, big = std::numeric_limits<double>::max();
    const auto normal = [&](double v) { return std::abs(v) >= low && std::abs(v) <= big; };
    const double c1 = x.c;
    x.c = times_pow2(c1, back);
    x.pinned = x.pinned && normal(c1) && normal(x.c);
    x.rough_lo = times_pow2(x.rough_lo, back);
    x.rough_hi = times_pow2(x.rough_hi, back);
    x.rough = x.rough && normal(x.rough_lo) && normal(x.rough_hi);
    return x;
}

template <class T> RAYPROOF_ALWAYS_INLINE PlanePin plane_pin(const Ray<T>& r, const Plane<T>& p) {
    using namespace lanes;
    D2 a[3], b[3];
    for (int j = 0; j < 3; ++j) {
        const double n = double(p.normal[j]);
        a[j] = make(-n, n);
        b[j] = make(double(r.origin[j]), double(r.direction[j]));
    }
    return plane_pin_of(double(p.offset), a, b);
}

// plane_pin, and for double input outside its range the rescaled pin (float input is
// always in range): what the paths out of line use (the general path's decisions and
// its rounding of t), so that every path rounds t from the same c.
template <class T> PlanePin plane_pin_any(const Ray<T>& r, const Plane<T>& p) {
    const PlanePin x = plane_pin(r, p);
    if constexpr (std::is_same_v<T, double>)
        if (!x.ranged) return plane_pin_rescaled(r, p);
    return x;
}

// The certified verdict from a plain floating-point filter, before anything is pinned
// (the verdict query answers from it alone; the full query takes its misses and goes on
// to plane_pin for the rest). In double (exact for float inputs), -N = n·o - offset in
// lane 0 and D = n·d in lane 1 as ((-offset + p_0) + p_1) + p_2 with the products p_j =
// fl(a_j b_j) (negation being exact, N~ is minus lane 0): each lane is at most 4
// roundings from its sum, |N~ - N| <= gamma(4)·S_N with S_N = |offset| + Σ|n_j o_j|, and
// lane 1 at most 3 (its first addition, 0 + p_0, is exact): |D~ - D| <= gamma(3)·S_D,
// each plus at most 3·2^-1075 from products in the subnormal range. The bound is
// e = fl(K·S~) + eta with K = gamma(4) (as rounded, K >= gamma(4)(1 - u) > 4u) and eta =
// 2^-1022. S~ (the same sum of the |p_j|, rounded alike) is at least S(1 - gamma(5)) -
// 2^-1073, so
//     e >= gamma(4)·S·(1 - gamma(5))(1 - u)^3 + eta/2                  (K, fl(K·S~), + eta)
//     |D~ - D| <= gamma(3)·S_D + 3·2^-1075 < e_D       (gamma(4)(1 - gamma(5))(1 - u)^3 > gamma(3))
//     |N~ - N| <= gamma(4)·S_N + 3·2^-1075 <= (1 + 2^-49)·e_N    (1/((1 - gamma(5))(1 - u)^3) < 1 + 10u)
// K is tight for this derivation: e_D must exceed D's own bound, gamma(3)·S_D, after the
// roundings of S~, of K and of K·S~, and gamma(4) is the smallest gamma(n) that does
// (gamma(3)(1 - gamma(5))(1 - u)^3 < gamma(3)). With sigma = sign(D~), certain
// when |D~| > e_D, t = N/D lies in [t_min, t_max] iff A = sigma·N - t_min·|D| >= 0 and
// C = t_max·|D| - sigma·N >= 0, in lanes 0 and 1. They are computed as X~ = sigma·Y~
// with Y~ = fl((N~, -N~) + fl((-t_min, t_max)·D~)) (the sign bit of D~ moved onto Y~,
// exactly); rounding to nearest being symmetric, X~ = fl(fl(±sigma·N~) ∓ fl(limit·|D~|)),
// and for a finite X~ it is within
//     (1 + 2^-49)·e_N + |limit|·e_D + 2u|P~| + u|N~| + 2^-1075
// of A and C, P~ = fl(limit·D~) (the errors of N~ and D~, then one rounding for the
// product, one for the sum, 2^-1075 for a product in the subnormal range). |N~| <= S~_N
// and |D~| <= S~_D (the same sums of the absolute values, rounded alike: rounding is
// monotone and symmetric), and e >= fl(K·S~) >= 4u(1 - u)·S~ - 2^-1075 with e >= eta, so
// u|N~| < e_N/3.9, 2u|P~| <= 2u(1 + u)|limit|·S~_D < |limit|·e_D/1.9 and 2^-1075 <
// 2^-52·e_N: the error is below 1.53(e_N + |limit|·e_D), and E = 2·fl(e_N +
// fl(|limit|·e_D)) >= 1.99(e_N + |limit|·e_D) (two roundings, the product's underflow
// far below e_N, the doubling exact) covers it. So X~ >= E
// proves the condition and X~ < -E disproves it. Only for a finite X~: an infinite one
// from a finite limit is an overflow (of the product or of the sum), which bounds
// nothing (A can have either sign then), and decides nothing. An infinite limit (t_min = -inf, t_max = +inf) holds
// by itself (D != 0), and is taken as holding. Validity comes with the verdict: e
// finite means every number but t_min and t_max is finite (an infinite or NaN input
// makes S~ infinite or NaN), a certain sign of D means n != 0 and d != 0, and the
// limits are checked in the lanes as the Aabb's are (valid_range_lanes).
// verdict_declined when the filter cannot decide (D too close to 0, extreme exponents
// that overflow S~ or X~, a crossing within the bounds of a limit), else
// int(Verdict::miss) or int(Verdict::hit).
// Contraction (detail/eft.hpp): class C1. Fused, p_2 enters N~ and D~ unrounded, which
// the gamma(4) and gamma(3) counts allow; |N~| <= S~_N and |D~| <= S~_D then hold up to
// (1 + u)^2, inside the factors 3.9 and 1.9 above; a fused X~ or E has fewer roundings, and a
// fused X~ cannot overflow through its product, which only removes a case.
template <class T> RAYPROOF_ALWAYS_INLINE int plane_verdict_common(const Ray<T>& r, const Plane<T>& p) {
    using namespace lanes;
    constexpr double K = gamma<double>(4), eta = 0x1p-1022, inf = std::numeric_limits<double>::infinity();
    // The inputs as pairs of doubles (for float, from whole loads of the ray and the
    // plane: lanes::float_quad).
    double f;
    D2 n01, o01, d01, n22, od2, limit;  // od2 = (o_2, d_2)
    if constexpr (std::is_same_v<T, float>) {
        const Quad r0 = float_quad<8, 0>(r), r1 = float_quad<8, 4>(r), pl = float_quad<4, 0>(p);
        f = lane1(pl.hi);
        n01 = pl.lo, o01 = r0.lo, d01 = high_low(r0.hi, r1.lo), n22 = lows(pl.hi, pl.hi);
        od2 = low_high(r0.hi, r1.lo), limit = r1.hi;
    } else {
        f = p.offset;
        n01 = load2(p.normal.data()), o01 = load2(r.origin.data()), d01 = load2(r.direction.data());
        n22 = splat(p.normal[2]), od2 = make(r.origin[2], r.direction[2]), limit = make(r.t_min, r.t_max);
    }
    // The products (n_j o_j, n_j d_j) per axis, axes 0 and 1 from one product each.
    const D2 po = n01 * o01, pd = n01 * d01;
    const D2 x0 = lows(po, pd), x1 = highs(po, pd), x2 = n22 * od2;
    const D2 sum = ((make(-f, 0.0) + x0) + x1) + x2, mag = ((make(std::abs(f), 0.0) + abs(x0)) + abs(x1)) + abs(x2);
    const D2 e = mag * splat(K) + splat(eta), ND = negate_lane0(sum);  // (N~, D~)
    const D2 Ns = splat(lane0(ND)), Ds = splat(lane1(ND)), eN = splat(lane0(e)), eD = splat(lane1(e));
    const D2 lim = negate_lane0(limit);  // (-t_min, t_max)
    const D2 X = times_sign(negate_lane1(Ns) + lim * Ds, Ds);
    const D2 Q = eN + abs(limit) * eD, E = Q + Q;
    const M2 finite = abs(X) < splat(inf);
    const M2 holds = ((X >= E) & finite) | (lim == splat(inf)), fails = (X < -E) & finite;
    const D2 ordered = negate_lane1(limit);  // (t_min, -t_max)
    const M2 valid_all = (e < splat(inf)) & valid_range_lanes(ordered);
    const bool usable = int(bits(valid_all) == 3) & (bits(abs(ND) > e) >> 1);
    const bool hit = bits(holds) == 3, miss = bits(fails) != 0;
    return usable & (int(hit) | int(miss)) ? int(hit) : verdict_declined;
}

// An enclosure of t in the pbrt-v4 manner (plane_sums, plane_enclosure; the conservative
// answer's, and the certified float answer's): t~ = fl(N~·fl(1/D~)) from one plain
// evaluation of N = offset - n·o and D = n·d in double (and for the conservative float
// answer first in float, below), widened by a bound E derived for it.
// N~ and D~ are computed as in plane_verdict_common (-N~ = ((-offset + p_0) + p_1) + p_2,
// D~ = (p_0' + p_1') + p_2', p_j = fl(n_j o_j), p_j' = fl(n_j d_j)), with the bounds
// e = fl(fl(K·S~) + eta), K = gamma(4), S~ the same sums of the |terms|, eta = 2^-1022:
// |N~ - N| <= (1 + 2^-49)·e_N and |D~ - D| < e_D (the derivation is there; a fused
// evaluation has fewer roundings, class C1).
// When e_D <= 2^-20|D~| (so D != 0, and the ray is not nearly parallel), with q =
// N~/D~ exactly:
//     |t - q| = |(N - N~)D~ + N~(D~ - D)|/|D·D~| <= (e_N' + |q|·e_D)/(|D~| - e_D)
//             <= (1 + 2^-19)(e_N' + |q|·e_D)/|D~|,            e_N' = (1 + 2^-49)·e_N,
// and with inv = fl(1/D~) and t~ = fl(N~·inv), both normal or zero and finite (checked:
// |inv| in [2^-1022, max], t~ finite), |t~ - q| <= gamma(2)|q| + 2^-1075. Since |q| <=
// (1 + 2.01u)|t~| + 2^-1074, |N~|·|inv| >= (1 - u)|q| and |inv| >= (1 - u)/|D~|,
//     |t - t~| <= (1 + 2^-18)(e_N + |N~|·(e_D·|inv|))·|inv| + 2.01u|t~| + 2^-1073.
// The code takes E = fl(2·fl(fl(e_N·|inv|) + fl(|t~|·fl(fl(e_D·|inv|) + 3u))) + eta),
// each term in units of t, and |t~| standing for |N~|·|inv|: |t~| >= (1 - u)|N~|·|inv| -
// 2^-1075. The relative error of D~, r = fl(e_D·|inv|), is normal, as e_D >= (1 - u)K·S_D~
// (e_D >= eta covers K·S_D~ below 2^-1022) and |inv| >= (1 - u)/S_D~ (|D~| <= S_D~,
// rounding being monotone), so r >= (1 - u)^3·K: one rounding of u; and r <= 2^-19
// (e_D <= 2^-20|D~|). Every other product is in units of t, its underflow (2^-1075 each,
// times at most 1 + 3u) inside eta. (Grouped as fl(|N~|·e_D)·|inv|², that product
// underflowed to 0 for tiny normals, n near 2^-716, and the lost term was 2^18 ulps of
// t.) Six roundings of at most (1 - u) each, with the doubling exact, leave
//     E >= 1.99·(e_N + |N~|·(e_D·|inv|))·|inv| + 5.99u|t~| + eta/2,
// which covers the bound above with room for the two roundings of t~ ∓ E (u(|t~| + E),
// inside the 5.99u|t~| and the 0.99·(...)). So [fl(t~ - E), fl(t~ + E)] holds t: a hit
// of the exact answer (t in [t_min, t_max]) is a hit here, and the interval encloses it.
// An infinite or NaN E or t~ (an overflow: huge inputs, a nearly parallel ray) and
// everything the checks above exclude (a parallel ray, whose answer needs the exact
// sign of N) go to plane_conservative_general.
// The same checks prove the validity rules but those on t_min and t_max (valid_range,
// joined to them): |inv| in [2^-1022, max] makes D~ finite and nonzero, so n and d are
// nonzero; e_D <= 2^-20|D~| then makes e_D, S_D~ and every |n_j d_j| finite (not NaN:
// a comparison with NaN is false), hence n and d finite (a finite number times ±inf is
// ±inf or NaN, 0·inf included); a finite E makes e_N, S_N~, |offset| and every
// |n_j o_j| finite, hence offset and o finite. So an invalid input never answers here:
// it goes to plane_conservative_general, which checks the rules in full, and the
// certified query to its double-word path.
// For float input the conservative answer runs the same operations in float first
// (plane_sums<float>, plane_enclosure<float>: no conversion, and a float division), with
// u = 2^-24, eta = 2^-126, K = gamma(5) and the check e_D <= 2^-10|D~| (PlaneBounds).
// The products n_j·o_j are rounded now, and underflow (by at most 2^-150 each): each
// term of N~ has at most four roundings, so |N~ - N| <= gamma(4)·S + 2^-148 with S the
// exact sum of the |terms|, and S~ >= (1 - u)^4·S - 2^-148; e_N = fl(fl(K·S~) + eta) >=
// (1 - u)^6·K·S + (1 - u)·eta - 2^-147 > gamma(4)·S + 2^-148, so |N~ - N| <= e_N, and
// |D~ - D| <= e_D likewise. With e_D <= 2^-10|D~| and q = N~/D~,
//     |t - q| <= (e_N + |q|·e_D)/((1 - 2^-10)|D~|),  |t~ - q| <= 2.01u|q| + 2^-150,
// and |q| <= (1 + 2.01u)|t~| + 2^-149, |inv| >= (1 - u)/|D~|, e_D·|inv| normal (as
// above) and below 2^-9.9: |t - t~| <= 1.0011·B + 2^-149, B = e_N·|inv| + |t~|·(e_D·|inv|
// + 2.01u). The computed E >= 2(1 - u)^5·B + (1 - u)·eta - 2^-148 (five roundings, two
// products' underflow), which exceeds it by 0.99·B + 0.99·eta >= 1.99u|t~| + 0.99·eta,
// more than the roundings of t~ ∓ E (at most u(|t~| + E)). So [fl(t~ - E), fl(t~ + E)]
// holds t here too, and the checks prove the same validity rules.
// Products: the bound's are rounded() (class C3), so that whether E is finite and the
// enclosure's ends are the same bits wherever the query is inlined (the certified float
// path below decides from the double enclosure); the n_j·o_j and n_j·d_j are exact for
// float input in double (24-bit factors) and class C1 otherwise.
template <class C> struct PlaneBounds;  // the constants of the enclosure computed in C
template <> struct PlaneBounds<double> {
    static constexpr double K = gamma<double>(4), ratio = 0x1p-20;
};
template <> struct PlaneBounds<float> {
    static constexpr float K = gamma<float>(5), ratio = 0x1p-10f;
};
template <class C> struct PlaneSums {
    C num, den, en, ed;  // N~, D~, e_N, e_D
};
template <class C, class T> RAYPROOF_ALWAYS_INLINE PlaneSums<C> plane_sums(const Ray<T>& r, const Plane<T>& p) {
    static_assert(sizeof(C) >= sizeof(T), "the sums are computed in T or wider");
    constexpr C K = PlaneBounds<C>::K, eta = std::numeric_limits<C>::min();
    const C n0 = p.normal[0], n1 = p.normal[1], n2 = p.normal[2], f = p.offset;
    const C po0 = n0 * C(r.origin[0]), po1 = n1 * C(r.origin[1]), po2 = n2 * C(r.origin[2]);
    const C pd0 = n0 * C(r.direction[0]), pd1 = n1 * C(r.direction[1]), pd2 = n2 * C(r.direction[2]);
    const C num = -(((-f + po0) + po1) + po2), den = (pd0 + pd1) + pd2;
    const C sn = ((std::abs(f) + std::abs(po0)) + std::abs(po1)) + std::abs(po2);
    const C sd = (std::abs(pd0) + std::abs(pd1)) + std::abs(pd2);
    return {num, den, rounded(K * sn) + eta, rounded(K * sd) + eta};
}
template <class C> struct PlaneEnclosure {
    C lo, hi;  // [fl(t~ - E), fl(t~ + E)], which holds t when ok
    bool ok;   // E finite, e_D <= ratio·|D~|, |inv| in [eta, max]
};
template <class C> RAYPROOF_ALWAYS_INLINE PlaneEnclosure<C> plane_enclosure(const PlaneSums<C>& x) {
    constexpr C eta = std::numeric_limits<C>::min(), u = unit_roundoff<C>, big = std::numeric_limits<C>::max();
    const C inv = 1 / x.den, ai = std::abs(inv);
    const C t = rounded(x.num * inv);
    const C rel = rounded(x.ed * ai) + 3 * u;  // D~'s relative error (never subnormal), t~'s roundings
    const C bound = 2 * (rounded(x.en * ai) + rounded(std::abs(t) * rel)) + eta;
    const bool ok = int(x.ed <= PlaneBounds<C>::ratio * std::abs(x.den)) & int(ai >= eta) & int(ai <= big) &
                    int(bound <= big);  // false for NaN; a finite bound needs a finite t
    return {rounded(t - bound), rounded(t + bound), ok};
}

// The certified float answer from the enclosure: t rounded to the nearest float where
// both ends round to one (nearest_float). Every product behind lo and hi is exact or
// rounded() (plane_sums, plane_enclosure), so whether it answers is the same wherever it
// is inlined; the general path tries it first too (PlaneCrossing::faithful), so the two
// paths answer alike bit for bit.
RAYPROOF_ALWAYS_INLINE Pinned<float> plane_nearest_float(const PlaneEnclosure<double>& e) {
    return nearest_float(e.lo, e.hi, e.ok);
}

// The crossing as an affine quotient (detail/affine_quotients.hpp): one row, the
// normal, c = 0 and h_0 = -offset, so that side 0's (-h_0 - n·o)/(n·d) is
// (offset - n·o)/(n·d).
template <class T> AffineValues<1> plane_values(const Ray<T>& r, const Plane<T>& p) {
    AffineValues<1> v;
    for (int j = 0; j < 3; ++j) {
        v.o[j] = double(r.origin[j]);
        v.c[j] = 0;
        v.d[j] = double(r.direction[j]);
        v.a[0][j] = double(p.normal[j]);
    }
    v.h[0] = -double(p.offset);
    return v;
}

// The crossing t = num/den, num = offset - n·o, den = n·d, with interval enclosures
// and the exact values on demand: a source of exact quotients (detail/certified.hpp),
// for exact_compare and exact_faithful (axis 0, side 0 only), as the Obb's frame is, by
// AffineSource (num, den, safe, quick_compare, quick_faithful, scaled).
template <class T> class PlaneCrossing : public AffineSource<1, PlaneCrossing<T>> {
    using Source = AffineSource<1, PlaneCrossing<T>>;
    friend Source;

public:
    PlaneCrossing(const Ray<T>& r, const Plane<T>& p) : Source(std::is_same_v<T, float>), r_(&r), p_(&p) {
        Interval<double> n(double(p.offset)), d(0.0);
        for (int j = 0; j < 3; ++j) {
            const Interval<double> nj(double(p.normal[j]));
            n = n - times_point(nj, double(r.origin[j]));
            d = d + times_point(nj, double(r.direction[j]));
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
    // The same decisions without the interval filter (the exact stage alone), from
    // AffineSource's exact signs.
    int den_sign_exact() const { return this->exact_den_sign(0); }
    bool in_plane_exact() const { return this->exact_num_sign(0, 0) == 0; }
    Interval<double> enclose() const { return divide_signed(num_, den_, sden_); }
    // t faithfully rounded to T, given its enclosure t (den_sign() != 0), as the
    // straight-line path rounds it: for float by plane_nearest_float first; by plane_pin
    // next (for float the faithful double rounded to nearest, see faithful_to; +0 for t
    // == 0 exactly); next from the interval when it pins one float; else exactly
    // (went_exact is then set).
    T faithful(const Interval<double>& t, bool& went_exact) const {
        if constexpr (std::is_same_v<T, float>) {
            const Pinned<float> f = plane_nearest_float(plane_enclosure(plane_sums<double>(*r_, *p_)));
            if (f.ok) return f.t;
        }
        return faithful_after_nearest(t, went_exact);
    }
    // The same from its second step on: for a caller that tried plane_nearest_float
    // itself (poly_faithful), which would otherwise compute the enclosure twice.
    T faithful_after_nearest(const Interval<double>& t, bool& went_exact) const {
        const PlanePin x = plane_pin_any(*r_, *p_);
        if (x.pinned) return faithful_to<T>(x.c);
        if (x.zero) return T(0);
        if (const std::optional<T> f = faithful_from_enclosure<T>(t)) return *f;
        RAYPROOF_COUNT_EXACT(went_exact);
        return exact_faithful<T>(*this, 0, 0);
    }

private:
    AffineValues<1> affine_values() const { return plane_values(*r_, *p_); }
    const Ray<T>* r_;
    const Plane<T>* p_;
    Interval<double> num_, den_;
    int sden_;
};

static_assert(ExactQuotients<PlaneCrossing<float>> && ExactQuotients<PlaneCrossing<double>>);

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

// The conservative answer by interval arithmetic per operation, with exact signs where
// the intervals hold 0: what plane_conservative_common declines (parallel and nearly
// parallel rays, extreme exponents, and every invalid input), out of line. The validity
// rules are checked here, in full (the common path proves them when it answers).
template <class T> [[gnu::noinline, gnu::cold]] Hit<T> plane_conservative_general(const Ray<T>& r, const Plane<T>& p) {
    if (!valid(p) || !valid(r)) return invalid_hit<T>();
    const PlaneCrossing<T> x(r, p);
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

// The conservative answer: the enclosure (plane_enclosure) in double, clamped to [t_min,
// t_max] and rounded outward to T (outward_to), its verdict decided on the enclosure
// itself. For float input the enclosure in float first, which answers where it lies
// inside [t_min, t_max] (a hit, its ends t_enter and t_exit) or outside it (a miss); one
// that straddles t_min or t_max (t within some float steps of it, more on
// ill-conditioned input: float's bound is some 2^29 times double's) goes on to the
// double enclosure, so that the float path makes no false hit the double one would not.
// Its ends are wider than the double enclosure's (two float steps from the exact value on
// general input): on the `general` cases 37 float steps at the median, 1316 at the 99th
// percentile (more for an origin near the plane, where |N~| is small against its bound).
// What the enclosures' checks exclude goes to plane_conservative_general.
// On input whose products are subnormal in float the float stage pays a microcode assist
// per such operation (extreme input: 88 ns a query against 9 on uniform; fast float pays
// the same, 54 ns); a check that keeps it off inputs outside [2^-32, 2^32] was measured
// (extreme 21-25 ns) and not taken: it cost 20-30 % on uniform input, where every
// vector instruction adds to the throughput.
template <class T>
RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> plane_conservative_common(const Ray<T>& r, const Plane<T>& p) {
    if constexpr (std::is_same_v<T, float>) {
        const PlaneEnclosure<float> e = plane_enclosure(plane_sums<float>(r, p));
        const bool inside = int(e.lo >= r.t_min) & int(e.hi <= r.t_max),
                   outside = int(e.hi < r.t_min) | int(e.lo > r.t_max);
        if (int(e.ok) & int(valid_range(r)) & (int(inside) | int(outside))) [[likely]]
            return hit_when(inside, e.lo, e.hi);
    }
    const PlaneEnclosure<double> e = plane_enclosure(plane_sums<double>(r, p));
    if (!(int(e.ok) & int(valid_range(r)))) [[unlikely]]
        return std::nullopt;
    const OutwardEnds<T> ends = outward_to<T>(e.lo, e.hi, r.t_min, r.t_max);
    return hit_when(ends.meets, ends.lo, ends.hi);
}

template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Hit<T> query(const R& ray, const PreparedPlane<T>& p, conservative_t) {
    // A Ray's validity is proven by the common path or checked by the general one; a
    // prepared ray's flag (and the plane's) is one test.
    if constexpr (is_prepared_ray_v<R>)
        if (!p.ok || !valid(ray)) return invalid_hit<T>();
    const Ray<T>& r = ray_of(ray);
    return common_or_fallback(plane_conservative_common(r, p.shape), [&, &s = p.shape] { return plane_conservative_general(r, s); });
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

// The decisions from a pin x (plane_certified_common's, whose comment gives them), with
// nearest the float rounding of t where the enclosure gave one.
template <class T>
RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> plane_pin_answer(const Ray<T>& r, const Plane<T>& p, const PlanePin& x,
                                                              Pinned<T> nearest, bool rest_valid) {
    const double lo = double(r.t_min), hi = double(r.t_max);
    const bool crossing = int(x.pinned) & int(x.c > lo) & int(x.c < hi);
    const bool at_zero = int(x.zero) & int(lo <= 0) & int(hi >= 0);
    const bool miss = (int(x.pinned) & (int(x.c < lo) | int(x.c > hi))) |
                      (int(x.rough) & (int(x.rough_hi < lo) | int(x.rough_lo > hi))) |
                      (int(x.zero) & (int(lo > 0) | int(hi < 0)));
    Hit<T> h;
    if (rest_valid && (crossing || at_zero || miss)) {
        if (crossing || at_zero) {
            h.verdict = Verdict::hit;
            h.t_enter = h.t_exit = nearest.ok ? nearest.t : crossing ? faithful_to<T>(x.c) : T(0);
        }
        return h;
    }
    if (!(rest_valid && (x.lying || x.parallel))) return std::nullopt;
    if (!nonzero3(p.normal.data()) || !nonzero3(r.direction.data())) return std::nullopt;
    if (x.lying) {
        h.verdict = Verdict::hit;
        h.t_enter = r.t_min;
        h.t_exit = r.t_max;
    }
    return h;
}

// The straight-line path of the certified mode. For float input the conservative
// enclosure first: a hit when it lies inside [t_min, t_max] and t rounds to one float
// (plane_nearest_float, then the answer wherever this path hits), a miss when it lies
// outside. Then every decision from plane_pin. With t
// proven strictly between c's neighbours, t > t_min when c > t_min and t < t_max when c <
// t_max (a hit: t_min and t_max are doubles, so c > t_min means c's lower neighbour is
// at least t_min), t < t_min when c < t_min and t > t_max when c > t_max (a miss); a t
// whose rough enclosure lies outside [t_min, t_max] misses too; t == 0 exactly is
// compared as it is; a parallel ray misses, or hits on its whole range when it lies in
// the plane. The cases left (c equal to t_min or t_max), and anything plane_pin can
// neither pin, enclose nor decide exactly (a ray nearly in the plane, extreme
// exponents), go to the general path.
// Every answer but the parallel ones also proves most of the validity rules (every
// number but t_min and t_max finite, n and d nonzero: D != 0); the others come in as
// rest_valid, and a parallel answer checks n != 0 and d != 0 itself.
// A miss the verdict filter proves is answered at once (misses need no t).
template <class T>
RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> plane_certified_common(const Ray<T>& r, const Plane<T>& p,
                                                                    bool rest_valid = true) {
    Pinned<T> nearest{T(0), false};
    if constexpr (std::is_same_v<T, float>) {
        const double lo = double(r.t_min), hi = double(r.t_max);
        // The enclosure first (plane_enclosure: no double-word arithmetic), which decides
        // the verdict where it lies inside [t_min, t_max] or outside it, and rounds t to
        // the nearest float where it can (plane_nearest_float); its checks prove the
        // input valid but for t_min and t_max (rest_valid).
        // One branch, on whether it decided (nearly always); hit or miss is chosen
        // without a jump (hit_when: a coin toss on random rays).
        const PlaneEnclosure<double> e = plane_enclosure(plane_sums<double>(r, p));
        nearest = plane_nearest_float(e);
        const bool inside = int(e.lo >= lo) & int(e.hi <= hi) & int(nearest.ok),
                   outside = int(e.hi < lo) | int(e.lo > hi);
        if (int(rest_valid) & int(e.ok) & (int(inside) | int(outside))) [[likely]]
            return hit_when(inside, nearest.t, nearest.t);
    }
    if (plane_verdict_common(r, p) == int(Verdict::miss)) return Hit<T>{};
    return plane_pin_answer(r, p, plane_pin(r, p), nearest, rest_valid);
}

// Valid input only. Double input outside plane_pin's range (which the straight-line path
// declines) is first decided as that path decides, from the rescaled pin.
template <class T> [[gnu::noinline, gnu::cold]] Hit<T> plane_certified_general(const Ray<T>& r, const Plane<T>& p) {
    if constexpr (std::is_same_v<T, double>)
        if (!plane_pin(r, p).ranged)
            if (const std::optional<Hit<T>> h = plane_pin_answer(r, p, plane_pin_rescaled(r, p), {}, true)) return *h;
    return plane_certified(r, PlaneCrossing<T>(r, p));
}

// What the straight-line path declines: validated in full, then the general path.
// (A prepared ray's validity is decided already.)
template <class R, class T>
    requires RayOrPrepared<R, T>
[[gnu::noinline, gnu::cold]] Hit<T> plane_certified_declined(const R& r, const Plane<T>& p) {
    return answer_if_valid(r, p, [&] { return plane_certified_general(ray_of(r), p); });
}

template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Hit<T> query(const R& ray, const PreparedPlane<T>& p, certified_t) {
    // The straight-line path answers only where its pinned crossing has proven the plane
    // and the ray valid apart from t_min and t_max (see plane_certified_common), so it
    // takes those as a flag; anything it declines is validated in full first. A prepared
    // ray gives its whole validity as the flag: where it is false the ray is invalid,
    // the path proves nothing then, and the answer is Verdict::invalid either way.
    const Ray<T>& r = ray_of(ray);
    bool rest_valid;
    if constexpr (is_prepared_ray_v<R>)
        rest_valid = ray.valid();
    else
        rest_valid = valid_range(r);
    return common_or_general(plane_certified_common(r, p.shape, rest_valid),
                             [&, &s = p.shape] { return plane_certified_declined(ray, s); });
}

// What the verdict filter declines: the full query's verdict, out of line.
template <class T> [[gnu::noinline, gnu::cold]] Verdict plane_verdict_declined(const Ray<T>& r, const Plane<T>& p) {
    return query(r, prepare(p), certified).verdict;
}

// The certified verdict alone: the filter's verdict (which proves the input valid),
// else the full query's. The prepared flag is not consulted on the filter's path.
template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Verdict verdict_query(const R& ray, const PreparedPlane<T>& p, certified_t) {
    const Ray<T>& r = ray_of(ray);
    return verdict_or(plane_verdict_common(r, p.shape), [&, &s = p.shape] { return plane_verdict_declined(r, s); });
}

}  // namespace rayproof::detail
