// rayproof/ray_obb.hpp — ray against oriented box.
//
// Shape:     the closed solid { p : |(p - center)·a_i| <= half_extent_i, i = 0,1,2 }, a_i
//            the i-th column of `axes` exactly as stored: the axes need not be unit nor
//            orthogonal (a non-unit axis scales its slab: the slab half-width along a_i is
//            half_extent_i / |a_i|). Linearly dependent axes are invalid (decided exactly).
// Query:     as Ray/Aabb: [t_enter, t_exit], face = 2·i + side where side 0 is the plane
//            (p - center)·a_i == -half_extent_i.
// Algorithm: change of frame, then the Aabb slab core: o'_i = (o - center)·a_i,
//            d'_i = d·a_i, lo = -half_extent, hi = half_extent; the slab values
//            (±h_i - o'_i)/d'_i are exactly the parameters where the ray crosses the
//            planes (p - center)·a_i = ±h_i (Eberly, "Intersection of a Line and a Box",
//            Geometric Tools; Ericson, Real-Time Collision Detection, 5.3.3).
// Degenerate cases: d·a_i == 0 (parallel to a slab; the core's ±0 rule applies),
//            half_extent_i == 0 (flat box), origin inside, edges and corners.
// Modes:     fast — o'_i carries the error of a difference and a 3-term dot product,
//            |δ| <= gamma(4) relative to the sum of the absolute terms, d'_i gamma(3); a
//            tiny exact d·a_i can round to ±0 or to the wrong sign near perpendicular
//            directions. Measured, not promised.
//            conservative — o'_i, d'_i and the slab values are evaluated in interval
//            arithmetic with outward rounding (detail/interval.hpp), in double for both
//            scalar types; the exact sign of d'_i is used when its interval holds 0 (a
//            nearly parallel slab whose sign is unknown gives the half-line of values
//            on the side its numerator allows, or no constraint at all).
//            certified — o'_i and d'_i enclosed by one plain evaluation in double and
//            the static bounds gamma(4)·Σ|a_ji (o_j - c_j)| and gamma(3)·Σ|a_ji d_j|
//            (derivation at ObbFrame), then the slab values in interval arithmetic;
//            these intervals decide every comparison they separate; the rest,
//            and the sign of d'_i, are decided exactly: num = ±h_i - Σ_j a_ji (o_j - c_j)
//            and den = Σ_j a_ji d_j are degree 2, comparisons of two slab values degree 4
//            (detail/exact.hpp). t is pinned first from double-word num and den with
//            proven bounds (detail/compensated.hpp; for float the faithful double
//            rounded to nearest), next rounded from the interval when it lies strictly
//            between the neighbours of its midpoint, else exactly.
#pragma once

#include <rayproof/detail/compensated.hpp>
#include <rayproof/detail/slab_certified.hpp>
#include <rayproof/detail/slab_fast.hpp>
#include <rayproof/detail/validate.hpp>

