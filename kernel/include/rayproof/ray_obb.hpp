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
//            conservative — in the pbrt-v4 manner first (obb_conservative_common):
//            o'_i, d'_i and the slab values in plain double, each slab value widened by
//            the bound the certified path derives for it (static gamma(n) bounds of the
//            frame, then of the quotient), the latest lower bound of an entry and the
//            earliest upper bound of an exit taken, while every slab is far from
//            parallel to the ray (|d'_i| >= 2^20 times its bound). For float input the
//            same in float first, one bound per axis, answering where it decides the
//            verdict with room to spare (else the double one). Otherwise: o'_i, d'_i
//            and the slab values are evaluated in interval
//            arithmetic with outward rounding (detail/interval.hpp), in double for both
//            scalar types; the exact sign of d'_i is used when its interval holds 0 (a
//            nearly parallel slab whose sign is unknown gives the half-line of values
//            on the side its numerator allows, or no constraint at all).
//            certified — straight-line code first (obb_certified_common): o'_i and d'_i
//            from one plain evaluation in double with static bounds, each slab value
//            with its own bound, the winners and the verdict proven in two lanes as for
//            the aligned box, and each winning value rounded faithfully by pinning it
//            from double-word num and den (detail/compensated.hpp; for float the
//            faithful double rounded to nearest). What these bounds leave undecided
//            (close values: rays through edges and corners; nearly parallel slabs)
//            goes to a second stage (obb_certified_stage): the general path's
//            decisions over the same bounds, each comparison they leave decided
//            exactly, first from double-word num and den (word_compare), which decide
//            exact ties of integer-like input and the nearly equal values; it answers
//            as the general path does, bit for bit. The general path: o'_i and d'_i
//            enclosed by the same static bounds
//            gamma(4)·Σ|a_ji (o_j - c_j)| and gamma(3)·Σ|a_ji d_j| (derivation at
//            ObbFrame), then the slab values in interval arithmetic; these intervals
//            decide every comparison they separate; the rest, and the sign of d'_i, are
//            decided exactly: num = ±h_i - Σ_j a_ji (o_j - c_j) and den = Σ_j a_ji d_j
//            are degree 2, comparisons of two slab values degree 4 (detail/exact.hpp),
//            each taken first from double-word pairs, then from fixed-size sums of
//            error-free products (detail/affine_quotients.hpp, shared with the plane),
//            on the input rescaled by powers of two where it is outside the Expansion
//            type's range. t is pinned as on the straight-line path first (so the paths
//            answer alike bit for bit), then from the pairs of the exact side, next
//            rounded from the interval when it lies strictly between the neighbours of
//            its midpoint, else exactly (from the same sums first).
#pragma once

#include <rayproof/detail/affine_quotients.hpp>
#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/compensated.hpp>
#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/detail/lanes.hpp>
#include <rayproof/detail/prepared.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/detail/slab_certified.hpp>
#include <rayproof/detail/slab_fast.hpp>
#include <rayproof/detail/validate.hpp>
#include <rayproof/prepared_ray.hpp>

