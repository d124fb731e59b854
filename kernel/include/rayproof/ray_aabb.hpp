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
//            winning slab value (p - o)/d is rounded faithfully by a compensated
//            division: s + e = p - o exactly (two_sum), q = fl(s/d), r = s - q·d exactly
//            (fma), q' = fl(q + fl(fl(r + e)/d)); |q + fl(fl(r+e)/d) - t| <= gamma(2)·1.5
//            ulp(q), far below half a gap, so q' is one of the two floats enclosing t
//            and is t when t is representable. Valid while |s|, |q| >= 2^-960 (no
//            residual or quotient underflow); otherwise exact arithmetic decides.
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
        const Pair se = two_sum(double(plane(i, side)), -double(o_[i]));  // p - o = s + e exactly
        if (se.hi == 0) return T(0);
        const double d = d_[i], q = se.hi / d;
        if (std::abs(se.hi) >= 0x1p-960 && std::abs(q) >= 0x1p-960 && std::abs(q) <= std::numeric_limits<double>::max()) {
            const double r = std::fma(-q, d, se.hi);  // exact residual
            const double q2 = q + (r + se.lo) / d;
            // beyond the largest finite T: the enclosing finite neighbour (as exact_faithful)
            if (std::abs(q2) > double(std::numeric_limits<T>::max()))
                return std::copysign(std::numeric_limits<T>::max(), T(q2 > 0 ? 1 : -1));
            return static_cast<T>(q2);
        }
        RAYPROOF_COUNT_EXACT(went_exact);
        return exact_faithful<T>(*this, i, side);
    }

private:
    T plane(int i, int side) const { return side ? b_->hi[i] : b_->lo[i]; }
    const T* o_;
    const T* d_;
    const Aabb<T>* b_;
    double t_[3][2] = {}, e_[3][2] = {};
    bool ok_;
};

template <class T> Hit<T> query(const Ray<T>& r, const PreparedAabb<T>& p, conservative_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    return slab_conservative(AabbFrame<T>(r, p.box), r.t_min, r.t_max);
}

template <class T> Hit<T> query(const Ray<T>& r, const PreparedAabb<T>& p, certified_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    return slab_certified(AabbFrame<T>(r, p.box), r.t_min, r.t_max);
}

}  // namespace rayproof::detail
