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
//            conservative — in the pbrt-v4 manner (aabb_conservative_common): the
//            slab method in plain floating point (in double for both scalar types, as
//            fl(fl(p - o)·fl(1/d)), three roundings: |t~ - t| <= gamma(3)|t| plus an
//            underflow term), then only the two winners widened: t_enter = t~ -
//            (2·gamma(3)|t~| + 2^-1022) and t_exit likewise up (the derivation is at the
//            code), each clamped to [t_min, t_max] and rounded outward to T. A computed
//            ±inf from a parallel axis is exact. For double input, a reciprocal that is
//            not normal and finite (|d_i| beyond 2^1022, d_i == 0, or subnormal) or an
//            overflowed winner goes to the interval path (slab_conservative on
//            AabbFrame, outward rounding per operation), which the enclosures below
//            also feed: there each slab value t~ = fl(fl(p - o)·fl(1/d)) (fl(fl(p -
//            o)/d) where 1/d is not normal and finite) gets the enclosure t~ ∓
//            (K|t~| + 2^-1022) with K = 2·gamma(3), the bound of the conservative path
//            (the derivation is at aabb_conservative_common), valid while t~ is
//            finite; an overflowed one gets an outward-rounded interval division.
//            Parallel axes are decided exactly (comparisons of floats).
//            certified — the same enclosures decide every comparison they separate;
//            overlapping ones are decided by exact arithmetic (detail/exact.hpp). The
//            common case runs as straight-line code (aabb_certified_common): the entry
//            and the negated exit problem side by side in two lanes
//            (detail/lanes.hpp), the winners' identity and the verdict proven by the
//            enclosures, and each winning slab value (p - o)/d rounded faithfully by
//            one correction of its approximation t~: with s + e = p - o exactly
//            (two_sum), tt = t~ cut to 26 bits and d = dh + dl cut the same way, the
//            products tt·dh and tt·dl are exact and t' = fl(tt + fl(fl(fl(s - tt·dh)
//            + fl(e - tt·dl))·fl(1/d))) is one of the two floats enclosing t, and t
//            itself when t is representable (the derivation is at the code). It
//            answers for |d_i| < 2^1022 (1/d normal), the winners' |d| in [2^-500,
//            2^500] and |t~| in [2^-400, 2^400] (or t == 0). What it leaves on input
//            whose values it can vouch for goes to a second stage
//            (aabb_certified_stage): the general path's slab method over the same
//            values and bounds, with its comparisons and roundings. Everything else
//            goes to the general path (slab_certified on AabbFrame). Both round
//            faithfully by the compensated correction of faithful_slab_value (valid
//            while |s|, |t~| >= 2^-960) and exact arithmetic beyond. Their exact
//            comparisons take the sign of (p1 - o1)·d2 - (p2 - o2)·d1 from error-free
//            differences and products without an expansion type (compare_slab_values,
//            detail/exact.hpp): where both differences are exact, two exact products
//            compared as rounded pairs, or by their exponents and significands
//            (compare_products) where a product leaves the exact range, at any scale;
//            otherwise at any scale where every product is exact, and else, where the
//            positions and the directions each span at most 199
//            binades, the same quotients with positions and directions rescaled by
//            powers of two into the Expansion type's safe range (AabbScaledQuotients:
//            exact, and every comparison keeps its sign); only the rest goes to
//            BigDyadic.
//            For float, every step runs in double: a faithfully rounded double rounded
//            to nearest float is a faithfully rounded float.
//            Contraction (detail/eft.hpp): the enclosures are class C1, the products
//            of 26- and 27-bit parts class C2, and the probe's terms and the rounded
//            candidates class C3 (rounded(), at the code).
//            The verdict alone (verdict() in intersect.hpp) runs on the same lanes and
//            bounds (aabb_verdict_common): a certain verdict needs no winner and no
//            rounding, and what it cannot decide goes to the same general path.
#pragma once

#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/lanes.hpp>
#include <rayproof/detail/prepared.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/detail/slab_certified.hpp>
#include <rayproof/detail/slab_fast.hpp>
#include <rayproof/detail/validate.hpp>
#include <rayproof/prepared_ray.hpp>

#include <array>
#include <optional>
#include <type_traits>

