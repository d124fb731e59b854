// rayproof/ray_aabb.hpp — ray against axis-aligned box.
//
// Shape:     the closed solid box { p : lo <= p <= hi } (componentwise). A flat box
//            (lo_i == hi_i) is valid and is hit only by rays that touch that plane.
// Query:     the set of t in [t_min, t_max] with o + t·d in the box: a closed interval
//            [t_enter, t_exit] or empty. face = 2·axis + side of the entry plane (side 0:
//            lo, the -axis side; 1: hi), -1 when the point at t_min is already in the box;
//            ties (edges, corners) go to the lowest axis.
// Algorithm: the slab method (Kay & Kajiya, SIGGRAPH 1986) in the branch-free form with
//            reciprocal directions (Williams et al., JGT 2005), see detail/slab_fast.hpp.
// Degenerate cases: d_i = ±0 (the ray is parallel to slab i: it hits iff lo_i <= o_i <=
//            hi_i, including o_i exactly on a plane, where the naive (lo_i - o_i)/d_i is
//            0/0); origin inside (t_enter = t_min, face -1); grazing an edge or a corner
//            (t_enter == t_exit); flat boxes.
// Modes:     fast — two roundings per slab value: each computed slab value is the exact
//            one times (1+δ), |δ| <= gamma(2) = 2u/(1-2u), while no value over- or
//            underflows; the verdict can be wrong when the entry and exit values are
//            that close, and is measured, not promised (rayproof-audit).
//            conservative — each slab value t~ = fl(fl(p - o)·fl(1/d)), computed in
//            double (exactly representable inputs for float), is three roundings from
//            t: |t~ - t| <= gamma(3)|t| <= gamma(3)/(1 - gamma(3))|t~|; the enclosure
//            [t~ - K|t~|, t~ + K|t~|] with K = 2·gamma(3) covers that and the two
//            roundings of its own ends (K|t~|(1 - u) - u|t~|(1 + K) >= gamma(3)/(1 -
//            gamma(3))|t~|). Valid while 1/d is normal and t~ is finite and normal (or
//            t~ == 0 from p == o); otherwise an outward-rounded interval division is used.
//            Parallel axes are decided exactly (comparisons of floats).
//            certified — the same enclosures decide every comparison they separate;
//            overlapping ones are decided by exact arithmetic (detail/exact.hpp). The
//            winning slab value (p - o)/d is rounded faithfully by one compensated
//            correction of its approximation t~: s + e = p - o exactly (two_sum),
//            t' = fl(t~ + fl(fl(e - fl(t~·d - s))·fl(1/d))); the correction is off by a
//            tiny fraction of a gap, so t' is one of the two floats enclosing t and is
//            t when t is representable (faithful_slab_value has the derivation). Valid
//            while |s|, |t~| >= 2^-960 (nothing underflows); otherwise exact
//            arithmetic decides. The common case runs as straight-line code
//            (aabb_certified_common) and hands anything it cannot prove to the general
//            path.
//            For float, every step runs in double: a faithfully rounded double rounded
//            to nearest float is a faithfully rounded float.
#pragma once

#include <rayproof/detail/slab_certified.hpp>
#include <rayproof/detail/slab_fast.hpp>
#include <rayproof/detail/validate.hpp>

