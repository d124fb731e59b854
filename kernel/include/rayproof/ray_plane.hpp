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
//            certified — straight-line code first (plane_certified_common on
//            plane_pin): num and den as double-word sums of exact products in two lanes,
//            with bounds that are 0 when the sums are exact; t pinned between the two
//            neighbours of a candidate by a proven bound on the residual num - c·den
//            (then t against t_min and t_max is decided by comparing c with them, and c
//            is t faithfully rounded; for float the faithful double rounded to nearest);
//            a rough enclosure of t for nearly parallel rays that miss; exact zeros
//            (t == 0, a ray in or parallel to the plane) when the sums are exact. No
//            interval and one branch. What it cannot decide goes to the general path
//            (plane_certified): intervals decide what they separate, otherwise exact
//            arithmetic (detail/exact.hpp): sign(den) and sign(num) are degree 2, the
//            position of t against t_min/t_max sign(num - t_min·den)·sign(den) degree
//            3; t is rounded by plane_pin first (so the two paths answer alike bit for
//            bit), next from the interval when it lies strictly between the neighbours
//            of its midpoint, else exactly.
#pragma once

#include <rayproof/detail/lanes.hpp>
#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/detail/slab_certified.hpp>
#include <rayproof/detail/validate.hpp>

#include <bit>
#include <cstdint>

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