namespace rayproof::detail {

template <class T> using PreparedAabb = Prepared<Aabb<T>>;  // detail/prepared.hpp

// The reciprocals a PreparedRay holds, rounded to T (fast mode: for float one more
// rounding than T(1)/d_i, which the mode does not promise anything about).
template <class T> struct PreparedInverse {
    const T* inv;
    RAYPROOF_ALWAYS_INLINE T operator()(int i) const { return inv[i]; }
};

// R is a Ray or a PreparedRay (prepared_ray.hpp) throughout: from a PreparedRay every
// path takes its validity and its reciprocals fl(1/d_i) as decided once, the same values
// the Ray paths compute per query, so the certified answers are the same bit for bit.

// Fast mode in full: the validity rules checked one by one, then the slab method with
// the parallel axes decided on the sign of d_i (detail/slab_fast.hpp). What
// aabb_fast_common declines, out of line.
template <class T> [[gnu::noinline, gnu::cold]] Hit<T> aabb_fast_general(const Ray<T>& r, const Aabb<T>& b) {
    if (!valid(b) || !valid(r)) return invalid_hit<T>();
    return slab_fast(r.origin.data(), r.direction.data(), b.lo.data(), b.hi.data(), r.t_min, r.t_max);
}

// Fast mode's common case: the branch-free slab of the textbooks (min and max of the
// two slab values, no choice on the sign of d_i) with the validity rules folded into
// one probe. probe = s - s for s the sum of the six slab values and the three d_i: 0
// exactly when every term is finite, and then every input but t_min and t_max is finite
// (an infinite or NaN o_i, lo_i or hi_i makes its slab values infinite or NaN, as
// 1/d_i is finite and nonzero for a finite nonzero d_i; d_i itself is a term) and no
// d_i is 0 (1/±0 = ±inf makes the values ±inf, or NaN for an origin on the plane), so
// the direction is not the zero vector. The box's lo <= hi and the range rules are
// three and three comparisons. With every slab value finite, min and max choose the
// same values as the choice on the sign of d_i, except for a flat box (equal values,
// the same either way); the face's side is the sign of d_i, as there. A parallel axis,
// an overflowed value and invalid input go to aabb_fast_general, which answers them by
// the contract's rules.
template <class T> RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> aabb_fast_common(const Ray<T>& r, const Aabb<T>& b) {
    const T* o = r.origin.data();
    const T* d = r.direction.data();
    const T* lo = b.lo.data();
    const T* hi = b.hi.data();
    T t_enter = r.t_min, t_exit = r.t_max, sum = 0;
    int face = -1;
    RAYPROOF_UNROLL3
    for (int i = 0; i < 3; ++i) {
        const T inv = T(1) / d[i];
        const T t_lo = (lo[i] - o[i]) * inv, t_hi = (hi[i] - o[i]) * inv;
        // min and max on two comparisons of their own: on one shared comparison the compiler
        // swaps the pair with a branch, which random directions mispredict half the time.
        const T t_in = t_hi < t_lo ? t_hi : t_lo, t_out = t_lo < t_hi ? t_hi : t_lo;
        sum += (t_lo + t_hi) + d[i];
        const bool later = t_in > t_enter;
        face = pick_int(later, 2 * i + int(std::signbit(d[i])), face);
        t_enter = later ? t_in : t_enter;
        t_exit = t_out < t_exit ? t_out : t_exit;
    }
    const bool ok = int(sum - sum == 0) & int(lo[0] <= hi[0]) & int(lo[1] <= hi[1]) & int(lo[2] <= hi[2]) &
                    int(valid_range(r));
    if (!ok) [[unlikely]]
        return std::nullopt;
    Hit<T> h;
    h.verdict = t_enter <= t_exit ? Verdict::hit : Verdict::miss;
    h.t_enter = t_enter;
    h.t_exit = t_exit;
    h.face = face;
    return h;
}

template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Hit<T> query(const R& ray, const PreparedAabb<T>& p, fast_t) {
    const Ray<T>& r = ray_of(ray);
    if constexpr (is_prepared_ray_v<R>) {
        if (!p.ok || !valid(ray)) return invalid_hit<T>();
        return slab_fast_with(r.origin.data(), r.direction.data(), PreparedInverse<T>{ray.inv()}, p.shape.lo.data(),
                              p.shape.hi.data(), r.t_min, r.t_max);
    } else {
        return common_or_fallback(aabb_fast_common(r, p.shape), [&, &s = p.shape] { return aabb_fast_general(r, s); });
    }
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
// where the conditions above fail. p == o gives exactly +0 (ok). faithful_to
// (detail/certified.hpp) rounds it to T.
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
    // Contraction: mul_sub is one rounding of t~·d - s in every form (eft.hpp); the
    // correction's product is rounded() (class C3, as tc in aabb_certified_common: the
    // derivation allows a fused form, the bit-for-bit agreement of the paths does not).
    const double t = approx + rounded((se.lo - mul_sub(approx, d, se.hi)) * inv);
    const bool zero = se.hi == 0;
    return {zero ? 0.0 : t, bool(int(in_range) | int(zero))};
}
template <class T> std::optional<T> faithful_slab_value(T p, T o, T d) {
    const double inv = 1.0 / double(d);
    // t~ is rounded() (detail/eft.hpp, class C3): fused into t~ + correction it would
    // enter unrounded, while the correction is taken against its rounded value.
    const FaithfulDouble f =
        faithful_slab_double(double(p), double(o), double(d), rounded((double(p) - double(o)) * inv), inv);
    if (!f.ok) return std::nullopt;
    return faithful_to<T>(f.t);
}

// exact_compare(a, b) of slab values (p - o)/d given as {p, o, d} by value(i, side),
// without an expansion type (compare_slab_values and compare_slab_value, exact.hpp);
// none where a difference p - o is not a double and one of the products may be inexact
// (extreme exponents: exact_compare then tries the values at a safer scale, or an
// expansion type).
template <class Value> std::optional<int> slab_quick_compare(const SlabRef& a, const SlabRef& b, Value&& value) {
    if (a.axis >= 0 && b.axis >= 0) {
        const auto x = value(a.axis, a.side), y = value(b.axis, b.side);
        return compare_slab_values(x[0], x[1], x[2], y[0], y[1], y[2]);
    }
    if (a.axis >= 0) {
        const auto x = value(a.axis, a.side);
        return compare_slab_value(x[0], x[1], x[2], b.c);
    }
    const auto y = value(b.axis, b.side);
    const std::optional<int> s = compare_slab_value(y[0], y[1], y[2], a.c);
    if (!s) return std::nullopt;
    return -*s;
}

// The slab values of a double box and ray for the exact stage at a safer scale: every
// position (o_i, lo_i, hi_i) multiplied by 2^sp and every direction d_i by 2^sd, so that
// each quotient (p - o_i)/d_i is 2^(sp - sd) = 2^shift() times the frame's. Only axes
// with d_i != 0 count (a parallel axis has no slab value). With E_p the largest and e_p
// the smallest binary exponent (ilogb) of the nonzero positions, sp = 99 - E_p puts
// every nonzero position in [2^(99 - (E_p - e_p)), 2^100); likewise sd for the
// directions (exact.hpp, ExponentSpan). Where both spans E - e are at most 199, every
// nonzero scaled value lies in [2^-100, 2^100], the Expansion type's safe range
// (expansion_safe), and each product by a power of two is exact (its result is a
// normal double). The grazing cases that are integer configurations scaled by a large
// or tiny power of two, which the Expansion type refused, are then decided with it
// instead of BigDyadic.
class AabbScaledQuotients {
public:
    template <class T> static std::optional<AabbScaledQuotients> make(const T* o, const T* d, const Aabb<T>& b) {
        ExponentSpan positions, directions;
        for (int i = 0; i < 3; ++i) {
            if (d[i] == 0) continue;
            directions.add(double(d[i]));
            positions.add(double(o[i]));
            positions.add(double(b.lo[i]));
            positions.add(double(b.hi[i]));
        }
        const std::optional<int> sp = positions.safe_shift(), sd = directions.safe_shift();
        if (!sp || !sd || directions.hi < directions.lo) return std::nullopt;  // too wide, or every axis parallel
        return AabbScaledQuotients(o, d, b, *sp, *sd);
    }