namespace rayproof::detail {

// A box with its validity decided once (the batch form prepares once per call).
template <class T> struct PreparedAabb {
    Aabb<T> box;
    bool ok;
};
template <class T> PreparedAabb<T> prepare(const Aabb<T>& b) { return {b, valid(b)}; }

template <class T> Hit<T> query(const Ray<T>& r, const PreparedAabb<T>& p, fast_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    return slab_fast(r.origin.data(), r.direction.data(), p.box.lo.data(), p.box.hi.data(), r.t_min, r.t_max);
}

// x·y - z with one rounding: the fused multiply-add where the target has one, else
// Dekker's exact product (x·y = ph + pl, Veltkamp splitting; exact when nothing
// overflows or underflows) followed by (ph - z) - pl, where ph - z is exact
// (Sterbenz: ph and z are within a factor 2 of each other in the use below) and the
// last subtraction rounds once.
RAYPROOF_ALWAYS_INLINE double mul_sub(double x, double y, double z) {
#if defined(__FMA__) || defined(__FP_FAST_FMA)
    return std::fma(x, y, -z);
#else
    constexpr double split = 134217729.0;  // 2^27 + 1
    const double cx = split * x, cy = split * y;
    const double xh = cx - (cx - x), xl = x - xh, yh = cy - (cy - y), yl = y - yh;
    const double ph = x * y;
    const double pl = ((xh * yh - ph) + xh * yl + xl * yh) + xl * yl;
    return (ph - z) + pl;
#endif
}

// (p - o)/d faithfully rounded to T by one compensated correction of an approximation
// t~ with |t~ - t| <= gamma(3)|t| (as the slab values are computed), or nothing when
// the conditions below fail (then exact arithmetic rounds).
// s + e = p - o exactly (two_sum), so t = (s + e)/d and t - t~ = (s - t~·d + e)/d.
// r~ = fl(t~·d - s) (one rounding) is off by at most u|s - t~·d| <= u·4 ulp(t)|d|;
// delta = fl(fl(e - r~)·fl(1/d)) then differs from t - t~ by at most about
// (u + gamma(3))·5 ulp(t), a tiny fraction of a gap, so RN(t~ + delta) is one of the
// two doubles enclosing t, and t itself when it is representable. Needs |s|, |t~| >=
// 2^-960 and 1/d normal (no underflow in r~ or delta), |t~|, |d| <= 2^995.
// faithful_slab_double is the correction in double, branch-free: {t', ok}; ok is false
// where the conditions above fail. p == o gives exactly +0 (ok). faithful_to rounds it
// to T.
struct FaithfulDouble {
    double t;
    bool ok;
};
RAYPROOF_ALWAYS_INLINE FaithfulDouble faithful_slab_double(double p, double o, double d, double approx, double inv) {
    const Pair se = two_sum(p, -o);
    // |d|, |t~| <= 2^995 also keeps Dekker's splitting (no hardware fma) from overflowing.
    // |s| <= 2^1020 also keeps two_sum itself exact (its intermediate s - a overflows
    // within an ulp of the largest double, giving a NaN error term).
    const double as = std::abs(se.hi), at = std::abs(approx), ai = std::abs(inv);
    const bool in_range = int(as >= 0x1p-960) & int(as <= 0x1p1020) & int(at >= 0x1p-960) & int(at <= 0x1p995) &
                          int(ai >= 0x1p-1022) & int(ai <= std::numeric_limits<double>::max()) &
                          int(std::abs(d) <= 0x1p995);
    const double t = approx + (se.lo - mul_sub(approx, d, se.hi)) * inv;
    const bool zero = se.hi == 0;
    return {zero ? 0.0 : t, bool(int(in_range) | int(zero))};
}
// The faithfully rounded double to T: a faithfully rounded double rounded to nearest T
// is a faithfully rounded T (the two T values enclosing t enclose the double); beyond
// the largest finite T the enclosing finite neighbour is answered, as exact_faithful
// does.
template <class T> T faithful_to(double t) {
    if constexpr (std::is_same_v<T, double>) {
        return t;
    } else {
        constexpr double big = std::numeric_limits<T>::max();
        return static_cast<T>(std::min(std::max(t, -big), big));
    }
}
template <class T> std::optional<T> faithful_slab_value(T p, T o, T d) {
    const double inv = 1.0 / double(d);
    const FaithfulDouble f = faithful_slab_double(double(p), double(o), double(d), (double(p) - double(o)) * inv, inv);
    if (!f.ok) return std::nullopt;
    return faithful_to<T>(f.t);
}

// The slab frame of an axis-aligned box (see detail/slab_certified.hpp): the slab
// values are (p - o_i)/d_i with p = lo_i (side 0) or hi_i (side 1).
template <class T> class AabbFrame {
public:
    AabbFrame(const Ray<T>& r, const Aabb<T>& b) : o_(r.origin.data()), d_(r.direction.data()), b_(&b) {
        // K = 2·gamma(3): see the header comment.
        constexpr double K = 2 * gamma<double>(3);
        ok_ = true;
        for (int i = 0; i < 3; ++i) {
            if (d_[i] == 0) continue;
            const double inv = 1.0 / double(d_[i]);
            ok_ &= std::abs(inv) >= std::numeric_limits<double>::min() && std::abs(inv) <= std::numeric_limits<double>::max();
            for (int side = 0; side < 2; ++side) {
                const double s = double(plane(i, side)) - double(o_[i]);
                const double t = s * inv;
                const double a = std::abs(t);
                ok_ &= (a >= 0x1p-1000 && a <= std::numeric_limits<double>::max()) || s == 0;
                t_[i][side] = t;
                e_[i][side] = a * K;
            }
        }
    }
    int den_sign(int i) const { return (d_[i] > 0) - (d_[i] < 0); }
    bool inside_parallel(int i) const { return b_->lo[i] <= o_[i] && o_[i] <= b_->hi[i]; }
    // Both are exact comparisons of floats already (the names the other frames use for
    // their exact stage).
    int den_sign_exact(int i) const { return den_sign(i); }
    bool inside_parallel_exact(int i) const { return inside_parallel(i); }
    Interval<double> enclose(int i, int side) const {
        if (ok_) return {t_[i][side] - e_[i][side], t_[i][side] + e_[i][side]};
        const double s = double(plane(i, side)) - double(o_[i]);
        return Interval<double>(step_down(s), step_up(s)) / Interval<double>(double(d_[i]));
    }
    template <class E> E num(int i, int side) const { return E(double(plane(i, side))) - E(double(o_[i])); }
    template <class E> E den(int i) const { return E(double(d_[i])); }
    bool safe() const {
        for (int i = 0; i < 3; ++i)
            if (!expansion_safe(o_[i]) || !expansion_safe(d_[i]) || !expansion_safe(b_->lo[i]) ||
                !expansion_safe(b_->hi[i]))
                return false;
        return true;
    }
    T faithful(int i, int side, const Interval<double>&, bool& went_exact) const {
        if (const std::optional<T> t = faithful_slab_value<T>(plane(i, side), o_[i], d_[i])) return *t;
        RAYPROOF_COUNT_EXACT(went_exact);
        return exact_faithful<T>(*this, i, side);
    }

private:
    T plane(int i, int side) const { return side ? b_->hi[i] : b_->lo[i]; }
    const T* o_;
    const T* d_;
    const Aabb<T>* b_;
    double t_[3][2], e_[3][2];
    bool ok_;
};

template <class T> Hit<T> query(const Ray<T>& r, const PreparedAabb<T>& p, conservative_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    return slab_conservative(AabbFrame<T>(r, p.box), r.t_min, r.t_max);
}

// The certified answer's common case in straight-line code: the slab values and their
// error bounds, the entry argmax and exit argmin as in fast mode, checks that the bounds
// separate every comparison that decided them, and the faithful rounding of the winning
// entry and exit values. Everything is computed branch-free (the verdict, the winning
// axes and the signs of d are as random as the rays); one well-predicted branch hands
// anything the checks cannot vouch for (close values, overflow, extreme exponents) to
// the general path, slab_certified on AabbFrame, which decides exactly. This one only
// answers where its decisions are proven, so both give the same answer.
// Bound: with 1/d normal and finite (|d| in [2^-1022, 2^995]), p - o exact when it is
// subnormal, and a subnormal product off by at most 2^-1075, each computed value is
// within gamma(3)|t| + 2^-1075 of t; the ends t~ ∓ (K|t~| + eta), K = 2·gamma(3),
// eta = 2^-1022 (the smallest normal: a subnormal constant would slow every query on
// processors that take an assist on subnormal operands), cover that and their own two
// roundings (see the header comment). An overflowed value (±inf) makes some check
// compare a NaN, which fails it.
template <class T> std::optional<Hit<T>> aabb_certified_common(const Ray<T>& r, const Aabb<T>& b) {
    constexpr double K = 2 * gamma<double>(3), eta = 0x1p-1022, inf = std::numeric_limits<double>::infinity();
    // Parallel axes (d_i == ±0), directions whose reciprocal is not a normal double and
    // directions beyond faithful_slab_double's range go to the general path.
    const double a0 = std::abs(double(r.direction[0])), a1 = std::abs(double(r.direction[1])),
                 a2 = std::abs(double(r.direction[2]));
    if (!(int(std::min(std::min(a0, a1), a2) >= 0x1p-1022) & int(std::max(std::max(a0, a1), a2) <= 0x1p995)))
        return std::nullopt;
    // Latest entry (t_min first, strict > keeps the lowest axis on ties), earliest exit,
    // and the runners-up (the largest value among the entries that did not win, the
    // smallest among the exits). Per axis, the entry plane is lo for d > 0 and hi for
    // d < 0 (d != 0 here, and the computed values keep that order: both roundings are
    // monotone and 1/d has the sign of d).
    int w = -1, x = -1;
    double in = r.t_min, out = r.t_max, in2 = -inf, out2 = inf;
    double finite = 0;  // stays 0 while every slab value is finite, NaN otherwise (x - x)
    double inv[3], p_in[3], p_out[3], t_in[3], t_out[3];
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 3
#elif defined(__clang__)
#pragma clang loop unroll(full)
#endif
    for (int i = 0; i < 3; ++i) {
        const double o = r.origin[i];
        const bool neg = r.direction[i] < 0;
        inv[i] = 1.0 / double(r.direction[i]);
        p_in[i] = pick(neg, double(b.hi[i]), double(b.lo[i]));
        p_out[i] = pick(neg, double(b.lo[i]), double(b.hi[i]));
        t_in[i] = (p_in[i] - o) * inv[i];
        t_out[i] = (p_out[i] - o) * inv[i];
        // p - o can overflow although (p - o)/d is moderate: such a value must not be
        // taken for "no constraint".
        finite += (t_in[i] - t_in[i]) + (t_out[i] - t_out[i]);
        const bool later = t_in[i] > in, earlier = t_out[i] < out;
        w += int(later) * (i - w);
        x += int(earlier) * (i - x);
        in2 = std::max(in2, std::min(in, t_in[i]));
        out2 = std::min(out2, std::max(out, t_out[i]));
        in = t_in[i] > in ? t_in[i] : in;
        out = t_out[i] < out ? t_out[i] : out;
    }
    // The winner's bound strictly beyond the runner-up's (a tie fails this and goes to
    // the exact stage). Bounds are put on t_min and t_max too although they are exact
    // (fewer branches; it only makes the filter a little more cautious). With every slab
    // value finite, the runners-up are finite after three axes.
    const double ein = K * std::abs(in) + eta, eout = K * std::abs(out) + eta;
    const double in_lo = in - ein, in_hi = in + ein, out_lo = out - eout, out_hi = out + eout;
    const double in2_hi = in2 + (K * std::abs(in2) + eta), out2_lo = out2 - (K * std::abs(out2) + eta);
    const bool miss = in_lo > out_hi, hit = in_hi < out_lo;
    // The faithful entry and exit values, computed on every path (an axis index of -1,
    // t_min or t_max winning, reads axis 0 and discards the result).
    const int wi = w & ~(w >> 31), xi = x & ~(x >> 31);
    const FaithfulDouble fe = faithful_slab_double(p_in[wi], r.origin[wi], r.direction[wi], t_in[wi], inv[wi]);
    const FaithfulDouble fx = faithful_slab_double(p_out[xi], r.origin[xi], r.direction[xi], t_out[xi], inv[xi]);
    const bool rounded = int(miss) | ((int(w < 0) | int(fe.ok)) & (int(x < 0) | int(fx.ok)));
    if (!(int(in2_hi < in_lo) & int(out2_lo > out_hi) & (int(miss) | int(hit)) & int(finite == 0) & int(rounded)))
        return std::nullopt;
    const T te = w < 0 ? r.t_min : faithful_to<T>(fe.t);
    const T tx = x < 0 ? r.t_max : faithful_to<T>(fx.t);
    Hit<T> h;
    h.verdict = hit ? Verdict::hit : Verdict::miss;
    // A miss carries the default fields.
    h.t_enter = hit ? std::min(te, tx) : T(0);  // min: see slab_certified
    h.t_exit = hit ? tx : T(0);
    h.face = hit ? (w < 0 ? -1 : 2 * w + int(r.direction[wi] < 0)) : -1;
    return h;
}

template <class T> Hit<T> query(const Ray<T>& r, const PreparedAabb<T>& p, certified_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    if (const std::optional<Hit<T>> h = aabb_certified_common(r, p.box)) {
        RAYPROOF_COUNT_QUERY();
        return *h;
    }
    return slab_certified(AabbFrame<T>(r, p.box), r.t_min, r.t_max);
}

}  // namespace rayproof::detail