namespace rayproof::detail {

template <class T> struct PreparedObb {
    Obb<T> box;
    Vec3<T> lo, hi;  // -half_extent, half_extent
    bool ok;
};
template <class T> PreparedObb<T> prepare(const Obb<T>& b) { return {b, -b.half_extent, b.half_extent, valid(b)}; }

template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> query(const Ray<T>& r, const PreparedObb<T>& p, fast_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    const Vec3<T> o = p.box.axes.transpose() * (r.origin - p.box.center);
    const Vec3<T> d = p.box.axes.transpose() * r.direction;
    return slab_fast(o.data(), d.data(), p.lo.data(), p.hi.data(), r.t_min, r.t_max);
}

// The slab value (±h_i - o'_i)/d'_i as num = ±h_i - Σ_j a_ji (o_j - c_j), with o_j - c_j =
// s_j + e_j split exactly by two_sum (the start and six products), over den = Σ_j a_ji d_j
// (three products and three zeros), as double-word sums (detail/compensated.hpp) for
// pin_quotient; not ok when an input is out of quotient_sums' range.
template <class T> RAYPROOF_ALWAYS_INLINE QuotientSums obb_slab_sums(const Ray<T>& r, const Obb<T>& b, int i, int side) {
    using namespace lanes;
    const double h = b.half_extent[i];
    D2 a[6], f[6];
    M2 inputs = in_range(make(h, 0.0));
    for (int j = 0; j < 3; ++j) {
        const double x = b.axes(j, i);
        const Pair oc = two_sum(double(r.origin[j]), -double(b.center[j]));
        a[j] = make(-x, x);
        f[j] = make(oc.hi, double(r.direction[j]));
        a[3 + j] = make(-x, 0.0);
        f[3 + j] = make(oc.lo, 0.0);
        inputs = inputs & in_range(a[j]) & in_range(f[j]) & in_range(f[3 + j]);
    }
    return quotient_sums(make(side ? h : -h, 0.0), a, f, inputs);
}

// The slab frame of an oriented box: o'_i = (o - c)·a_i, d'_i = d·a_i, slab
// [-h_i, h_i]; value (±h_i - o'_i)/d'_i.
template <class T> class ObbFrame {
public:
    // Enclosures of o'_i and d'_i. The conservative mode's come from interval arithmetic
    // (outward rounding per operation, the tighter of the two, whose ends it answers);
    // the certified mode's (certified_t) from one plain evaluation and a static bound
    // (only the decisions it separates matter there, and it is cheaper), with
    // Δ~_j = fl(o_j - c_j) (within u/(1 - u)|Δ~_j| of o_j - c_j):
    //   |fl(Σ_j a_ji Δ~_j) - o'_i| <= gamma(3)·Σ|a_ji Δ~_j| + u/(1 - u)·Σ|a_ji Δ~_j| <= gamma(4)·Σ|a_ji Δ~_j|,
    //   |fl(Σ_j a_ji d_j) - d'_i| <= gamma(3)·Σ|a_ji d_j|
    // (Higham, ASNA, 3.1). The bound is doubled (covering its own few roundings), 2^-1022
    // covers underflowing products (at most 2^-1075 each), and each end then steps one
    // float outward (covering the rounding of value ± bound). An infinite or NaN bound
    // (an overflow) gives the whole line, which decides nothing.
    ObbFrame(const Ray<T>& r, const Obb<T>& b) : r_(&r), b_(&b) {
        Interval<double> oc[3];
        for (int j = 0; j < 3; ++j) oc[j] = Interval<double>(double(r.origin[j])) - Interval<double>(double(b.center[j]));
        for (int i = 0; i < 3; ++i) {
            Interval<double> op(0.0), dp(0.0);
            for (int j = 0; j < 3; ++j) {
                const Interval<double> a(double(b.axes(j, i)));
                op = op + a * oc[j];
                dp = dp + a * Interval<double>(double(r.direction[j]));
            }
            op_[i] = op;
            dp_[i] = dp;
            const int s = dp.certain_sign();
            sden_[i] = s != 2 ? s : exact_den_sign(i);
        }
    }
    ObbFrame(const Ray<T>& r, const Obb<T>& b, certified_t) : r_(&r), b_(&b) {
        constexpr double g4 = 2 * gamma<double>(4), g3 = 2 * gamma<double>(3), eta = 0x1p-1022;
        double oc[3], d[3];
        for (int j = 0; j < 3; ++j) {
            oc[j] = double(r.origin[j]) - double(b.center[j]);
            d[j] = double(r.direction[j]);
        }
        for (int i = 0; i < 3; ++i) {
            double op = 0, dp = 0, so = 0, sd = 0;
            for (int j = 0; j < 3; ++j) {
                const double a = b.axes(j, i), x = a * oc[j], y = a * d[j];
                op += x;
                dp += y;
                so += std::abs(x);
                sd += std::abs(y);
            }
            op_[i] = around(op, g4 * so + eta);
            dp_[i] = around(dp, g3 * sd + eta);
            const int s = dp_[i].certain_sign();
            sden_[i] = s != 2 ? s : exact_den_sign(i);
        }
    }
    int den_sign(int i) const { return sden_[i]; }
    bool inside_parallel(int i) const {
        const double h = b_->half_extent[i];
        if (-h <= op_[i].lo && op_[i].hi <= h) return true;
        if (op_[i].lo > h || op_[i].hi < -h) return false;
        return inside_parallel_exact(i);
    }
    // The same decisions without the interval filter (the exact stage alone).
    bool inside_parallel_exact(int i) const {
        const double h = b_->half_extent[i];
        const std::optional<bool> in = with_exact(safe(), [&](auto tag) -> std::optional<bool> {
            using E = typename decltype(tag)::type;
            const E o = oprime<E>(i), eh(h);
            const E above = eh - o, below = eh + o;
            if (any_overflowed(above, below)) return std::nullopt;
            return above.sign() >= 0 && below.sign() >= 0;
        });
        return *in;
    }
    Interval<double> enclose(int i, int side) const {
        const double h = b_->half_extent[i];
        return divide_signed(Interval<double>(side ? h : -h) - op_[i], dp_[i], sden_[i]);
    }
    template <class E> E num(int i, int side) const {
        const double h = b_->half_extent[i];
        return E(side ? h : -h) - oprime<E>(i);
    }
    template <class E> E den(int i) const {
        E s(0.0);
        for (int j = 0; j < 3; ++j) s = s + E(double(b_->axes(j, i))) * E(double(r_->direction[j]));
        return s;
    }
    bool safe() const {
        return expansion_safe(r_->origin) && expansion_safe(r_->direction) && expansion_safe(b_->center) &&
               expansion_safe(b_->axes) && expansion_safe(b_->half_extent);
    }
    // t faithfully rounded to T: by pin_quotient first (for float the faithful double
    // rounded to nearest), next from the enclosure when it pins one float, else exactly.
    T faithful(int i, int side, const Interval<double>& v, bool& went_exact) const {
        if (const PinnedQuotient x = pin_quotient(obb_slab_sums(*r_, *b_, i, side)); x.pinned) return faithful_to<T>(x.c);
        if (const std::optional<T> t = faithful_from_enclosure<T>(v)) return *t;
        RAYPROOF_COUNT_EXACT(went_exact);
        return exact_faithful<T>(*this, i, side);
    }

    int den_sign_exact(int i) const { return exact_den_sign(i); }

private:
    static Interval<double> around(double v, double e) {
        constexpr double inf = std::numeric_limits<double>::infinity();
        if (!(e <= std::numeric_limits<double>::max())) return {-inf, inf};
        return {step_down(v - e), step_up(v + e)};
    }
    template <class E> E oprime(int i) const {
        E s(0.0);
        for (int j = 0; j < 3; ++j)
            s = s + E(double(b_->axes(j, i))) * (E(double(r_->origin[j])) - E(double(b_->center[j])));
        return s;
    }
    int exact_den_sign(int i) const {
        return *with_exact(safe(), [&](auto tag) -> std::optional<int> {
            using E = typename decltype(tag)::type;
            const E d = den<E>(i);
            if (d.overflowed()) return std::nullopt;
            return d.sign();
        });
    }
    const Ray<T>* r_;
    const Obb<T>* b_;
    Interval<double> op_[3], dp_[3];
    int sden_[3];
};

template <class T> Hit<T> query(const Ray<T>& r, const PreparedObb<T>& p, conservative_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    return slab_conservative(ObbFrame<T>(r, p.box), r.t_min, r.t_max);
}

template <class T> Hit<T> query(const Ray<T>& r, const PreparedObb<T>& p, certified_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    return slab_certified(ObbFrame<T>(r, p.box, certified_t{}), r.t_min, r.t_max);
}

}  // namespace rayproof::detail