namespace rayproof::detail {

template <class T> struct PreparedObb {
    Obb<T> box;
    Vec3<T> lo, hi;  // -half_extent, half_extent
    bool ok;
};
template <class T> PreparedObb<T> prepare(const Obb<T>& b) { return {b, -b.half_extent, b.half_extent, valid(b)}; }

template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Hit<T> query(const R& ray, const PreparedObb<T>& p, fast_t) {
    if (!p.ok || !valid(ray)) return invalid_hit<T>();
    const Ray<T>& r = ray_of(ray);
    const Vec3<T> o = p.box.axes.transpose() * (r.origin - p.box.center);
    const Vec3<T> d = p.box.axes.transpose() * r.direction;
    return slab_fast(o.data(), d.data(), p.lo.data(), p.hi.data(), r.t_min, r.t_max);
}

// The slab value (±h_i - o'_i)/d'_i as num = ±h_i - Σ_j a_ji (o_j - c_j) over den =
// Σ_j a_ji d_j, as double-word sums (affine_row_sums, detail/affine_quotients.hpp) for
// pin_quotient; not ok when an input is out of quotient_sums' range.
template <class T> RAYPROOF_ALWAYS_INLINE QuotientSums obb_slab_sums(const Ray<T>& r, const Obb<T>& b, int i, int side) {
    double a[3], o[3], c[3], d[3];
    for (int j = 0; j < 3; ++j) {
        a[j] = double(b.axes(j, i));
        o[j] = double(r.origin[j]);
        c[j] = double(b.center[j]);
        d[j] = double(r.direction[j]);
    }
    return affine_row_sums(double(b.half_extent[i]), side, a, o, c, d);
}

// The certified float answer for slab value (i, side): its conservative enclosure
// [fl(t~ - E), fl(t~ + E)] (obb_conservative_common's derivation, in the same operations:
// o'_i~ and d'_i~ in plain double, E = 2·((eo + |num~|(u + ed·|inv|))·|inv| + 3u|t~|) +
// 2^-1022, valid while ed_i <= 2^-20|d'_i~| and |inv| >= 2^-1022, the bound finite), and
// t rounded to the nearest float where both its ends round to one (nearest_float).
// Every product is rounded() (class C3), so whether it answers is the same bits in every
// inlined copy; the general path tries it first too (ObbFrame::faithful), so the two
// paths answer alike bit for bit. For float input: in double, with room to spare (a
// float step is some 2^29 times the unit roundoff of double).
template <class T>
RAYPROOF_ALWAYS_INLINE Pinned<float> obb_nearest_float(const Ray<T>& r, const Obb<T>& b, int i, int side) {
    static_assert(std::is_same_v<T, float>);
    constexpr double g4 = 2 * gamma<double>(4), g3 = 2 * gamma<double>(3), eta = 0x1p-1022, u = unit_roundoff<double>;
    double x[3], y[3];
    for (int j = 0; j < 3; ++j) {
        const double a = b.axes(j, i);
        x[j] = rounded(a * (double(r.origin[j]) - double(b.center[j])));
        y[j] = rounded(a * double(r.direction[j]));
    }
    const double op = (x[0] + x[1]) + x[2], dp = (y[0] + y[1]) + y[2];
    const double eo = rounded(g4 * ((std::abs(x[0]) + std::abs(x[1])) + std::abs(x[2]))) + eta,
                 ed = rounded(g3 * ((std::abs(y[0]) + std::abs(y[1])) + std::abs(y[2]))) + eta;
    const double h = b.half_extent[i], inv = 1 / dp, ai = std::abs(inv);
    const double num = (side ? h : -h) - op, t = rounded(num * inv);
    const double k = u + rounded(ed * ai);
    const double e = 2 * (rounded((eo + rounded(std::abs(num) * k)) * ai) + rounded(3 * u * std::abs(t))) + eta;
    const bool ok = int(ed <= 0x1p-20 * std::abs(dp)) & int(ai >= eta) & int(e <= std::numeric_limits<double>::max());
    return nearest_float(t - e, t + e, ok);
}

// Slab value (i, side) faithfully rounded to T where the straight-line steps can vouch
// for it: for float the nearest float from its enclosure (obb_nearest_float), else
// pin_quotient's candidate (for float the faithful double rounded to nearest). Both paths
// round their winners with it (obb_certified_common, ObbFrame::faithful), so they answer
// alike bit for bit; not ok leaves the value to what each path does next.
template <class T> RAYPROOF_ALWAYS_INLINE Pinned<T> obb_pinned_value(const Ray<T>& r, const Obb<T>& b, int i, int side) {
    if constexpr (std::is_same_v<T, float>)
        if (const Pinned<float> f = obb_nearest_float(r, b, i, side); f.ok) return f;
    const PinnedQuotient x = pin_quotient(obb_slab_sums(r, b, i, side));
    return {faithful_to<T>(x.c), x.pinned};
}

// The box's slab values as affine quotients (detail/affine_quotients.hpp): rows a_i the
// axes, c the centre, h_i the half-extents.
template <class T> AffineValues<3> obb_values(const Ray<T>& r, const Obb<T>& b) {
    AffineValues<3> v;
    for (int j = 0; j < 3; ++j) {
        v.o[j] = double(r.origin[j]);
        v.c[j] = double(b.center[j]);
        v.d[j] = double(r.direction[j]);
        v.h[j] = double(b.half_extent[j]);
        for (int i = 0; i < 3; ++i) v.a[i][j] = double(b.axes(j, i));
    }
    return v;
}
using ObbQuotients = AffineQuotients<3>;

// Row i of the certified frame (ObbFrame's certified constructor, the derivation there):
// o'_i and d'_i from one plain evaluation in double, each enclosed by its static bound
// and one step outward. Out of line, so that every caller (the general path's frame, the
// second stage's rounding, obb_certified_stage) has the same bits whatever the
// includer's contraction.
struct ObbRow {
    Interval<double> op, dp;
};
template <class T> [[gnu::noinline]] ObbRow obb_certified_row(const Ray<T>& r, const Obb<T>& b, int i) {
    constexpr double g4 = 2 * gamma<double>(4), g3 = 2 * gamma<double>(3), eta = 0x1p-1022;
    constexpr double inf = std::numeric_limits<double>::infinity();
    double op = 0, dp = 0, so = 0, sd = 0;
    for (int j = 0; j < 3; ++j) {
        const double a = b.axes(j, i), x = a * (double(r.origin[j]) - double(b.center[j])), y = a * double(r.direction[j]);
        op += x;
        dp += y;
        so += std::abs(x);
        sd += std::abs(y);
    }
    const auto around = [](double v, double e) -> Interval<double> {
        if (!(e <= std::numeric_limits<double>::max())) return {-inf, inf};
        return {step_down(v - e), step_up(v + e)};
    };
    return {around(op, g4 * so + eta), around(dp, g3 * sd + eta)};
}
// Slab value (i, side) enclosed from its row, given the exact sign of d'_i (nonzero).
template <class T> Interval<double> obb_enclose(const Obb<T>& b, int i, int side, const ObbRow& row, int sden) {
    const double h = b.half_extent[i];
    return divide_signed(Interval<double>(side ? h : -h) - row.op, row.dp, sden);
}

// Whether the origin lies in the closed slab i of a box whose d'_i is 0, from the exact
// signs of a source over its slab values (AffineSource's, as exact_den_sign): h - o' >= 0
// and h + o' >= 0, that is num(i, 1) >= 0 >= num(i, 0).
template <class Source> bool obb_inside_parallel_exact(const Source& src, int i) {
    return src.exact_num_sign(i, 1) >= 0 && src.exact_num_sign(i, 0) <= 0;
}
// The same from an enclosure of o'_i where it decides, else exactly.
template <class Source> bool obb_inside_parallel(const Source& src, double h, const Interval<double>& op, int i) {
    if (-h <= op.lo && op.hi <= h) return true;
    if (op.lo > h || op.hi < -h) return false;
    return obb_inside_parallel_exact(src, i);
}

// The box's exact side alone (AffineSource over its slab values as ObbQuotients), for
// the second stage (obb_certified_stage): exact_compare and exact_faithful on it decide
// and round as on ObbFrame, whose exact side is the same.
template <class T> class ObbExact : public AffineSource<3, ObbExact<T>> {
    friend AffineSource<3, ObbExact<T>>;

public:
    ObbExact(const Ray<T>& r, const Obb<T>& b) : AffineSource<3, ObbExact<T>>(std::is_same_v<T, float>), r_(&r), b_(&b) {}

private:
    AffineValues<3> affine_values() const { return obb_values(*r_, *b_); }
    const Ray<T>* r_;
    const Obb<T>* b_;
};

// Slab value (i, side) faithfully rounded from the straight-line steps and the
// double-word sums, where they vouch for it: obb_pinned_value, then word_faithful on the
// box's exact side (src: the frame's or the second stage's), the two first steps of
// ObbFrame::faithful and of obb_certified_stage's rounding. Where src is safe() (every
// float input; double input in [2^-100, 2^100] or 0), word_faithful pins the input as
// given from the same sums bit for bit (affine_row_sums, as obb_slab_sums; in range for
// quotient_sums, so both ok alike), so a pin that failed would fail again: there the
// pin is taken from src's sums alone, which its comparisons have mostly made already.
// The same answers as the two steps in turn, for either caller.
template <class T, class Source>
std::optional<T> obb_word_rounding(const Ray<T>& r, const Obb<T>& b, const Source& src, int i, int side) {
    if constexpr (std::is_same_v<T, float>)
        if (const Pinned<float> f = obb_nearest_float(r, b, i, side); f.ok) return f.t;
    if (!src.safe())
        if (const PinnedQuotient x = pin_quotient(obb_slab_sums(r, b, i, side)); x.pinned) return faithful_to<T>(x.c);
    return src.template word_faithful<T>(i, side);
}

// The slab frame of an oriented box: o'_i = (o - c)·a_i, d'_i = d·a_i, slab
// [-h_i, h_i]; value (±h_i - o'_i)/d'_i. Its exact side (num, den, safe, quick_compare,
// quick_faithful, scaled) is AffineSource's, on the slab values as ObbQuotients.
template <class T> class ObbFrame : public AffineSource<3, ObbFrame<T>> {
    using Source = AffineSource<3, ObbFrame<T>>;
    friend Source;

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
    // Contraction (detail/eft.hpp): class C1; a fused a_ji·Δ~_j enters the sum with
    // rounding error 0, and the bound, taken on the rounded |products|, is off from the
    // exact ones' by a factor 1 + u at most, which the doubling covers.
    ObbFrame(const Ray<T>& r, const Obb<T>& b) : Source(std::is_same_v<T, float>), r_(&r), b_(&b) {
        Interval<double> oc[3];
        for (int j = 0; j < 3; ++j) oc[j] = Interval<double>(double(r.origin[j])) - Interval<double>(double(b.center[j]));
        for (int i = 0; i < 3; ++i) {
            Interval<double> op(0.0), dp(0.0);
            for (int j = 0; j < 3; ++j) {
                const double a = double(b.axes(j, i));
                op = op + times_point(oc[j], a);
                dp = dp + times_point(Interval<double>(a), double(r.direction[j]));
            }
            op_[i] = op;
            dp_[i] = dp;
            const int s = dp.certain_sign();
            sden_[i] = s != 2 ? s : this->exact_den_sign(i);
        }
    }
    ObbFrame(const Ray<T>& r, const Obb<T>& b, certified_t) : Source(std::is_same_v<T, float>), r_(&r), b_(&b) {
        for (int i = 0; i < 3; ++i) {
            const ObbRow row = obb_certified_row(r, b, i);
            op_[i] = row.op;
            dp_[i] = row.dp;
            const int s = dp_[i].certain_sign();
            sden_[i] = s != 2 ? s : this->exact_den_sign(i);
        }
    }
    int den_sign(int i) const { return sden_[i]; }
    bool inside_parallel(int i) const { return obb_inside_parallel(*this, double(b_->half_extent[i]), op_[i], i); }
    Interval<double> enclose(int i, int side) const { return obb_enclose(*b_, i, side, {op_[i], dp_[i]}, sden_[i]); }
    // t faithfully rounded to T, as the straight-line path rounds it (so that the two
    // paths answer alike bit for bit): obb_pinned_value (for float by obb_nearest_float
    // first, then by pin_quotient: the faithful double rounded to nearest), then
    // word_faithful (the same pin on the input as given where it is safe for the
    // double-word comparisons, else on the rescaled one), the two as obb_word_rounding
    // takes them, as obb_certified_stage does; next from the interval when it pins one
    // float, else exactly.
    T faithful(int i, int side, const Interval<double>& v, bool& went_exact) const {
        if (const std::optional<T> t = obb_word_rounding(*r_, *b_, *this, i, side)) return *t;
        if (const std::optional<T> t = faithful_from_enclosure<T>(v)) return *t;
        RAYPROOF_COUNT_EXACT(went_exact);
        return exact_faithful<T>(*this, i, side);
    }

    // The same decision without the interval filter (the exact stage alone).
    bool inside_parallel_exact(int i) const { return obb_inside_parallel_exact(*this, i); }

private:
    AffineValues<3> affine_values() const { return obb_values(*r_, *b_); }
    const Ray<T>* r_;
    const Obb<T>* b_;
    Interval<double> op_[3], dp_[3];
    int sden_[3];
};

static_assert(SlabFrame<ObbFrame<float>, float> && SlabFrame<ObbFrame<double>, double>);

// The conservative answer by interval arithmetic per operation (ObbFrame, exact signs
// where the intervals hold 0): what obb_conservative_common declines (slabs parallel or
// nearly parallel to the ray, extreme exponents), out of line. The inputs are valid.
template <class T> [[gnu::noinline, gnu::cold]] Hit<T> obb_conservative_general(const Ray<T>& r, const Obb<T>& b) {
    return slab_conservative(ObbFrame<T>(r, b), r.t_min, r.t_max);
}

// The conservative answer in the pbrt-v4 manner (obb_enclosure): the change of frame and
// the slab values in plain arithmetic, in double for double input, each slab value t~
// widened by a bound E derived from the one at obb_certified_common: o'_i and d'_i within
// eo_i = 2·gamma(4)·Σ|a_ji Δ~_j| + eta and ed_i = 2·gamma(3)·Σ|a_ji d_j| + eta (the
// derivation at ObbFrame's certified constructor, eta = 2^-1022), and while ed_i <=
// 2^-20|d'_i~| (which also makes the sign of d'_i, and so the side entered, certain),
//     |t - t~| <= (1 + 2^-19)(eo + |num~|(u + ed·|inv|(1 + 2u)))·|inv| + 3u|t~|
//              <= (1 + 2^-18)·B + 2^-1074,   B = eo·|inv| + |t~|·(ed·|inv| + 5u),
// as |num~|·|inv| <= (|t~| + 2^-1075)/(1 - u) (t~ = fl(num~·inv)). The code takes E =
// 2·(eo·|inv| + |t~|·(ed·|inv| + 5u)) + eta, each value's own: five roundings leave E >=
// 2(1 - u)^5·B + (1 - u)·eta - 2^-1074 (ed·|inv| is normal, as the plane's e_D·|inv|),
// more than |t - t~| + u(|t~| + E) (B >= 5u|t~|), so fl(t~ - E) and fl(t~ + E) are a
// lower and an upper bound of t. The side entered is picked first (a pick: no jump on a
// coin toss) and the bound computed for the two values kept, the entry and the exit.
// For float input the same in float first (no conversion; float's u = 2^-24, eta =
// 2^-126, a float product's underflow at most 2^-150, Δ~_j = fl(o_j - c_j) rounded as
// double input's is: the frame's derivation holds as written), with the check ed_i <=
// 2^-10|d'_i~| (the factor (1 + 2^-19) above becomes 1/((1 - 2^-10)(1 - u)) < 1.0011)
// and one bound per axis for its two values: m = fl(h_i + |o'_i~|) is at least |num~| of
// either side (|±h_i - o'_i~| <= h_i + |o'_i~|, and rounding is monotone), so |t~| <= (1 +
// u)·m·|inv| for both, and E = 2·((eo + m·(ed·|inv| + 5u))·|inv|) + eta covers both
// values' bounds as above. That enclosure answers a miss where its entry bound lies
// above its exit bound (certain: they bound the exact entry from below and the exact
// exit from above), and a hit where certain_hit (detail/certified.hpp) proves one, with
// E_max the largest bound: the exact entry is below the entry bound plus 2·E_max and the
// exact exit above the exit bound less 2·E_max. The rest (near a graze, where float's
// bounds, some 2^29 times double's, would add false hits) goes on to the double
// enclosure: every hit of the float path is a hit of the double one. Its ends are wider
// than the double enclosure's (one float step from the exact value on general input):
// on the `general` cases 46 float steps at the median, 546 at the 99th percentile, more
// where a slab is nearly parallel to the ray or the origin lies near a face (the one
// bound per axis is in units of its far side). On input whose products are subnormal
// in float the float stage pays a microcode assist per such operation (extreme input:
// 225 ns a query against 43 on uniform); a check that keeps it off inputs outside
// [2^-32, 2^32] was measured (extreme 57 ns) and not taken: it cost 11 % on uniform
// input, where every vector instruction adds to the throughput.
// The exact entry is max(t_min, max_i t_in_i) and each exact t_in_i lies above its
// fl(t~ - E): the largest of these lower bounds (and t_min) is a lower bound of the
// entry; likewise the smallest of the upper bounds of the exits (and t_max) is an upper
// bound of the exit. So a hit of the exact answer is a hit here and [t_enter, t_exit]
// encloses it. face is the axis of the largest lower bound (the mode may differ on
// ties).
// Range: every |fl(1/d'_i)| normal (>= eta; the ratio check keeps it finite, ed_i >=
// eta) and every bound finite, else obb_conservative_general.
// Contraction (detail/eft.hpp): class C1, as obb_certified_common's bounds.
template <class C> struct ObbBounds;  // the constants of the enclosures computed in C
template <> struct ObbBounds<double> {
    static constexpr double ratio = 0x1p-20;
};
template <> struct ObbBounds<float> {
    static constexpr float ratio = 0x1p-10f;
};
template <class C> struct ObbEnclosure {
    C lo, hi;  // a lower bound of the exact entry, an upper bound of the exact exit
    C e_max;   // the largest bound E of the slab values (float only; 0 in double)
    int face;  // the axis and side of the largest lower bound
    bool ok;   // every slab value's bound holds (finite, its slab not nearly parallel)
};
template <class C, class T>
RAYPROOF_ALWAYS_INLINE ObbEnclosure<C> obb_enclosure(const Ray<T>& r, const Obb<T>& b) {
    static_assert(sizeof(C) >= sizeof(T), "the frame is computed in T or wider");
    constexpr C g4 = 2 * gamma<C>(4), g3 = 2 * gamma<C>(3), eta = std::numeric_limits<C>::min(),
                u = unit_roundoff<C>, ratio = ObbBounds<C>::ratio;
    C oc[3], d[3];
    RAYPROOF_UNROLL3
    for (int j = 0; j < 3; ++j) {
        oc[j] = C(r.origin[j]) - C(b.center[j]);
        d[j] = C(r.direction[j]);
    }
    C lo = C(r.t_min), hi = C(r.t_max), probe = 0, e_max = 0;
    int face = -1, ok = 1;
    RAYPROOF_UNROLL3
    for (int i = 0; i < 3; ++i) {
        const C a0 = b.axes(0, i), a1 = b.axes(1, i), a2 = b.axes(2, i);
        const C x0 = a0 * oc[0], x1 = a1 * oc[1], x2 = a2 * oc[2], y0 = a0 * d[0], y1 = a1 * d[1], y2 = a2 * d[2];
        const C op = (x0 + x1) + x2, dp = (y0 + y1) + y2;
        const C eo = g4 * ((std::abs(x0) + std::abs(x1)) + std::abs(x2)) + eta,
                ed = g3 * ((std::abs(y0) + std::abs(y1)) + std::abs(y2)) + eta;
        const C h = b.half_extent[i], inv = 1 / dp, ai = std::abs(inv);
        ok &= int(ed <= ratio * std::abs(dp)) & int(ai >= eta);
        const C t0 = (-h - op) * inv, t1 = (h - op) * inv;  // sides 0 and 1
        const bool neg = dp < 0;                             // side 1 is entered
        const C t_in = pick(neg, t1, t0), t_out = pick(neg, t0, t1);  // no jump on a coin toss
        const C k = ed * ai + 5 * u;
        C in_lo, out_hi;
        if constexpr (std::is_same_v<C, float>) {
            const C e = 2 * ((eo + (h + std::abs(op)) * k) * ai) + eta;
            in_lo = t_in - e;
            out_hi = t_out + e;
            e_max = e > e_max ? e : e_max;
        } else {
            const C w = eo * ai;
            in_lo = t_in - (2 * (w + std::abs(t_in) * k) + eta);
            out_hi = t_out + (2 * (w + std::abs(t_out) * k) + eta);
        }
        probe += (in_lo - in_lo) + (out_hi - out_hi);
        face = pick_int(in_lo > lo, 2 * i + int(neg), face);
        lo = in_lo > lo ? in_lo : lo;
        hi = out_hi < hi ? out_hi : hi;
    }
    return {lo, hi, e_max, face, bool(ok & int(probe == 0))};
}
template <class T> RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> obb_conservative_common(const Ray<T>& r, const Obb<T>& b) {
    if constexpr (std::is_same_v<T, float>) {
        const ObbEnclosure<float> f = obb_enclosure<float>(r, b);
        const bool miss = f.lo > f.hi, hit = certain_hit(f.lo, f.hi, f.e_max);
        if (int(f.ok) & (int(hit) | int(miss))) [[likely]]
            return hit_when(hit, f.lo, f.hi, f.face);
    }
    const ObbEnclosure<double> e = obb_enclosure<double>(r, b);
    if (!e.ok) [[unlikely]]
        return std::nullopt;
    return hit_when(e.lo <= e.hi, round_down_to<T>(e.lo), round_up_to<T>(e.hi), e.face);
}

template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Hit<T> query(const R& ray, const PreparedObb<T>& p, conservative_t) {
    if (!p.ok || !valid(ray)) return invalid_hit<T>();
    const Ray<T>& r = ray_of(ray);
    return common_or_fallback(obb_conservative_common(r, p.box), [&] { return obb_conservative_general(r, p.box); });
}

// The certified answer's second stage, for what the straight-line path leaves undecided:
// entries or exits whose enclosures overlap (rays through edges and corners, or nearly
// so), slabs nearly parallel to the ray, values not finite. The general path's slab
// method (slab_certified: a slab parallel to the ray with the origin outside it is a
// miss; t_min, then the axes in order, an entry replaced only by a strictly greater
// value and an exit only by a strictly smaller one; then the order of the two) over the
// straight-line path's enclosures where they hold (known, bit i: slab i far from
// parallel and every value finite): lo[i] = V - E and hi[i] = V + E, lane 0 the entry,
// lane 1 the exit negated, the side entered from `negative`; for another slab, the
// frame's enclosures of its row (obb_certified_row), the sign of d'_i and the origin's
// place in a parallel slab decided as the frame decides them. Every comparison the
// enclosures leave is decided exactly (exact_compare on the box's exact side,
// ObbExact: the exact rows, the double-word pairs, then the exact sums, then the exact
// types), and the winners are rounded as ObbFrame::faithful rounds them
// (obb_word_rounding, the frame's enclosure of the value, exact_faithful). Every
// decision being the exact one and every rounding the same, it answers as the general
// path does, bit for bit, without building the frame's six enclosures where the
// straight-line path's hold.
template <class T>
[[gnu::noinline]] Hit<T> obb_certified_stage(const Ray<T>& r, const Obb<T>& b, const lanes::D2 (&lo)[3],
                                             const lanes::D2 (&hi)[3], int negative, int known) {
    using lanes::lane0, lanes::lane1;
    bool went_exact = false;
    const ObbExact<T> src(r, b);
    int sden[3];  // the exact sign of d'_i
    SlabEnclosures v;
    for (int i = 0; i < 3; ++i) {
        const bool enclosed = ((known >> i) & 1) && std::isfinite(lane0(lo[i])) && std::isfinite(lane0(hi[i])) &&
                              std::isfinite(lane1(lo[i])) && std::isfinite(lane1(hi[i]));
        if (enclosed) {
            sden[i] = ((negative >> i) & 1) ? -1 : 1;
            v.in[i][0] = lane0(lo[i]), v.in[i][1] = lane0(hi[i]);
            v.out[i][0] = -lane1(hi[i]), v.out[i][1] = -lane1(lo[i]);
            continue;
        }
        // as the frame: its row's enclosures, the exact signs where they hold 0
        const ObbRow row = obb_certified_row(r, b, i);
        const int s = row.dp.certain_sign();
        sden[i] = s != 2 ? s : src.exact_den_sign(i);
        if (sden[i] == 0) {  // parallel: a miss unless the origin lies in the closed slab
            if (!obb_inside_parallel(src, double(b.half_extent[i]), row.op, i)) return Hit<T>{};
            continue;
        }
        const Interval<double> v_in = obb_enclose(b, i, sden[i] > 0 ? 0 : 1, row, sden[i]),
                               v_out = obb_enclose(b, i, sden[i] > 0 ? 1 : 0, row, sden[i]);
        v.in[i][0] = v_in.lo, v.in[i][1] = v_in.hi;
        v.out[i][0] = v_out.lo, v.out[i][1] = v_out.hi;
    }
    // As ObbFrame::faithful, with the frame's enclosure of the value made for it alone.
    const auto round = [&](const SlabRef& x, const Interval<double>&) -> T {
        if (const std::optional<T> t = obb_word_rounding(r, b, src, x.axis, x.side)) return *t;
        const Interval<double> e = obb_enclose(b, x.axis, x.side, obb_certified_row(r, b, x.axis), sden[x.axis]);
        if (const std::optional<T> t = faithful_from_enclosure<T>(e)) return *t;
        RAYPROOF_COUNT_EXACT(went_exact);
        return exact_faithful<T>(src, x.axis, x.side);
    };
    const Hit<T> h = slab_decide(src, sden, v, r.t_min, r.t_max, went_exact, round);
    RAYPROOF_COUNT_FLUSH(went_exact);
    return h;
}

// The certified answer's common case in straight-line code, as the box's
// (aabb_certified_common): the entry problem in lane 0 and the exit problem, negated, in
// lane 1 of detail/lanes.hpp, but each slab value with its own bound, since the frame's
// errors are not relative to the value.
// Frame: o'_i~ = fl(Σ_j a_ji fl(o_j - c_j)) and d'_i~ = fl(Σ_j a_ji d_j), within eo_i =
// 2·gamma(4)·Σ|a_ji Δ~_j| + 2^-1022 and ed_i = 2·gamma(3)·Σ|a_ji d_j| + 2^-1022 of the
// exact o'_i, d'_i (the derivation is at ObbFrame's certified constructor). The path asks
// ed_i <= 2^-20|d'_i~| (the sign of d'_i is then certain and the ray is not nearly
// parallel to the slab).
// Slab values: num~ = fl(±h_i - o'_i~) is within eo + u|num~| of the exact numerator,
// inv = fl(1/d'_i~) and t~ = fl(num~·inv). With t = num/d'_i,
//     |t - num~/d'~| <= (|num - num~| + |num~|·ed·|1/d'~|)/(|d'~| - ed)
//                    <= (eo + |num~|(u + ed·|inv|(1 + 2u)))·|inv|(1 + 2^-19),
// and |t~ - num~/d'~| <= 3u|t~| (the roundings of inv and of the product), so E =
// 2·((eo + |num~|(u + ed·|inv|))·|inv| + 3u|t~|) + 2^-1022 bounds |t - t~| (the doubling
// covers the factors above and the bound's own roundings; 2^-1022 the underflow of its
// products).
// Winners: per lane, the axis w of the largest value wins certainly when its lower
// bound V_w - E_w lies above the upper bound V_j + E_j of every other axis (exactly one
// upper bound reaches it: w's own), and above the limit (t_min, or -t_max in lane 1);
// the limit wins certainly when every upper bound lies below it. The verdict is certain
// when the entry's upper bound lies below the exit's lower bound (a hit) or the entry's
// lower bound above the exit's upper bound (a miss, which needs no winner). All of it
// runs without a branch on the ray's direction; each winning slab value is then rounded
// as the general path rounds it first: for float to the nearest float from its own
// enclosure (obb_nearest_float), else by pin_quotient (obb_slab_sums). Anything these
// checks cannot vouch for (a value not finite, a slab nearly parallel, close values, a
// value pin_quotient cannot pin) goes to the general path.
template <class T>
RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> obb_certified_common(const Ray<T>& r, const Obb<T>& b) {
    using namespace lanes;
    constexpr double g4 = 2 * gamma<double>(4), g3 = 2 * gamma<double>(3), eta = 0x1p-1022, u = unit_roundoff<double>;
    D2 delta_d[3];  // (fl(o_j - c_j), d_j)
    for (int j = 0; j < 3; ++j)
        delta_d[j] = make(double(r.origin[j]) - double(b.center[j]), double(r.direction[j]));
    D2 V[3], E[3], probe = splat(0.0);
    int negative = 0;  // bit i: d'_i < 0
    int slabs_ok = 0;  // bit i: slab i far from parallel (its bounds below hold)
    for (int i = 0; i < 3; ++i) {
        D2 od = splat(0.0), mag = splat(0.0);  // (o'_i, d'_i) and the sums of their terms' magnitudes
        for (int j = 0; j < 3; ++j) {
            const D2 x = splat(double(b.axes(j, i))) * delta_d[j];
            od = od + x;
            mag = mag + abs(x);
        }
        const D2 err = mag * make(g4, g3) + splat(eta);
        const double op = lane0(od), dp = lane1(od), eo = lane0(err), ed = lane1(err), h = double(b.half_extent[i]);
        const double inv = 1 / dp, ai = std::abs(inv);
        slabs_ok |= int(ed <= 0x1p-20 * std::abs(dp)) << i;
        // t is rounded() (detail/eft.hpp, class C3): the probe and the comparisons take
        // the same values; every bound here is class C1.
        const D2 num = make(-h - op, h - op), t = rounded(num * splat(inv));  // sides 0 and 1
        const D2 e = (splat(eo) + abs(num) * splat(u + ed * ai)) * splat(ai) + splat(3 * u) * abs(t);
        const D2 bound = (e + e) + splat(eta);
        const M2 neg = splat(dp) < splat(0.0);  // side 1 is entered
        negative |= (bits(neg) & 1) << i;
        V[i] = negate_lane1(select(neg, swap(t), t));
        E[i] = select(neg, swap(bound), bound);
        probe = (probe + (V[i] - V[i])) + (E[i] - E[i]);
    }
    const D2 L[3] = {V[0] - E[0], V[1] - E[1], V[2] - E[2]}, H[3] = {V[0] + E[0], V[1] + E[1], V[2] + E[2]};
    // The largest value per lane (w: entry axis, v: exit axis) and its lower bound.
    const M2 c1 = V[1] > V[0], c2m = V[2] > max(V[0], V[1]);
    const int c01 = bits(c1), c2 = bits(c2m), c = c01 & ~c2;
    const int w = (c & 1) | ((c2 & 1) << 1), v = ((c >> 1) & 1) | (c2 & 2);
    const D2 Lw = select(c2m, L[2], select(c1, L[1], L[0]));
    const int r0 = bits(H[0] >= Lw), r1 = bits(H[1] >= Lw), r2 = bits(H[2] >= Lw);
    const int unique = (r0 ^ r1 ^ r2) & ~(r0 & r1 & r2);  // per lane: exactly one upper bound reaches Lw
    const D2 limit = make(double(r.t_min), -double(r.t_max));
    const int axis_wins = unique & bits(Lw > limit);
    const D2 Hmax = max(max(H[0], H[1]), H[2]), Lmax = max(max(L[0], L[1]), L[2]);
    const int limit_wins = bits(Hmax < limit);
    const D2 hh = max(limit, Hmax), gg = max(limit, Lmax);
    const bool hit = int((axis_wins | limit_wins) == 3) & int(bits(hh < -swap(hh)) == 3);
    const bool miss = bits(gg > -swap(gg)) == 3;
    const bool finite = bits(probe == splat(0.0)) == 3;
    if (!(finite && slabs_ok == 7 && (hit || miss))) return obb_certified_stage(r, b, L, H, negative, finite ? slabs_ok : 0);
    Hit<T> out;
    if (!hit) return out;
    T t_enter = r.t_min, t_exit = r.t_max;
    const int side_in = (negative >> w) & 1, side_out = 1 - ((negative >> v) & 1);
    // Each winner rounded as the general path rounds it (obb_pinned_value, ObbFrame::faithful).
    if (axis_wins & 1) {
        const Pinned<T> x = obb_pinned_value(r, b, w, side_in);
        if (!x.ok) return std::nullopt;
        t_enter = x.t;
    }
    if (axis_wins & 2) {
        const Pinned<T> x = obb_pinned_value(r, b, v, side_out);
        if (!x.ok) return std::nullopt;
        t_exit = x.t;
    }
    // As slab_certified: two exact values in one gap may round apart the wrong way.
    if (t_enter > t_exit) t_enter = t_exit;
    out.verdict = Verdict::hit;
    out.t_enter = t_enter;
    out.t_exit = t_exit;
    out.face = (axis_wins & 1) ? 2 * w + side_in : -1;
    return out;
}

// The general path, out of line (it is rare).
template <class T> [[gnu::noinline, gnu::cold]] Hit<T> obb_certified_general(const Ray<T>& r, const Obb<T>& b) {
    return slab_certified(ObbFrame<T>(r, b, certified_t{}), r.t_min, r.t_max);
}

template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Hit<T> query(const R& ray, const PreparedObb<T>& p, certified_t) {
    if (!p.ok || !valid(ray)) return invalid_hit<T>();
    const Ray<T>& r = ray_of(ray);
    return common_or_general(obb_certified_common(r, p.box), [&] { return obb_certified_general(r, p.box); });
}

}  // namespace rayproof::detail