    int shift() const { return shift_; }
    // Axes with d_i != 0 only (as every slab value).
    template <class E> E num(int i, int side) const { return E(p_[i][side]) - E(o_[i]); }
    template <class E> E den(int i) const { return E(d_[i]); }
    bool safe() const { return true; }
    std::optional<int> quick_compare(const SlabRef& a, const SlabRef& b) const {
        return slab_quick_compare(a, b, [&](int i, int side) { return std::array<double, 3>{p_[i][side], o_[i], d_[i]}; });
    }

private:
    // A parallel axis's values are scaled too but never used (they may leave the range).
    template <class T>
    AabbScaledQuotients(const T* o, const T* d, const Aabb<T>& b, int sp, int sd) : shift_(sp - sd) {
        for (int i = 0; i < 3; ++i) {
            d_[i] = times_pow2(double(d[i]), sd);
            o_[i] = times_pow2(double(o[i]), sp);
            p_[i][0] = times_pow2(double(b.lo[i]), sp);
            p_[i][1] = times_pow2(double(b.hi[i]), sp);
        }
    }
    double p_[3][2], o_[3], d_[3];
    int shift_;
};

// The exact side of a box's slab values (p - o_i)/d_i, p = lo_i (side 0) or hi_i (side
// 1), as a source of exact quotients (detail/certified.hpp): the comparisons at any scale
// (compare_at_any_scale), the rescaled values where those decline (scaled()), the
// expansion types beyond, and each value faithfully rounded (faithful_value). The slab
// frame (AabbFrame) adds the enclosures; the second stage (aabb_certified_stage) takes
// the straight-line path's instead.
template <class T> class AabbExact {
public:
    AabbExact(const Ray<T>& r, const Aabb<T>& b) : o_(r.origin.data()), d_(r.direction.data()), b_(&b) {}

    template <class E> E num(int i, int side) const { return E(double(plane(i, side))) - E(double(o_[i])); }
    template <class E> E den(int i) const { return E(double(d_[i])); }
    // (exact_compare: tried before the scaled() values, which it needs only where a
    // difference has an error term and one of its products leaves the exact range.)
    std::optional<int> compare_at_any_scale(const SlabRef& a, const SlabRef& b) const {
        return slab_quick_compare(a, b, [&](int i, int side) {
            return std::array<double, 3>{double(plane(i, side)), double(o_[i]), double(d_[i])};
        });
    }
    // Decided on first use, once per frame (each exact comparison asks).
    bool safe() const {
        if (safe_ < 0) {
            bool s = true;
            for (int i = 0; i < 3; ++i)
                s = s && expansion_safe(o_[i]) && expansion_safe(d_[i]) && expansion_safe(b_->lo[i]) &&
                    expansion_safe(b_->hi[i]);
            safe_ = s;
        }
        return safe_ != 0;
    }
    // The same slab values at a scale the Expansion type is safe at, where one exists
    // (exact_compare's comparisons use it when safe() is false). Made on first use, once
    // per frame (a query may compare several times).
    const std::optional<AabbScaledQuotients>& scaled() const {
        if (!scaled_made_) {
            scaled_ = AabbScaledQuotients::make(o_, d_, *b_);
            scaled_made_ = true;
        }
        return scaled_;
    }
    // Slab value (i, side), d_i != 0, faithfully rounded: the compensated correction
    // (faithful_slab_value) where it holds, else in exact arithmetic.
    T faithful_value(int i, int side, bool& went_exact) const {
        if (const std::optional<T> t = faithful_slab_value<T>(plane(i, side), o_[i], d_[i])) return *t;
        RAYPROOF_COUNT_EXACT(went_exact);
        return exact_faithful<T>(*this, i, side);
    }

protected:
    T plane(int i, int side) const { return side ? b_->hi[i] : b_->lo[i]; }
    const T* o_;
    const T* d_;
    const Aabb<T>* b_;

private:
    mutable int safe_ = -1;  // safe(), -1 until asked
    mutable bool scaled_made_ = false;
    mutable std::optional<AabbScaledQuotients> scaled_;
};

// The slab frame of an axis-aligned box (see detail/slab_certified.hpp): the exact side
// above with an enclosure of every slab value.
template <class T> class AabbFrame : public AabbExact<T> {
    using AabbExact<T>::o_, AabbExact<T>::d_, AabbExact<T>::b_, AabbExact<T>::plane;

public:
    AabbFrame(const Ray<T>& r, const Aabb<T>& b) : AabbFrame(r, b, nullptr) {}
    // The reciprocals as the prepared ray decided them: the same values fl(1/d_i).
    AabbFrame(const PreparedRay<T>& r, const Aabb<T>& b) : AabbFrame(r.ray(), b, r.rinv()) {}

private:
    // rinv: the prepared ray's fl(1/d_i), or nullptr: divided here (the same values).
    // Each slab value t~ = fl(fl(p - o)·fl(1/d)) where 1/d is normal and finite, else
    // fl(fl(p - o)/d) (|d| beyond 2^1022, or so small that 1/d overflows): within
    // gamma(3)|t| + 2^-1075 of t either way (three roundings or two; p - o is exact
    // when it is subnormal, and an underflowed product or quotient is off by at most
    // 2^-1075). Its enclosure is t~ ∓ B(t~), B(v) = fl(fl(K|v|) + eta), K = 2·gamma(3),
    // eta = 2^-1022: the bound of aabb_conservative_common, whose derivation covers that
    // error and the two roundings of the ends, underflow included. ok_[i][side]: t~ is
    // finite, so the enclosure holds; an overflowed value is enclosed by an
    // outward-rounded division instead (enclose).
    template <class Rinv> AabbFrame(const Ray<T>& r, const Aabb<T>& b, Rinv rinv) : AabbExact<T>(r, b) {
        constexpr double K = 2 * gamma<double>(3), eta = std::numeric_limits<double>::min();
        for (int i = 0; i < 3; ++i) {
            ok_[i][0] = ok_[i][1] = true;
            if (d_[i] == 0) continue;
            const double d = double(d_[i]);
            double inv;
            if constexpr (std::is_null_pointer_v<Rinv>)
                inv = 1.0 / d;
            else
                inv = rinv[i];
            const bool inv_ok =
                std::abs(inv) >= std::numeric_limits<double>::min() && std::abs(inv) <= std::numeric_limits<double>::max();
            for (int side = 0; side < 2; ++side) {
                const double s = double(plane(i, side)) - double(o_[i]);
                const double t = inv_ok ? s * inv : s / d;
                const double a = std::abs(t);
                ok_[i][side] = a <= std::numeric_limits<double>::max();
                t_[i][side] = t;
                e_[i][side] = K * a + eta;
            }
        }
    }

public:
    int den_sign(int i) const { return (d_[i] > 0) - (d_[i] < 0); }
    bool inside_parallel(int i) const { return b_->lo[i] <= o_[i] && o_[i] <= b_->hi[i]; }
    Interval<double> enclose(int i, int side) const {
        if (ok_[i][side]) return {t_[i][side] - e_[i][side], t_[i][side] + e_[i][side]};
        const double s = double(plane(i, side)) - double(o_[i]);
        return divide_by_point(Interval<double>(step_down(s), step_up(s)), double(d_[i]));
    }
    T faithful(int i, int side, const Interval<double>&, bool& went_exact) const {
        return this->faithful_value(i, side, went_exact);
    }

private:
    double t_[3][2], e_[3][2];
    bool ok_[3][2];
};

static_assert(SlabFrame<AabbFrame<float>, float> && SlabFrame<AabbFrame<double>, double>);

// The conservative answer by interval arithmetic per operation (AabbFrame, outward
// rounding where its bound does not apply): what aabb_conservative_common declines, out
// of line (parallel axes for double input, extreme exponents). The inputs are valid.
template <class R, class T>
    requires RayOrPrepared<R, T>
[[gnu::noinline, gnu::cold]] Hit<T> aabb_conservative_general(const R& ray, const Aabb<T>& b) {
    const Ray<T>& r = ray_of(ray);
    return slab_conservative(AabbFrame<T>(ray, b), r.t_min, r.t_max);
}

// The conservative answer in the pbrt-v4 manner: the slab method evaluated in plain
// floating point, as the fast mode does (in double for both scalar types), and only the
// two winners widened, t_enter down and t_exit up, by a bound derived for them.
// Entry: with m the largest computed entry value (or t_min) and j its axis, the exact
// entry max(t_min, max_i t_i) is at least max(t_min, t_j), and t_j >= m - e(m) for e
// the error bound of m below; so max(t_min, fl(m - B(m))) is a lower bound of the exact
// entry, whichever axis truly wins and whatever the other axes computed (a lost
// constraint, a NaN that never wins, only widens). Likewise min(t_max, fl(x + B(x))),
// x the smallest computed exit, is an upper bound of the exact exit. So a hit of the
// exact answer (entry <= exit) is a hit here, and [t_enter, t_exit] encloses it.
// Error of one slab value, with 1/d normal and finite: t~ = fl(fl(p - o)·fl(1/d)) =
// t(1 + θ3) + η, |θ3| <= gamma(3) (three roundings: p - o is exact when it is
// subnormal, and a normal difference is one rounding), |η| <= 2^-1075 from a product
// in the subnormal range; so |t~ - t| <= g|t~| + 2·2^-1075, g = gamma(3)/(1 - gamma(3)).
// The bound B(v) = fl(fl(K·a) + eta), a = min(|v|, max), K = 2·gamma(3) (>= 6u(1 - u) as
// rounded), eta = 2^-1022 (a normal constant: a subnormal one would slow every query
// on processors that take an assist on subnormal operands). fl(K·a) >= K·a(1 - u) -
// 2^-1075, B >= (K·a(1 - u) - 2^-1075 + eta)(1 - u), and fl(v - B) <= v - B + u(a + B),
// so fl(v - B) <= v - g·a - 2·2^-1075 as soon as B(1 - u) >= (g + u)·a + 2·2^-1075:
// (1 - u)^3·6u(1 - u) > 4u + 10u² >= g + u, and (1 - u)^2(eta - 2^-1075) > 2·2^-1075.
// The same for fl(x + B(x)) from above. An infinite v stands for an exact one (a
// parallel axis whose origin lies outside its slab gives +inf as an entry, -inf as an
// exit; one inside gives -inf, +inf or NaN, no constraint), and a = max keeps B finite
// so that fl(±inf ∓ B) is ±inf: never inf - inf.
// Range: for float input every value is computed in double and needs nothing more
// (|p - o| <= 2^129, 1/d in [2^-128, 2^150] for a nonzero float d, products in
// [2^-277, 2^279] or 0: all normal), and a computed ±inf is an exact one. For double
// input the bound needs every fl(1/d_i) normal and finite (|d_i| in (2^-1024, 2^1022]:
// |fl(1/d)| in [2^-1022, max], checked as min and max of the three |1/d_i|), and an
// infinite winner is an overflow unless exact: m == +inf or x == -inf (a parallel miss,
// or an overflowed finite value) and any d_i == 0 go to aabb_conservative_general, out
// of line, which answers them by interval arithmetic.
// Both ends are then rounded to T outward (float: round_down_to/round_up_to). face is
// the computed winner's (the mode may differ on ties).
// Contraction (detail/eft.hpp): class C1. No product here meets an addition but K·a +
// eta, whose fused form has one rounding fewer, which the derivation allows.
template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> aabb_conservative_common(const R& ray, const Aabb<T>& b) {
    constexpr double K = 2 * gamma<double>(3), eta = 0x1p-1022, big = std::numeric_limits<double>::max();
    const Ray<T>& r = ray_of(ray);
    const T* o = r.origin.data();
    const T* d = r.direction.data();
    double m = double(r.t_min), x = double(r.t_max), amin = inf<double>, amax = 0;
    int face = -1;
    RAYPROOF_UNROLL3
    for (int i = 0; i < 3; ++i) {
        double inv;
        if constexpr (is_prepared_ray_v<R>)
            inv = ray.rinv(i);
        else
            inv = 1.0 / double(d[i]);
        const double t_lo = (double(b.lo[i]) - double(o[i])) * inv;
        const double t_hi = (double(b.hi[i]) - double(o[i])) * inv;
        const bool neg = std::signbit(d[i]);
        const double t_in = pick(neg, t_hi, t_lo), t_out = pick(neg, t_lo, t_hi);
        face += int(t_in > m) * (2 * i + int(neg) - face);
        m = t_in > m ? t_in : m;  // a NaN never wins
        x = t_out < x ? t_out : x;
        const double ai = std::abs(inv);
        amin = ai < amin ? ai : amin;
        amax = ai > amax ? ai : amax;
    }
    if constexpr (std::is_same_v<T, double>) {
        const bool ok = int(amin >= std::numeric_limits<double>::min()) & int(amax <= big) & int(m < inf<double>) &
                        int(x > -inf<double>);
        if (!ok) [[unlikely]]
            return std::nullopt;
    }
    const double am = std::abs(m), ax = std::abs(x);
    const double lo = m - (K * (am < big ? am : big) + eta), hi = x + (K * (ax < big ? ax : big) + eta);
    const double enter = lo > double(r.t_min) ? lo : double(r.t_min), exit = hi < double(r.t_max) ? hi : double(r.t_max);
    Hit<T> h;
    if (enter <= exit) {
        h.verdict = Verdict::hit;
        h.t_enter = round_down_to<T>(enter);
        h.t_exit = round_up_to<T>(exit);
        h.face = face;
    }
    return h;
}

// What aabb_conservative_in_t declines: validated in full, then the double path above,
// then the interval path. Out of line.
template <class T> [[gnu::noinline, gnu::cold]] Hit<T> aabb_conservative_declined(const Ray<T>& r, const Aabb<T>& b) {
    if (!valid(b) || !valid(r)) return invalid_hit<T>();
    if (const std::optional<Hit<T>> h = aabb_conservative_common(r, b)) return *h;
    return slab_conservative(AabbFrame<T>(r, b), r.t_min, r.t_max);
}

// The same enclosure computed in T itself (for float, the float roundings: u = 2^-24,
// eta = 2^-126), for a Ray: the derivation at aabb_conservative_common holds with u, K =
// 2·gamma(3) and eta = the smallest normal of T, and with 2^-1075 replaced by half T's
// smallest subnormal, as soon as every fl(1/d_i) is normal and finite and every slab
// value is finite; then it holds for all six values, and the widened winners bound the
// exact entry and exit as there.
// Validity and range, folded as in aabb_fast_common: probe = s - s for s the sum of the
// six slab values is 0 exactly when all of them are finite, and then o, lo and hi are
// finite and no d_i is 0 or so small that 1/d_i overflows (1/d_i is then ±inf, and a
// slab value ±inf or NaN); |d_i| <= 1/min (2^1022 for double, 2^126 for float) keeps d
// finite and every |fl(1/d_i)| >= min, normal. lo <= hi and the range rules are checked
// as comparisons. Everything else (parallel axes, invalid input, extreme exponents) goes
// to aabb_conservative_declined, which validates in full first.
// Contraction: class C1, as aabb_conservative_common.
template <class T> RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> aabb_conservative_in_t(const Ray<T>& r, const Aabb<T>& b) {
    constexpr T K = 2 * gamma<T>(3), eta = std::numeric_limits<T>::min(), dmax = T(1) / std::numeric_limits<T>::min();
    const T* o = r.origin.data();
    const T* d = r.direction.data();
    const T* lo = b.lo.data();
    const T* hi = b.hi.data();
    T m = r.t_min, x = r.t_max, sum = 0;
    int face = -1, small_d = 1;
    RAYPROOF_UNROLL3
    for (int i = 0; i < 3; ++i) {
        const T inv = T(1) / d[i];
        const T t_lo = (lo[i] - o[i]) * inv, t_hi = (hi[i] - o[i]) * inv;
        const T t_in = t_hi < t_lo ? t_hi : t_lo, t_out = t_lo < t_hi ? t_hi : t_lo;  // as aabb_fast_common
        sum += t_lo + t_hi;
        small_d &= int(std::abs(d[i]) <= dmax);
        const bool later = t_in > m;
        face = pick_int(later, 2 * i + int(std::signbit(d[i])), face);
        m = later ? t_in : m;
        x = t_out < x ? t_out : x;
    }
    const bool ok = int(sum - sum == 0) & small_d & int(lo[0] <= hi[0]) & int(lo[1] <= hi[1]) &
                    int(lo[2] <= hi[2]) & int(valid_range(r));
    if (!ok) [[unlikely]]
        return std::nullopt;
    // m and x are finite here, or t_min = -inf / t_max = +inf themselves (exact, and
    // their "bound" is infinite: -inf - (inf) = -inf, never inf - inf).
    const T l = m - (K * std::abs(m) + eta), u = x + (K * std::abs(x) + eta);
    const T enter = l > r.t_min ? l : r.t_min, exit = u < r.t_max ? u : r.t_max;
    return hit_when(enter <= exit, enter, exit, face);
}

template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Hit<T> query(const R& ray, const PreparedAabb<T>& p, conservative_t) {
    if constexpr (is_prepared_ray_v<R>) {
        if (!p.ok || !valid(ray)) return invalid_hit<T>();
        return common_or_fallback(aabb_conservative_common(ray, p.shape),
                                  [&, &s = p.shape] { return aabb_conservative_general(ray, s); });
    } else {
        return common_or_fallback(aabb_conservative_in_t(ray, p.shape),
                                  [&, &s = p.shape] { return aabb_conservative_declined(ray, s); });
    }
}

// The certified answer's second stage, for what the straight-line paths (below) leave
// undecided on usable input (every slab value finite with 1/d normal and finite, lo <= hi
// on every axis, a valid range: valid input, and no axis parallel): entries or exits
// whose enclosures overlap (rays through edges and corners, or nearly so), winners
// outside the correction's range. The general path's slab method (slab_certified: t_min,
// then the axes in order, an entry replaced only by a strictly greater value and an exit
// only by a strictly smaller one; then the order of the two) over the straight-line
// path's own values V[i] = (entry, -exit) and bounds: each value v enclosed by
// v ∓ (K|v| + eta) (aabb_lanes, where the bound is derived), every comparison they leave
// decided exactly on the box's exact side (AabbExact), and the winners rounded as
// AabbFrame::faithful rounds them. Every decision being the exact one and every rounding
// the same, it answers as the general path does, bit for bit, without building the
// frame or validating the input again.
template <class T>
[[gnu::noinline]] Hit<T> aabb_certified_stage(const Ray<T>& r, const Aabb<T>& b, const lanes::D2 (&V)[3]) {
    using lanes::lane0, lanes::lane1;
    constexpr double K = 2 * gamma<double>(3), eta = 0x1p-1022;
    RAYPROOF_COUNT_QUERY();
    bool went_exact = false;
    const AabbExact<T> src(r, b);
    int sden[3];
    SlabEnclosures v;
    for (int i = 0; i < 3; ++i) {
        sden[i] = r.direction[i] > 0 ? 1 : -1;  // never 0 on usable input
        const double e = lane0(V[i]), x = -lane1(V[i]), be = K * std::abs(e) + eta, bx = K * std::abs(x) + eta;
        v.in[i][0] = e - be, v.in[i][1] = e + be, v.out[i][0] = x - bx, v.out[i][1] = x + bx;
    }
    const Hit<T> h = slab_decide(src, sden, v, r.t_min, r.t_max, went_exact, [&](const SlabRef& ref, const Interval<double>&) {
        return src.faithful_value(ref.axis, ref.side, went_exact);
    });
    RAYPROOF_COUNT_FLUSH(went_exact);
    return h;
}

// The certified answer's common case in straight-line code, the entry problem in lane 0
// and the exit problem, negated, in lane 1 of detail/lanes.hpp (the exit is the
// smallest slab exit, minus it the largest of the negated exits; negation is exact and
// rounding to nearest is symmetric, so lane 1 computes exactly the negation of the
// scalar exit code and both lanes look for a maximum).
// Per axis the two slab values t~ = fl(fl(p - o)·fl(1/d)); the entry is the smaller and
// the exit the larger (both roundings are monotone and 1/d has the sign of d, so this is
// the plane entered: lo for d > 0, hi for d < 0). Per lane m is the largest value and
// m2 the runner-up. With the bounds
//     lo(v) = v - (K|v| + eta),  hi(v) = v + (K|v| + eta),
// increasing in v (slopes 1 ± K > 0), the exact lane value (latest entry, negated
// earliest exit) lies in [max(lo(m), limit), max(hi(m), limit)], limit = t_min in lane
// 0 and -t_max in lane 1: so the verdict is certain when the entry's and the exit's
// enclosures are disjoint, and needs no winner (this is all the verdict query uses).
// The full query also needs the winners: an axis's identity is certain when m2 lies
// below m's lower bound lo(m) (m2 needs no bound of its own: the derivation is at
// aabb_certified_common), the limit wins certainly when hi(m) lies below it. Then both
// winners are rounded faithfully, in the two lanes at once (the correction and its
// derivation are below).
// Everything runs branch-free (the verdict, the winning axes and the signs of d are as
// random as the rays); one well-predicted branch hands anything these checks cannot
// vouch for (close values, overflow, extreme exponents) to the general path,
// slab_certified on AabbFrame, which decides exactly. This one only answers where its
// decisions are proven, so both give the same answer.
// Bound: with 1/d normal and finite, p - o exact when it is subnormal, and a subnormal
// product off by at most 2^-1075, each computed value is within gamma(3)|t| + 2^-1075
// of t; the ends t~ ∓ (K|t~| + eta), K = 2·gamma(3), eta = 2^-1022 (the smallest
// normal: a subnormal constant would slow every query on processors that take an
// assist on subnormal operands), cover that and their own two roundings (see the header
// comment). The full query's winners' check rests on the same lower bound and spends all
// of K (its derivation is at aabb_certified_common): a smaller K needs a new one there.
// Validity and overflow: this path answers only when all six computed values are
// finite and so are the directions' terms of the same probe (4·d_i for double, d_i for
// float). A finite 4·d_i means |d_i| < 2^1022, so |fl(1/d_i)| >= 2^-1022 is normal; a
// finite slab value fl(fl(p - o)·fl(1/d)) needs 1/d finite (d_i = ±0, or so small that
// 1/d_i overflows, gives ±inf or NaN) and p - o finite, hence p and o finite (an
// infinite or NaN operand gives ±inf or NaN). So with lo <= hi on every axis and the
// range checked here, the inputs are valid and no separate validation is needed. An
// overflow of p - o or of the product (t finite but beyond the range) gives ±inf and
// sends the query to the general path, which validates in full first.

// The slab values in their two lanes and the bounds every certain verdict rests on,
// shared by the full query (aabb_certified_common) and the verdict query
// (aabb_verdict_common), so that the two decide a verdict by the same computation.
struct AabbLanes {
    lanes::D2 d01, d22, inv01, inv22;  // the directions and their reciprocals
    lanes::M2 usable;                  // every value (and direction term) finite, lo <= hi
    lanes::D2 V[3];                    // per axis (entry, -exit) as computed
    lanes::D2 v01, f01;                // max and min of axes 0 and 1
    lanes::D2 m;                       // per lane the largest value
    lanes::D2 limit;                   // (t_min, -t_max)
    lanes::D2 m_lo, m_hi;              // m's enclosure
    lanes::M2 proven;                  // lane 0: a hit is proven, lane 1: a miss (not yet
                                       // the winners, which only the full query needs);
                                       // either only on a valid range
};

template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE AabbLanes aabb_lanes(const R& ray, const Aabb<T>& b) {
    using namespace lanes;
    const Ray<T>& r = ray_of(ray);
    constexpr double K = 2 * gamma<double>(3), eta = 0x1p-1022;
    AabbLanes L;
    // The inputs as pairs of doubles; for float, from whole loads of the ray and the box
    // (lanes::float_quad): p2 = (lo_2, o_2), q2 = (o_2, hi_2).
    constexpr bool from_float = std::is_same_v<T, float>;
    D2 o01, lo01, hi01, p2, q2;
    if constexpr (from_float) {
        const Quad r0 = float_quad<8, 0>(r), r1 = float_quad<8, 4>(r), box = float_quad<6, 0>(b);
        const D2 o2d0 = r0.hi, d12 = r1.lo, lo2_hi0 = box.hi, hi12 = load2(b.hi.data() + 1);
        L.d01 = high_low(o2d0, d12);
        L.d22 = highs(d12, d12);
        o01 = r0.lo, lo01 = box.lo, hi01 = high_low(lo2_hi0, hi12);
        p2 = lows(lo2_hi0, o2d0), q2 = low_high(o2d0, hi12);
        L.limit = negate_lane1(r1.hi);
    } else {
        L.d01 = load2(r.direction.data());
        L.d22 = splat(double(r.direction[2]));
        o01 = load2(r.origin.data()), lo01 = load2(b.lo.data()), hi01 = load2(b.hi.data());
        const double o2 = double(r.origin[2]);
        p2 = make(double(b.lo[2]), o2), q2 = make(o2, double(b.hi[2]));
        L.limit = make(r.t_min, -double(r.t_max));
    }
    // 1/d for the three axes (axes 0 and 1 in one division), or from a prepared ray the
    // same values fl(1/d_i) as it decided them (no division); where it is not normal and
    // finite the values below are meaningless, and the probe sends the query to the
    // general path (the probe is the same either way: it adds the direction terms
    // computed here, so a prepared ray declines exactly what its ray declines).
    if constexpr (is_prepared_ray_v<R>) {
        L.inv01 = load2(ray.rinv());
        L.inv22 = splat(ray.rinv(2));
    } else {
        L.inv01 = splat(1.0) / L.d01;
        L.inv22 = splat(1.0) / L.d22;
    }
    // The slab values t~ = fl(fl(p - o)·fl(1/d)): t_lo01 = (t_lo0, t_lo1), t_hi01 =
    // (-t_hi0, -t_hi1) ((lo - o, o - hi) is (t_lo, -t_hi)·d exactly as rounded, rounding
    // to nearest being symmetric), x2 = (t_lo2, -t_hi2); per axis (entry, -exit) =
    // (min(t_lo, t_hi), min(-t_hi, -t_lo)), for axes 0 and 1 computed side by side as
    // in01 and out01 and regrouped per axis (the same operations on the same operands as
    // axis 2's min(x2, -swap(x2))).
    // Contraction (detail/eft.hpp): the probe below must add the very values the lanes
    // compare (class C3), and a product fused into its sum would be added unrounded
    // (finite where the rounded product overflowed), so the three products are
    // rounded(); the bounds are class C1.
    const D2 t_lo01 = rounded((lo01 - o01) * L.inv01), t_hi01 = rounded((o01 - hi01) * L.inv01);
    const D2 x2 = rounded((p2 - q2) * L.inv22);
    const D2 in01 = min(t_lo01, -t_hi01), out01 = min(t_hi01, -t_lo01);
    L.V[0] = lows(in01, out01);
    L.V[1] = highs(in01, out01);
    L.V[2] = min(x2, -swap(x2));
    // probe = s - s for s the sum of all six values (two per lane) and the directions'
    // terms: 0 when s is finite, NaN when a term is infinite or NaN (or when finite terms
    // overflow the sum, which only sends a valid query to the general path), so probe ==
    // 0 implies every term finite. The directions need terms of their own: an infinite
    // d_i has 1/d_i = ±0 and finite slab values. For double the terms 4·d_i (4·d_2 in
    // both lanes) are infinite or NaN exactly when |d_i| >= 2^1022 or d_i is NaN; for
    // float every finite nonzero float has 1/d normal and finite, and d_i itself is the
    // term. A zero d_i makes its slab values ±inf, or NaN where p - o is 0.
    // The terms 4·d_i are rounded() (class C3): fused, fl(4·d_0 + fl(4·d_2)) can be
    // finite for |d_0| >= 2^1022 (4·d_0 exact inside the fma, d_2 of the other sign).
    const D2 dterms = from_float ? L.d01 + L.d22 : rounded(L.d01 * splat(4.0)) + rounded(L.d22 * splat(4.0));
    const D2 sum = ((t_lo01 + t_hi01) + x2) + dterms, probe = sum - sum;
    // lo <= hi on the three axes (lane 1 of the axis-2 test is o2 <= o2, true for the
    // finite values that pass the probe).
    L.usable = (probe == splat(0.0)) & (lo01 <= hi01) & (p2 <= swap(q2));
    L.v01 = max(L.V[0], L.V[1]);
    L.f01 = min(L.V[0], L.V[1]);
    L.m = max(L.v01, L.V[2]);
    const D2 bm = abs(L.m) * splat(K) + splat(eta);
    L.m_lo = L.m - bm;
    L.m_hi = L.m + bm;
    // The exact lane value (the latest entry, the negated earliest exit) lies in
    // [max(m_lo, limit), max(m_hi, limit)]: every exact slab value lies below the
    // upper bound of its computed one, and these bounds increase with the value, so
    // below m_hi; and the exact maximum is at least the exact value of m's own axis.
    // h: the entry's upper and the exit's lower bound, g: the bounds a miss is judged
    // on; a hit is certain when h0 < -h1, a miss when g0 > -g1. Both as the signs of
    // the sums (h0 + h1, g0 + g1), in one addition: a sum of two doubles rounds to a
    // value of its exact sign (0 only when it is 0, ±inf of its sign on overflow). h
    // lies in (-inf, +inf] (m_hi is finite or +inf by overflow) and g in [-inf, +inf)
    // on a valid range, so no sum is inf - inf then; max(m_hi, limit) is the limit when
    // it is NaN, so a NaN limit makes its sum NaN, which decides nothing. Either verdict
    // is taken only on a valid range (valid_range_lanes).
    const D2 h = max(L.m_hi, L.limit), g = max(L.m_lo, L.limit);
    const D2 sums = lows(h, g) + highs(h, g);
    L.proven = (negate_lane1(sums) < splat(0.0)) & valid_range_lanes(L.limit);
    return L;
}

// The certified verdict alone (verdict() in intersect.hpp) from the same lanes: a hit
// is certain when the latest entry's upper bound lies below the earliest exit's lower
// bound, a miss when the latest entry's lower bound lies above the earliest exit's
// upper bound; no winner is needed, and nothing is rounded. verdict_declined when the
// general path must decide (see verdict_or, detail/certified.hpp). Both are never
// proven at once (g <= h in each lane, and rounding is monotone).
template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE int aabb_verdict_common(const R& r, const Aabb<T>& b) {
    using namespace lanes;
    const AabbLanes L = aabb_lanes(r, b);
    const int proven = bits(L.proven);
    return int(bits(L.usable) == 3) & int(proven != 0) ? proven & 1 : verdict_declined;
}

// The full query: the verdict above, then the winners' identity and their faithful
// rounding.
template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> aabb_certified_common(const R& ray, const Aabb<T>& b) {
    using namespace lanes;
    const Ray<T>& r = ray_of(ray);
    const AabbLanes L = aabb_lanes(ray, b);
    const D2 d01 = L.d01, d22 = L.d22, m = L.m, limit = L.limit, m_lo = L.m_lo, m_hi = L.m_hi;
    // The runner-up m2 per lane, and the winning axes (w: entry, v: exit) from the lane
    // masks with bit arithmetic (ties fail the checks below, so their order does not
    // matter).
    const D2 m2 = max(L.f01, min(L.v01, L.V[2]));
    const int c01 = bits(L.V[1] > L.V[0]), c2 = bits(L.V[2] > L.v01), c = c01 & ~c2;
    const int w = (c & 1) | ((c2 & 1) << 1), v = ((c >> 1) & 1) | (c2 & 2);
    // Per lane: the axis certainly wins, or the limit certainly does. The axis of m wins
    // certainly when m2 < m_lo = fl(m - b), b = fl(fl(K|m|) + eta), K = 2·gamma(3): m's
    // lower bound carries about twice m's own error, which covers m2's too, so m2 needs
    // no bound (any fl(m2 + c|m2|) >= m2 would be proven alike, and c = 0 is the tight
    // one; the check spends all of K). With t_A, t_B the exact values of m's and m2's
    // axes, ufp(x) = 2^floor(log2|x|), u = 2^-53, all values normal (|m| in [2^-400,
    // 2^400] for double, checked below; in [2^-277, 2^278] for float input, see there):
    //   t~ = fl(fl(s)·fl(1/d)) = fl(t(1 + α)(1 + β)), |α|, |β| <= u:
    //     e(t~) = |t~ - t| <= u·ufp(t~) + 2u(1 + 4u)|t~| <= 3.1u|t~|        (E)
    //   K = 2·fl(3u/(1 - 3u)) >= 6u, so b >= fl(K|m|) >= 6u(1 - u)|m|
    //   m2 < m_lo, two doubles: m_lo - m2 >= 2u·ufp(the one of smaller magnitude)
    //   m > 0, 0 < m2 < m, 2^k = ufp(m):
    //     m_lo <= (m - b) + u·ufp(m - b) <= m - b + u·2^k
    //     m - m2 >= b - u·2^k + 2u·ufp(m2)
    //     t_A - t_B >= (m - m2) - e(m) - e(m2)                           (E for both)
    //               >= 6u(1 - u)m - u2^k + 2u·ufp(m2) - (u2^k + 2u(1 + 4u)m)
    //                  - (u·ufp(m2) + 2u(1 + 4u)m2)                      (m2 < m)
    //               >= 2u(m - 2^k) + u·ufp(m2) - 22u²m > 0 when m2 >= m/4 (ufp(m2) > m/8);
    //     m2 < m/4: t_B <= 1.01·m2 < 0.26m < t_A
    //   m < 0, m2 < m, a = |m|, a2 = |m2| = a + G, 2^k = ufp(a):
    //     |m_lo| >= (a + b) - u·ufp(a + b), ufp(m_lo) >= ufp(a + b) >= 2^k
    //     a2 >= |m_lo| + 2u·ufp(m_lo) >= a + b + u2^k, so G >= 6u(1 - u)a + u2^k
    //     t_A - t_B >= G - e(m) - e(m2)
    //               >= G - (u2^k + 2u(1 + 4u)a) - (u·ufp(a2) + 2u(1 + 4u)(a + G))
    //               >= 2ua - u·ufp(a2) - 2uG - 26u²a          (the first G by its bound)
    //               >= u(a - 3G) - 26u²a > 0 when G <= a/4       (ufp(a2) <= a2 = a + G);
    //     G > a/4: t_A - t_B >= G - 3.1u(a + a2) >= G(1 - 27.9u) > 0     (a + a2 < 9G)
    //   m > 0 >= m2: t_A >= 0.99m > 0 and t_B <= 0 (rounding keeps the sign; an
    //     underflowed m2 == 0 is within 2^-1074 of t_B, far below t_A)
    //   m == 0: only from s == 0, t_A = 0 (fl(p - o) == 0 iff p == o; the double path
    //     checks s == 0 or |m| >= 2^-400, float products do not underflow), m_lo = -eta
    //     and m2 < -eta < 0, so t_B < 0
    // So t_B < t_A whenever the check passes, ties included.
    const M2 axis_wins = (m2 < m_lo) & (m_lo > limit), limit_wins = m_hi < limit;
    const M2 hit = (axis_wins | limit_wins) & both_lane0(L.proven), miss = both_lane1(L.proven);
    // The winners rounded faithfully, computed on every path (discarded when a limit
    // wins, or on a miss). Double input (float input below needs none of this): lane 0
    // the plane entered on axis w, lane 1 the plane left on axis v in the negated
    // problem (o - p). With s + e = p - o exactly (two_sum),
    // t = (s + e)/d and t - tt = (s + e - tt·d)/d for tt = t~ cut to 26 bits (|tt - t~|
    // < 2^-25|t~|). With d = dh + dl (dh: d cut to 26 bits, dl = d - dh exact, at most
    // 27 bits) the products tt·dh (52 bits) and tt·dl (53 bits) are exact, and
    // s - tt·dh is exact by Sterbenz (tt·dh = s(1 ± 2^-23)). e - tt·dl (both below
    // 2^-24|s|) and the sum of the two (below 2^-22|s|) round once each, the product
    // with fl(1/d) twice more: the correction is off by less than 2^-72|t|, so
    // RN(tt + correction) lies within 2^-19 of a gap from t: one of the two floats
    // enclosing t, and t itself when it is representable. This needs no overflow and no
    // underflow: the winner's |d| in [2^-500, 2^500] (checked here: the lanes only
    // bound it by 2^1022) and |t~| in [2^-400, 2^400] give |s| =
    // |t~·d|(1 ± 2u) in [2^-901, 2^901] and every product and partial sum normal (or
    // zero); s == 0 gives the exact ±0.
    const int negative = bits(d01 < splat(0.0)) | (bits(d22 < splat(0.0)) & 1) << 2;  // bit i: d_i < 0
    const int neg_w = (negative >> w) & 1, neg_v = (negative >> v) & 1;
    // For float input the winners' computed values need no correction: within
    // gamma(3)|t| < 2^-51|t| of t (no underflow or overflow in double: |p - o| >= 2^-149
    // or 0, |1/d| in (2^-128, 2^149]), they round to float faithfully (a float lying
    // between t and m would be within 2^-51|t| of m, far nearer than half the spacing
    // 2^-25|t| (2^-150 among subnormals) to the float beyond it, so m rounds to that float,
    // which encloses t; t itself when t is a float), and faithful_to clamps beyond the
    // float range.
    D2 tc = m;
    M2 decided = miss | hit;
    if constexpr (!std::is_same_v<T, float>) {
        const double inv[3] = {lane0(L.inv01), lane1(L.inv01), lane0(L.inv22)};
        const double d_w = double(r.direction[w]), d_v = double(r.direction[v]);
        const D2 dd = make(d_w, d_v), tt = high26(m), dh = high26(dd);
        // The entry lane wants p - o for the plane entered (hi when d_w < 0), the exit
        // lane o - p for the plane left (lo when d_v < 0), split exactly by one two-lane
        // two_sum: its s is the value the slab values above were made from (rounding to
        // nearest is symmetric, so fl(hi - o) = -fl(o - hi)).
        // The planes are read by index, not chosen by a ternary, which the compiler turns
        // into a jump that random directions mispredict half the time.
        const T* const sides[2] = {b.lo.data(), b.hi.data()};
        const double p_in = double(sides[neg_w][w]), p_out = double(sides[1 - neg_v][v]);
        const SumOf<D2> se = two_sum(make(p_in, double(r.origin[v])), -make(double(r.origin[w]), p_out));
        // tt·dh and tt·(dd - dh) are exact (eft.hpp, class C2); the correction's product
        // with 1/d is rounded() (class C3: fused into tt + ..., one rounding fewer, which
        // the derivation allows, but the candidate would depend on the compiler's choice
        // in each inlined copy; rounded, every path computes the same bits).
        tc = tt + rounded(((se.hi - tt * dh) + (se.lo - tt * (dd - dh))) * make(inv[w], inv[v]));
        const D2 am = abs(m), ad = abs(dd);
        const M2 in_range =
            (am >= splat(0x1p-400)) & (am <= splat(0x1p400)) & (ad >= splat(0x1p-500)) & (ad <= splat(0x1p500));
        const M2 rounded = limit_wins | in_range | (se.hi == splat(0.0));
        decided = miss | (hit & rounded);
    }
    // One branch on both lanes: a miss, or a hit decided and rounded in both.
    if (bits(L.usable & decided) != 3) return std::nullopt;
    // The winner's value lies above the limit when the axis wins (its faithful rounding
    // too: the limit is a float) and below it when the limit wins, so max(tc, limit)
    // selects without a branch (a NaN tc gives the limit). Then (t_enter, t_exit) with
    // + 0.0 making an exact zero +0, t_enter = min(t_enter, t_exit) (see slab_certified;
    // rounding to T is monotone, so the min may come first), and both +0 on a miss (its
    // default fields).
    const D2 u = negate_lane1(max(tc, limit)) + splat(0.0);
    const D2 t = keep(hit, low_high(min(u, swap(u)), u));
    const bool is_hit = bits(hit) == 3;
    Hit<T> out;
    out.verdict = Verdict(int(is_hit));
    static_assert(int(Verdict::miss) == 0 && int(Verdict::hit) == 1);
    out.t_enter = faithful_to<T>(lane0(t));
    out.t_exit = faithful_to<T>(lane1(t));
    out.face = (2 * w + neg_w) | -int(int(bits(limit_wins) & 1) | int(!is_hit));
    return out;
}

// The general path, out of line: it is rare, and inlined it would make every query pay
// for its stack frame. The inputs are assumed valid.
template <class T> [[gnu::noinline, gnu::cold]] Hit<T> aabb_certified_general(const Ray<T>& r, const Aabb<T>& b) {
    return slab_certified(AabbFrame<T>(r, b), r.t_min, r.t_max);
}

// What the straight-line paths decline: on usable input with a valid range (see
// aabb_certified_stage) the second stage, over the lanes computed again (the straight-line
// path does not keep them: holding them for this rare call slows its common case);
// otherwise validated in full (the straight-line paths answer only for valid input, see
// the validity note above), then the general path. A prepared ray's validity is decided
// already.
template <class R, class T>
    requires RayOrPrepared<R, T>
[[gnu::noinline, gnu::cold]] Hit<T> aabb_certified_declined(const R& r, const Aabb<T>& b) {
    const AabbLanes L = aabb_lanes(r, b);
    if (int(lanes::bits(L.usable) == 3) & int(valid_range(ray_of(r)))) return aabb_certified_stage(ray_of(r), b, L.V);
    return answer_if_valid(r, b, [&] { return aabb_certified_general(ray_of(r), b); });
}

// The certified answer in full. The prepared flag is not consulted: the straight-line
// path checks validity itself, and what it declines is validated again.
template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Hit<T> query(const R& r, const PreparedAabb<T>& p, certified_t) {
    return common_or_general(aabb_certified_common(r, p.shape), [&, &s = p.shape] { return aabb_certified_declined(r, s); });
}

// The certified verdict alone: the same lanes and the same fallback as the full query.
template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Verdict verdict_query(const R& r, const PreparedAabb<T>& p, certified_t) {
    return verdict_or(aabb_verdict_common(r, p.shape), [&, &s = p.shape] { return aabb_certified_declined(r, s).verdict; });
}

}  // namespace rayproof::detail