// The crossing t = N/D (N = offset - n·o, D = n·d) pinned between two adjacent doubles,
// with no interval and no branch: pinned means that t lies strictly between the two
// neighbours of c, so c is one of the two doubles enclosing t (t itself when t is a
// double), and D != 0. The certified straight-line path decides everything from it, and
// the general path rounds t with it first, so the two agree bit for bit.
//
// Sums: N (lane 0) and D (lane 1) side by side (detail/lanes.hpp), each a sum of four
// doubles, offset (or 0) and three products held exactly as hi + lo (exact_product).
// s cascades offset and the three high parts by two_sum, whose errors q_i are exact;
// c = fl(q_1 + lo_1 + q_2 + lo_2 + q_3 + lo_3) in that order (Sum2 of Ogita, Rump and
// Oishi, "Accurate sum and dot product", SIAM J. Sci. Comput. 26(6), 2005). Then N =
// s + Σq_i + Σlo_i exactly, and the recursive sum c of the six small terms is off by at
// most gamma(5)·S, S = Σ|q_i| + Σ|lo_i| (Higham, ASNA, 4.2); bound = fl(2·gamma(5)·fl(S))
// covers it (fl(S) >= (1 - gamma(5))·S; the doubling covers that and the product's
// rounding). The bound is 0 exactly when every small term is, and then s + c is the
// exact sum: integer-like input (exact products) is decided exactly, zeros included.
// s and c are then renormalized by fast_two_sum (exact when |c| <= |s| or s == 0,
// checked; the same exact sum, its high part fl(s + c), |c| <= u|s| after it): below,
// s_N + c_N and s_D + c_D name the renormalized pairs, b_N and b_D their bounds.
// Range: n_i, o_i and d_i each 0 or of magnitude in [2^-450, 2^490], offset 0 or in
// [2^-450, 2^1000]. Then every product is exact (exact_product's conditions: a nonzero
// product is at least 2^-900), nothing overflows (A < 2^1001), every term and partial
// sum is a multiple of 2^-1004 (so 0 or normal, and the additions' relative error bound
// holds), and a nonzero S is at least 2^-1004 (the bound's rounding, even subnormal,
// stays far inside the doubling's slack).
// Candidate: tt = fl(s_N/s_D) cut to 26 bits and s_D = d26 + d27 (d26 cut the same way,
// d27 = s_D - d26 exact, at most 27 bits): under the guards |tt| >= 2^-490 and |s_D| >=
// 2^-500 (both finite; |s_D| < 2^981 by the range) the products tt·d26 and tt·d27 (at
// most 52 and 53 bits, the last of weight at least 2^-1067, and near |s_N| < 2^1001)
// are exact, and
//     x1 = fl(s_N - tt·d26), x2 = fl(x1 - tt·d27), e1 = fl(tt·c_D), x3 = fl(c_N - e1),
//     rho = fl(x2 + x3)
// give R(tt) = N - tt·D = rho + eps_N - tt·eps_D + E1, |E1| <= u(|x1| + |x2| + |e1| + |x3|
// + |rho|) (each rounding to nearest is off by at most u times its result, plus 2^-1075
// where it underflows); eps_N and eps_D are the sums' errors (bounds b_N and b_D). The
// candidate is c = fl(tt + fl(rho·fl(1/s_D))). Its accuracy is not relied on (any
// candidate may be tried, the proof below decides); for the record, x1 is exact by
// Sterbenz and c is nearly always t correctly rounded.
// Proof: t lies strictly between c's neighbours when |t - c| < u|c|: for |c| = m·2^e,
// m in [1, 2), the gap below c is 2^(e-52), or 2^(e-53) when m == 1, and the gap above
// 2^(e-52), both at least u|c| = m·2^(e-53) (subnormal c: both gaps 2^-1074 > u|c|; c ==
// 0 never passes). And |t - c| = |R(c)|/|D| with R(g) = N - g·D. From R(tt):
//     R(c) = R(tt) - (c - tt)·D = rho + E1 + eps_N - c·eps_D - (c - tt)·(s_D + c_D),
// and with w = fl(fl(c - tt)·s_D), v = fl(rho - w):
//     |R(c) - v| <= b_N + u(|x1| + |x2| + |e1| + |x3| + |rho|) + |c|·b_D + 5u|w| + u|v| =: e
// (the rounding of c - tt, the c_D left out (|c_D| <= u|s_D|) and the product's rounding
// together at most 3u(1 + 3u)|w|, and the last subtraction's), while |D| >= (1 - u)|s_D|
// - b_D. The test lhs < rhs with
//     lhs = fl(fl(fl(|v|·(1 + 2u)) + fl(2e + 2^-1020))·(1 + 2^-40)),
//     rhs = fl(fl(u|c|)·fl(fl(|s_D|·(1 - 2^-40)) - 4·b_D))
// proves |R(c)| < u|c|·|D|: lhs is at least |v| + e (the doubling of e covers the
// roundings of its own evaluation, 2^-1020 every underflow, the factor 1 + 2^-40 the
// last roundings), rhs at most u|c|((1 - u)|s_D| - b_D) (u|c| is exact for |c| >=
// 2^-900, checked; the factor 1 - 2^-40 and 4·b_D absorb the three roundings). A NaN or
// an infinity anywhere (an overflow, a candidate of 0/0) fails the comparison.
// Rough enclosure, for a t far from c's neighbours' reach (a nearly parallel ray, whose
// t the sums' bounds cannot pin to one ulp): when |c_N| + b_N <= 2^-20|s_N| and |c_D| +
// b_D < 2^-20|s_D|, N = s_N(1 + a) and D = s_D(1 + b) with |a|, |b| <= 2^-20(1 + u), and
// q = fl(s_N/s_D) = (s_N/s_D)(1 + e), |e| <= u, so t/q = (1 + a)/((1 + b)(1 +
// e)) lies within 2^-18 of 1: t is in [q - fl(2^-17|q|), q + fl(2^-17|q|)] rounded
// (each end's rounding is far below the 2^-18|q| of slack), and D != 0.
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
};
template <class T> RAYPROOF_ALWAYS_INLINE PlanePin plane_pin(const Ray<T>& r, const Plane<T>& p) {
    using namespace lanes;
    constexpr double K = 2 * exact_impl::gamma(5), u = exact_impl::u;
    const double f = double(p.offset);
    double n[3], o[3], d[3];
    for (int j = 0; j < 3; ++j) {
        n[j] = double(p.normal[j]);
        o[j] = double(r.origin[j]);
        d[j] = double(r.direction[j]);
    }
    const auto in_range = [](D2 x, D2 top) {  // each lane 0 or of magnitude in [2^-450, top] (false for NaN)
        const D2 a = abs(x);
        return ((a >= splat(0x1p-450)) | (a == splat(0.0))) & (a <= top);
    };
    const D2 top = splat(0x1p490);
    const M2 inputs = in_range(make(n[0], n[1]), top) & in_range(make(n[2], f), make(0x1p490, 0x1p1000)) &
                      in_range(make(o[0], o[1]), top) & in_range(make(o[2], d[0]), top) & in_range(make(d[1], d[2]), top);
    D2 s = make(f, 0.0), c = splat(0.0), E = splat(0.0);
    for (int j = 0; j < 3; ++j) {
        const Product q = exact_product(make(-n[j], n[j]), make(o[j], d[j]));
        const SumOf<D2> x = two_sum(s, q.hi);
        s = x.hi;
        c = (c + x.lo) + q.lo;
        E = (E + abs(x.lo)) + abs(q.lo);
    }
    const D2 bound = E * splat(K);
    // s + c renormalized by fast_two_sum, exact when |c| <= |s| or s == 0 (checked): s
    // alone is 0 when the high parts cancel.
    const D2 hi = s + c, lo = c - (hi - s);
    const M2 renormal = (abs(c) <= abs(s)) | (s == splat(0.0));
    const double nh = lane0(hi), nl = lane0(lo), dh = lane1(hi), dl = lane1(lo), bn = lane0(bound),
                 bd = lane1(bound);
    // R(tt) and the candidate.
    const double c0 = nh / dh, inv = 1 / dh, tt = high26(c0), d26 = high26(dh);
    const double x1 = nh - tt * d26, x2 = x1 - tt * (dh - d26), e1 = tt * dl, x3 = nl - e1, rho = x2 + x3;
    const double cand = tt + rho * inv;
    const D2 scale = abs(make(tt, dh));
    const M2 scale_ok = (scale >= make(0x1p-490, 0x1p-500)) & (scale <= splat(std::numeric_limits<double>::max()));
    // R(cand) ~ v within e, and the test |t - cand| < u|cand| (see the proof above).
    const double ac = std::abs(cand), w = (cand - tt) * dh, v = rho - w;
    const double e_fixed = (bn + u * ((((std::abs(x1) + std::abs(x2)) + std::abs(e1)) + std::abs(x3)) + std::abs(rho))) +
                           (ac * bd + 5 * u * std::abs(w));
    const double lhs = (std::abs(v) * (1 + 2 * u) + (2 * e_fixed + 0x1p-1020)) * (1 + 0x1p-40);
    const double rhs = (u * ac) * (std::abs(dh) * (1 - 0x1p-40) - 4 * bd);
    const bool in = bits(inputs) == 3;
    const bool pinned = int(in) & int(bits(renormal & scale_ok) == 3) & int(ac >= 0x1p-900) & int(lhs < rhs);
    // The rough enclosure.
    const bool sums = int(in) & int(bits(renormal) == 3);
    const double pad = 0x1p-17 * std::abs(c0);
    const bool rough = int(sums) & int(std::abs(nl) + bn <= 0x1p-20 * std::abs(nh)) &
                       int(std::abs(dl) + bd < 0x1p-20 * std::abs(dh)) & int(pad <= std::numeric_limits<double>::max());
    // Exact zeros (bit 0: N, bit 1: D): z proven zero, nz proven nonzero.
    const int z = bits((bound == splat(0.0)) & (hi == splat(0.0))), nz = bits(abs(hi) > bound + bound);
    const bool zero = int(sums) & z & (nz >> 1), lying = int(sums) & int(z == 3), parallel = int(sums) & (z >> 1) & nz;
    return {cand, pinned, c0 - pad, c0 + pad, rough, zero, lying, parallel};
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
    // t faithfully rounded to T, given its enclosure t (den_sign() != 0): by plane_pin
    // first (the straight-line path's rounding; for float the faithful double rounded to
    // nearest, see faithful_to; +0 for t == 0 exactly); next from the enclosure when it
    // pins one float; else exactly (went_exact is then set).
    T faithful(const Interval<double>& t, bool& went_exact) const {
        const PlanePin x = plane_pin(*r_, *p_);
        if (x.pinned) return faithful_to<T>(x.c);
        if (x.zero) return T(0);
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

// The straight-line path of the certified mode: every decision from plane_pin. With t
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
template <class T>
RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> plane_certified_common(const Ray<T>& r, const Plane<T>& p,
                                                                    bool rest_valid = true) {
    const PlanePin x = plane_pin(r, p);
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
            h.t_enter = h.t_exit = crossing ? faithful_to<T>(x.c) : T(0);
        }
        return h;
    }
    if (!(rest_valid && (x.lying || x.parallel))) return std::nullopt;
    const auto nonzero = [](const Vec3<T>& v) { return v[0] != 0 || v[1] != 0 || v[2] != 0; };
    if (!nonzero(p.normal) || !nonzero(r.direction)) return std::nullopt;
    if (x.lying) {
        h.verdict = Verdict::hit;
        h.t_enter = r.t_min;
        h.t_exit = r.t_max;
    }
    return h;
}

template <class T> [[gnu::noinline, gnu::cold]] Hit<T> plane_certified_general(const Ray<T>& r, const Plane<T>& p) {
    return plane_certified(r, PlaneCrossing<T>(r, p));
}

template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> query(const Ray<T>& r, const PreparedPlane<T>& p, certified_t) {
    // The straight-line path answers only where its pinned crossing has proven the plane
    // and the ray valid apart from t_min and t_max (see plane_certified_common), so it
    // takes those as a flag; anything it declines is validated in full first.
    const bool rest_valid = valid_range(r);
    return common_or_general(plane_certified_common(r, p.plane, rest_valid), [&] {
        return !p.ok || !valid(r) ? invalid_hit<T>() : plane_certified_general(r, p.plane);
    });
}

}  // namespace rayproof::detail
