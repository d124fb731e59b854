// rayproof/ray_polyhedron.hpp — ray against convex polyhedron.
//
// Shape:     the closed solid { p : n_k·p <= offset_k for every plane k } of a
//            ConvexPolyhedron (the normals point out). No planes: all of space. An
//            infeasible set: the empty set (always a miss). Unbounded solids are valid.
// Query:     per plane, num_k = offset_k - n_k·o and den_k = n_k·d; the ray is in the
//            closed half-space k exactly for the t with num_k - t·den_k >= 0, that is
//            t >= t_k = num_k/den_k when den_k < 0 (the ray enters through plane k),
//            t <= t_k when den_k > 0 (it leaves), every t when den_k == 0 and num_k >= 0
//            (parallel, the origin inside the half-space), no t when den_k == 0 and
//            num_k < 0. The answer is [t_enter, t_exit] = [max(t_min, entries), min(t_max,
//            exits)], a hit when t_enter <= t_exit. face = the index k of the entry
//            plane realizing t_enter, the lowest k on ties (duplicate and coincident
//            planes included); -1 when t_enter == t_min (the point at t_min is inside).
// Algorithm: the slab method generalized to k half-spaces (Kay & Kajiya, "Ray Tracing
//            Complex Scenes", SIGGRAPH 1986; E. Haines, "Fast Ray-Convex Polyhedron
//            Intersection", Graphics Gems II, 1991): one pass over the planes keeping the
//            latest entry and the earliest exit, leaving as soon as they cross.
// Degenerate cases: a ray parallel to a plane (den_k == 0 exactly, decided by the origin's
//            side, its boundary included); the origin on a plane; grazing an edge or a
//            vertex (t_enter == t_exit); duplicate and coincident planes (the lowest index
//            wins the face); no planes; infeasible and unbounded sets; a flat solid from
//            two opposite planes with equal offsets.
// Modes:     fast — the textbook loop in T: num_k and den_k are each a few roundings from
//            their values (|den~ - den| <= gamma(3)·Σ|n_j d_j|, |num~ - num| <=
//            gamma(4)·(|offset| + Σ|n_j o_j|)) and t_k one more; where den_k is of the
//            order of its own bound even its sign, and so the side, is unknown. Measured,
//            not promised; no allocation.
//            conservative — per plane N~, D~ in double with the derived bounds |N~ - N| <
//            eN, |D~ - D| < eD (e = fl(fl(gamma(5)·S~) + 2^-1022), S~ the same sum of
//            absolute values; derivation at poly_crossing); the sign of den, and the
//            origin's side for a parallel plane (den == 0 exactly), are certain from the
//            bounds or decided exactly; each crossing is enclosed around q =
//            fl(N~·fl(1/D~)) by a derived bound, its ends rounded to nearest, where den
//            is more than 32 times its bound (crossing_enclosure_quick: one division),
//            else around q = fl(N~/D~) with outward steps (crossing_enclosure), or,
//            when den is within twice its bound of 0, by the outward-rounded quotient
//            of the two enclosures (unbounded on one side then), and within 32 times its
//            bound by the intersection of the two (crossing_enclosure_conservative: a
//            ray leaving a face from gamma(22)·S of it is answered miss on it however
//            grazing, poly_leaving_margin); for float input the pass in float first
//            (quick enclosures only), answering where it decides the verdict with room
//            to spare (poly_conservative_float), else the double pass.
//            [t_enter, t_exit] = [largest entry lower bound, smallest exit upper bound],
//            which encloses the exact interval, so the verdict can only err towards hit.
//            certified — crossing_enclosure's intervals filter each comparison of the
//            pass (a crossing against the current entry or exit, entry against exit);
//            what they cannot separate is decided exactly (detail/exact.hpp,
//            detail/certified.hpp: sign(num_a·den_b - num_b·den_a)·sign(den_a)·
//            sign(den_b), degree 4; against a limit sign(num - c·den)·sign(den),
//            degree 3): first from num and den as double-word pairs with error
//            bounds (detail/compensated.hpp: word_compare), which decide every
//            comparison they separate and every exact tie of integer-like input, then
//            from fixed-size sums of error-free products (PolySource::quick_compare),
//            both on the input as given where it lies in the safe range, else scaled
//            into it by powers of two (the origin, the normals, the offsets and the
//            direction each by their own), then in Shewchuk expansions, or BigDyadic
//            beyond their safe range (2^±1000 scaling, denormals: there the bounds
//            overflow, or their 2^-1022 floor swamps the values, and the filter
//            declines what it cannot separate). The verdict and the face
//            are exact; the winners' t is faithfully rounded: a plane ±e_i as the box's
//            slab values are (so a polyhedron of a box's planes answers as the box, bit
//            for bit), any other plane as the plane's crossing is (for float the
//            nearest float from its enclosure first, then plane_pin, the interval, else
//            an exact quotient). verdict() runs the same pass without the
//            rounding. No allocation, any number of planes.
#pragma once

#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/compensated.hpp>
#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/detail/prepared.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/detail/validate.hpp>
#include <rayproof/ray_aabb.hpp>
#include <rayproof/ray_plane.hpp>
#include <rayproof/types.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <span>

namespace rayproof::detail {

// A polyhedron is prepared by reference (detail/prepared.hpp): its validity, every plane's,
// decided once.
template <class T> inline constexpr bool prepared_by_reference<ConvexPolyhedron<T>> = true;
template <class T> using PreparedPolyhedron = Prepared<ConvexPolyhedron<T>>;

// The end of a pass (fast mode's below, and the conservative and certified ones): the
// planes it did not vouch for checked by the rules (all of them when probe is NaN, else
// those from `from` on), then its answer.
template <class T>
RAYPROOF_ALWAYS_INLINE Hit<T> poly_checked(std::span<const Plane<T>> planes, std::size_t from, T probe, const Hit<T>& h) {
    const std::span<const Plane<T>> unchecked = probe == 0 ? planes.subspan(from) : planes;
    return valid(ConvexPolyhedron<T>{unchecked}) ? h : invalid_hit<T>();
}

// Fast mode checks the planes' validity inside its pass instead of before it (prepare()'s
// flag, a separate loop over every plane, cost as much as 40% of the query): for a valid
// ray (o finite, d finite and nonzero), num_k = offset_k - n_k·o is NaN or infinite
// whenever plane k holds a NaN or infinite number (a non-finite offset passes into num
// as it is; a non-finite n_kj makes n_kj·o_j NaN when o_j == 0, else infinite, and so
// n_k·o), and a zero normal gives den_k = 0 exactly, whose branch tests the normal. So
// the pass sums num_k - num_k (+0 for a finite num_k, NaN otherwise) and tests nonzero3
// where den_k == 0; a NaN sum (an invalid plane, or an overflow of a valid one) and the
// planes after an early miss are left to valid(), the rules themselves.
// Inlined, so that the flag prepare() computes goes unused and unevaluated.
template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> query(const Ray<T>& r, const PreparedPolyhedron<T>& p, fast_t) {
    if (!valid(r)) return invalid_hit<T>();
    Hit<T> h;
    T t0 = r.t_min, t1 = r.t_max, probe = 0;
    int face = -1;
    const std::span<const Plane<T>> planes = p.shape.planes;
    for (std::size_t k = 0; k < planes.size(); ++k) {
        const Plane<T>& q = planes[k];
        const T den = q.normal.dot(r.direction);
        const T num = q.offset - q.normal.dot(r.origin);
        probe += num - num;
        if (den == 0) {
            if (!nonzero3(q.normal.data())) return invalid_hit<T>();
            if (num < 0) return poly_checked(planes, k + 1, probe, h);  // parallel, outside
            continue;
        }
        const T t = num / den;
        if (den < 0) {
            if (t > t0) {
                t0 = t;
                face = int(k);
            }
        } else if (t < t1) {
            t1 = t;
        }
        if (t0 > t1) return poly_checked(planes, k + 1, probe, h);
    }
    h.verdict = Verdict::hit;
    h.t_enter = t0;
    h.t_exit = t1;
    h.face = face;
    if (!(probe == 0)) [[unlikely]]
        return poly_checked(planes, planes.size(), probe, h);
    return h;
}

// ---- Conservative and certified: the planes' crossings with derived bounds ------------

// One plane's num = offset - n·o and den = n·d, computed in double (exact conversions for
// float inputs) as N~ = fl(fl(fl(offset - p_0) - p_1) - p_2) and D~ = fl(fl(p_0 + p_1) +
// p_2), p_j = fl(n_j o_j) (resp. fl(n_j d_j)), with the bounds eN, eD below.
// Bound: each product is (1 + δ)·exact plus at most 2^-1075 where it falls in the
// subnormal range, each sum (1 + δ), |δ| <= u. In N~ the offset passes 3 subtractions,
// n_0 o_0 its product's rounding and 3, n_1 o_1 1 + 2, n_2 o_2 1 + 1: at most 4 roundings
// on any term (Higham, ASNA, Lemma 3.1), so |N~ - N| <= gamma(4)·S_N + 3·2^-1075·(1 +
// gamma(3)), S_N = |offset| + Σ|n_j o_j|; in D~ the first sum 0 + p_0 is exact, so at
// most 3: |D~ - D| <= gamma(3)·S_D + 3·2^-1075·(1 + gamma(2)), S_D = Σ|n_j d_j|.
// S~ (the same sums of |p_j| = fl(|n_j|·|o_j|), rounding being symmetric: nonnegative
// terms, rounded alike) is at least
// S(1 - gamma(5)) - 2^-1073. The bound is e = fl(fl(K·S~) + eta) with K = fl(gamma(5))
// and eta = 2^-1022:
//     e >= ((gamma(5)(1 - u)·S~)(1 - u) + eta)(1 - u)
//       >= gamma(5)(1 - u)^3 (1 - gamma(5))·S - 2^-1120 + eta(1 - u)
//       >  gamma(4)·S + 2^-1072          (gamma(5)(1 - u)^3(1 - gamma(5)) > gamma(4))
// so |N~ - N| < eN and |D~ - D| < eD, strictly. Contraction (detail/eft.hpp): class C1,
// a fused product-sum has fewer roundings. Overflow: a finite e means every partial sum
// of absolute values is finite, so every product and partial sum of N~ and D~ is; an
// infinite e (overflow at extreme exponents) bounds nothing, and the enclosures below
// are then the whole line, which the exact stage decides.
// The conservative pass for float input runs first in float (poly_crossing<float>: no
// conversion): the same derivation with u = 2^-24, eta = 2^-126 and a product's underflow
// at most 2^-150 (so 2^-148 in place of 2^-1072 above).
template <class C> struct Crossing {
    C N, D, eN, eD;
    bool finite_N, finite_D;  // eN (resp. eD) finite: the bound holds
};
using PolyCrossing = Crossing<double>;
template <class C = double, class T>
RAYPROOF_ALWAYS_INLINE Crossing<C> poly_crossing(const Ray<T>& r, const Plane<T>& p) {
    static_assert(sizeof(C) >= sizeof(T), "the sums are computed in T or wider");
    constexpr C K = gamma<C>(5), eta = std::numeric_limits<C>::min(), big = std::numeric_limits<C>::max();
    C N = C(p.offset), SN = std::abs(N), D = 0, SD = 0;
    for (int j = 0; j < 3; ++j) {
        const C n = C(p.normal[j]), no = n * C(r.origin[j]), nd = n * C(r.direction[j]);
        N = N - no;
        D = D + nd;
        SN = SN + std::abs(no);  // fl(|n|·|o|) = |fl(n·o)|: rounding is symmetric
        SD = SD + std::abs(nd);
    }
    const C eN = K * SN + eta, eD = K * SD + eta;
    return {N, D, eN, eD, eN <= big, eD <= big};
}

// The enclosure of num (or den) from its computed value and bound, outward rounded (the
// whole line when the bound does not hold).
inline Interval<double> around(double x, double e, bool finite) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    if (!finite) return {-inf, inf};
    return Interval<double>(x) + Interval<double>(-e, e);
}

// The crossing t = N/D enclosed, given the exact sign s != 0 of D. When both bounds hold
// and |D~| > 2·eD (D's sign is then certain and |D| > |D~|/2), from q = fl(N~/D~):
// with N = N~ + a, D = D~ + b, |a| < eN, |b| < eD and r = |N~/D~|,
//     |t - N~/D~| = |a·D~ - N~·b|/|D·D~| < (eN + r·eD)/|D| < 2(eN + r·eD)/|D~|,
// and q = (N~/D~)(1 + δ) + η (|δ| <= u, |η| <= 2^-1075), so r <= |q|(1 + 2u) + 2^-1074 and
//     |t - q| < 2(1 + 2u)(eN + |q|·eD)/|D~| + 2^-52|q| + 2^-1073.
// Computed: X = fl(fl(eN + fl(|q|·eD))/|D~|) is at least (1 - 4u)(eN + |q|·eD)/|D~| -
// 2^-1075 (three roundings; the product's underflow, at most 2^-1075 <= u·eN as eN >=
// 2^-1022, counted as a fourth), and E = fl(fl(3·X) + fl(2^-51·|q|)) + 2^-1020, rounded,
// covers the bound: 3(1 - 4u)(1 - u)^3 > 2(1 + 2u), 2^-51(1 - u)^2 > 2^-52 and 2^-1020(1 -
// u) exceeds every absolute term (each a few 2^-1075). An overflow makes E infinite
// (the whole line, still an enclosure). The ends q ∓ E are rounded outward (Interval).
// Contraction: class C1 (a fused step has fewer roundings). Otherwise (q infinite, den
// nearly 0 or a bound not holding) the outward-rounded interval quotient, unbounded on
// one side when D's enclosure holds 0 (divide_signed).
inline Interval<double> crossing_enclosure(const PolyCrossing& c, int s) {
    if (c.finite_N && c.finite_D && std::abs(c.D) > 2 * c.eD) {
        const double q = c.N / c.D, aq = std::abs(q);
        if (aq <= std::numeric_limits<double>::max()) {
            const double X = (c.eN + aq * c.eD) / std::abs(c.D);
            const double E = (3 * X + 0x1p-51 * aq) + 0x1p-1020;
            return Interval<double>(q) + Interval<double>(-E, E);
        }
    }
    return divide_signed(around(c.N, c.eN, c.finite_N), around(c.D, c.eD, c.finite_D), s);
}

// Conservative mode's enclosure of the crossing where |D~| > 32·eD (nearly every plane
// on general input: crossing_enclosure_quick), with one division and no stepping: with
// inv = fl(1/D~) normal (checked) and q = fl(N~·inv), |q - N~/D~| <= 2.01u·r + 2^-1075
// (r = |N~/D~|), and as at crossing_enclosure |t - N~/D~| < 2(eN + r·eD)/|D~|, where
// 1/|D~| <= |inv|/(1 - u) and r <= (1 + 2.01u)|q| + 2^-1073. The code takes E =
// fl(fl(3·X) + 2^-1019), X = fl(fl(eN + fl(|q|·eD))·|inv|): after its five roundings 3X
// exceeds 2(1 + 3.02u)(eN + |q|·eD)·|inv| by 0.99·(eN + |q|·eD)·|inv| at least, and since
// |N~| <= (1 + 8u)·S~ (the same terms, three roundings each way) eN >= 4.9u·|N~|, so
// that excess is at least 4.8u|q|: more than 2.01u·r, the roundings of q ∓ E (u(|q| +
// E)) and E's own; 2^-1019 covers every absolute term (a few 2^-1073). So [fl(q - E),
// fl(q + E)] holds t. A bound not finite, |inv| not normal or E not finite goes to the
// stepped enclosures. The same in float (the float pass, below) with 2^-123 for 2^-1019,
// above its absolute terms (a few 2^-147).
// Contraction (detail/eft.hpp): class C1, a fused step has fewer roundings.
// Otherwise (crossing_enclosure_conservative): crossing_enclosure's, and where 2·eD <
// |D~| <= 32·eD (below, crossing_enclosure is that quotient already) also the
// outward-rounded quotient of the two enclosures (divide_signed), their intersection
// (both enclose t). Near 0 the derived bound alone is wide: E >=
// 3|q|·eD/|D~|, above |q| itself when |D~| < 3·eD, so the interval reaches across 0
// whatever N is; the quotient's end on the side of 0 keeps N's sign whenever N's
// enclosure does. Certified mode keeps crossing_enclosure alone (its faithful rounding
// starts from that interval, so that its t stays the plane's).
//
// poly_leaving_margin: a ray leaving a plane's half-space from outside, o at distance
// delta from the plane and n·d > 0 (the exact crossing t = N/D < 0, N = -g, g = n·o -
// offset = delta·|n|), is answered miss on [0, t_max] by conservative mode — the plane's
// upper end below 0, so [t_enter, t_exit] is empty for every polyhedron with that
// plane — when g >= gamma(22)·S, S = |offset| + Σ|n_j o_j|, and S >= 2^-960·(1 +
// Σ|n_j d_j|) (the absolute terms): the distance by which the tracer moves a secondary
// ray's origin off a conservative polyhedron's face. With |N~ - N| < eN, eN <=
// gamma(5)(1 + 8u)·S + 2^-1022(1 + u) (three roundings, and the computed S~ exceeds S by
// at most gamma(5)·S):
//   |D~| > 32·eD: the upper end fl(q + E) (crossing_enclosure_quick) is below 0 when q +
//     E < -2^-1075. E <= 3(1 + 8u)(eN + |q|·eD)/|D~| + 2^-1019(1 + u), and eD/|D~| <
//     1/32, so it suffices that |q|(1 - 3(1 + 8u)/32) > 3(1 + 8u)·eN/|D~| + 2^-1018,
//     with |q| >= (1 - 2u)|N~|/|D~| - 2^-1075 and |N~| >= g - eN: g > 4.3104·eN
//     + 2^-1017·|D~|, which gamma(22)·S gives: 4.3104·gamma(5)(1 + 8u) < 21.56u <
//     gamma(22) - 0.44u, and 0.44u·S covers the absolute terms for S >= 2^-960(1 + |D|).
//     Where the quick enclosure declines, crossing_enclosure's end fl_up(q + E), q =
//     fl(N~/D~), is below 0 on the same condition, its E <= 3(1 + 6u)(eN + |q|·eD)/|D~|
//     + 2^-51(1 + 2u)|q| + 2^-1020(1 + u) (the constants as above, but 1 - 3/32 - 2^-50).
//   |D~| <= 32·eD: the quotient's upper end step_up(fl_up(N~ + eN)/(D~ + eD)) is below 0:
//     N~ + eN < -g + 2eN <= -(gamma(22) - 2·gamma(5)(1 + 8u))·S < -11u·S, and its
//     quotient by D~ + eD <= 33·eD <= 166u·Σ|n_j d_j| + 2^-1016 lies below -2^-1073
//     for S >= 2^-960·(1 + Σ|n_j d_j|).
// A leaving ray's entry-type crossings (origin inside, moving inwards, t = N/D < 0) only
// lower bound the entry, which t_min then dominates: nothing to bound there.
inline constexpr double poly_leaving_margin = gamma<double>(22);
inline Interval<double> crossing_enclosure_conservative(const PolyCrossing& c, int s) {
    Interval<double> v = crossing_enclosure(c, s);
    if (c.finite_N && c.finite_D && std::abs(c.D) > 2 * c.eD && std::abs(c.D) <= 32 * c.eD) {
        const Interval<double> w = divide_signed(around(c.N, c.eN, true), around(c.D, c.eD, true), s);
        v = Interval<double>(std::max(v.lo, w.lo), std::min(v.hi, w.hi));
    }
    return v;
}
template <class C> struct QuickCrossing {
    C lo, hi, E;
    bool ok;
};
template <class C> RAYPROOF_ALWAYS_INLINE QuickCrossing<C> crossing_enclosure_quick(const Crossing<C>& c) {
    constexpr C floor = 8 * std::numeric_limits<C>::min();  // 2^-1019 (float: 2^-123)
    const C inv = 1 / c.D, ai = std::abs(inv), q = c.N * inv, aq = std::abs(q);
    const C E = 3 * ((c.eN + aq * c.eD) * ai) + floor;
    // Both bounds finite, without testing them: an infinite or NaN eD fails the first
    // test, an infinite or NaN eN (or N) makes E infinite or NaN where ai > 0.
    const bool ok = int(std::abs(c.D) > 32 * c.eD) & int(ai >= std::numeric_limits<C>::min()) &
                    int(E <= std::numeric_limits<C>::max());
    return {q - E, q + E, E, ok};
}

// The ray and the planes as a source of exact quotients (detail/certified.hpp): plane k's
// crossing num_k/den_k (side ignored). Degree 2 in the inputs, so a comparison of two
// crossings, sign(num_a·den_b - num_b·den_a), is degree 4: exact in Expansion for
// expansion_safe inputs, else in BigDyadic (with_exact), over the whole finite range.
template <class T> class PolySource {
public:
    PolySource(const Ray<T>& r, std::span<const Plane<T>> planes) : r_(&r), planes_(planes) {}
    template <class E> E num(int k, int = 0) const {
        const Plane<T>& p = planes_[std::size_t(k)];
        E s(double(p.offset));
        for (int j = 0; j < 3; ++j) s = s - E(double(p.normal[j])) * E(double(r_->origin[j]));
        return s;
    }
    template <class E> E den(int k) const {
        const Plane<T>& p = planes_[std::size_t(k)];
        E s(0.0);
        for (int j = 0; j < 3; ++j) s = s + E(double(p.normal[j])) * E(double(r_->direction[j]));
        return s;
    }
    // Every input expansion_safe (decided once, on first use: the exact stage is rare;
    // scan()).
    bool safe() const {
        if (safe_ < 0) scan();
        return safe_ != 0;
    }
    // The exact signs of num and den: from the double-word pairs where they decide, else
    // from the fixed-size sums (both on the fine values below, which scale neither sign;
    // on input with no fine scaling, the sums with checked products), else in an exact
    // type.
    int num_sign(int k) const {
        const std::optional<PlaneValues> v = values(k);
        if (v)
            if (const std::optional<int> s = word_sign(v->word.n, v->word.bn)) return *s;
        if (const GrowingSum<8> s = v ? num_sum(*v, true) : num_sum(given(k), false); !s.full) return s.sign();
        return exact_sign(safe(), [&](auto tag) { return num<typename decltype(tag)::type>(k); });
    }
    int den_sign(int k) const {
        const std::optional<PlaneValues> v = values(k);
        if (v)
            if (const std::optional<int> s = word_sign(v->word.d, v->word.bd)) return *s;
        if (const GrowingSum<8> s = v ? den_sum(*v, true) : den_sum(given(k), false); !s.full) return s.sign();
        return exact_sign(safe(), [&](auto tag) { return den<typename decltype(tag)::type>(k); });
    }
    // exact_compare's sign before the exact types. On the fine values below: from the
    // double-word pairs (detail/compensated.hpp, word_compare) where they decide, else
    // from num = offset - Σ n_j·o_j and den = Σ n_j·d_j as fixed-size sums of
    // error-free products (GrowingSum: exact on fine values, every product of their
    // components exact too; compare_sums, detail/affine_quotients.hpp), a constant c
    // compared with c·2^(sp - sd) on scaled values where that is exact. On input with no
    // fine scaling (a group of values spanning more binades than the safe range holds):
    // the same sums from the input as given, every product checked. None where none of
    // these decides.
    std::optional<int> quick_compare(const SlabRef& a, const SlabRef& b) const {
        if (a.axis < 0) {
            const std::optional<int> s = quick_compare(b, a);
            if (!s) return std::nullopt;
            return -*s;
        }
        if (const std::optional<PlaneValues> x = values(a.axis)) return fine_compare(*x, b);
        return given_compare(a.axis, b);
    }

private:
    // The scaling for input not safe() (quick_compare): scan()'s.
    const std::optional<AffineShifts>& shifts() const {
        if (safe_ < 0) scan();
        return shifts_;
    }
    // One pass over the input, on first use (AffineSpans): whether every input is
    // expansion_safe (double: every value 0 or of magnitude in [2^-100, 2^100]; float:
    // finite), and the scaling for input that is not, which also scales the origin and
    // the direction here once, for every plane's values.
    void scan() const {
        AffineSpans spans;
        for (int j = 0; j < 3; ++j) {
            o_[j] = double(r_->origin[j]);
            d_[j] = double(r_->direction[j]);
            spans.ray(o_[j], d_[j]);
        }
        for (const Plane<T>& p : planes_)
            spans.row(double(p.normal[0]), double(p.normal[1]), double(p.normal[2]), double(p.offset));
        safe_ = std::is_same_v<T, double> ? spans.within(0x1p-100, 0x1p100)
                                          : spans.within(0, std::numeric_limits<double>::max());
        if (safe_) return;
        shifts_ = spans.shifts();
        if (shifts_)
            for (int j = 0; j < 3; ++j) {
                o_[j] = times_pow2(o_[j], shifts_->sp);
                d_[j] = times_pow2(d_[j], shifts_->sd);
            }
    }
    // Plane k's input as fine values: as given on safe() input, else scaled into the
    // safe range (affine_shifts: the origin by 2^sp, every normal by 2^sa, every offset
    // by 2^(sp + sa), the direction by 2^sd, each exact), which multiplies each num by
    // 2^(sp + sa) and each den by 2^(sa + sd) (every sign of a num, a den or a difference
    // of two crossings unchanged, every crossing times 2^(sp - sd)); with the pairs of
    // quotient_sums (num in lane 0: the offset, then -n_j·o_j; den in lane 1: n_j·d_j),
    // fine sums there. None where no scaling exists or the sums are not ok. Made anew at
    // each call: keeping them (the last two planes', or every plane's of a pass) measured
    // no faster.
    struct PlaneValues {
        double offset, n[3], o[3], d[3];
        WordQuotient word;
    };
    std::optional<PlaneValues> values(int k) const {
        AffineShifts s{0, 0, 0};
        if (!safe()) {
            if (!shifts()) return std::nullopt;
            s = *shifts();
        }
        using namespace lanes;
        const Plane<T>& p = planes_[std::size_t(k)];
        const bool scale = !safe();
        PlaneValues v;
        v.offset = scale ? times_pow2(double(p.offset), s.sp + s.sa) : double(p.offset);
        D2 a[3], f[3];
        M2 inputs = in_range(make(v.offset, 0.0));
        for (int j = 0; j < 3; ++j) {
            v.n[j] = scale ? times_pow2(double(p.normal[j]), s.sa) : double(p.normal[j]);
            v.o[j] = o_[j];
            v.d[j] = d_[j];
            a[j] = make(-v.n[j], v.n[j]);
            f[j] = make(v.o[j], v.d[j]);
            inputs = inputs & in_range(a[j]) & in_range(f[j]);
        }
        const QuotientSums q = quotient_sums_short_first(make(v.offset, 0.0), a, f, inputs);
        if (!q.ok) return std::nullopt;
        v.word = unpack(q);
        return v;
    }
    // Plane k's input as given, in double (word unset).
    PlaneValues given(int k) const {
        const Plane<T>& p = planes_[std::size_t(k)];
        PlaneValues v{};
        v.offset = double(p.offset);
        for (int j = 0; j < 3; ++j) {
            v.n[j] = double(p.normal[j]);
            v.o[j] = double(r_->origin[j]);
            v.d[j] = double(r_->direction[j]);
        }
        return v;
    }
    // quick_compare on the fine values: the pairs, then the sums (a constant scaled
    // with the values, where exactly).
    std::optional<int> fine_compare(const PlaneValues& x, const SlabRef& b) const {
        if (b.axis < 0) {
            double c = b.c;
            if (!safe() && !scale_exactly(b.c, shifts()->sp - shifts()->sd, c)) return std::nullopt;
            if (const std::optional<int> s = word_compare(x.word, c)) return s;
            return sums_compare(x, c, true);
        }
        const std::optional<PlaneValues> y = values(b.axis);
        if (!y) return std::nullopt;
        if (const std::optional<int> s = word_compare(x.word, y->word)) return s;
        return sums_compare(x, *y, true);
    }
    // quick_compare on the input as given (no fine scaling): the sums, products checked.
    std::optional<int> given_compare(int k, const SlabRef& b) const {
        if (b.axis < 0) return sums_compare(given(k), b.c, false);
        return sums_compare(given(k), given(b.axis), false);
    }
    static std::optional<int> sums_compare(const PlaneValues& v, double c, bool fine) {
        const GrowingSum<8> n = num_sum(v, fine), d = den_sum(v, fine);
        if (n.full || d.full || d.sign() == 0) return std::nullopt;
        return compare_sums(n, d, c);
    }
    static std::optional<int> sums_compare(const PlaneValues& v1, const PlaneValues& v2, bool fine) {
        const GrowingSum<8> n1 = num_sum(v1, fine), d1 = den_sum(v1, fine), n2 = num_sum(v2, fine),
                            d2 = den_sum(v2, fine);
        if (n1.full || d1.full || n2.full || d2.full || d1.sign() == 0 || d2.sign() == 0) return std::nullopt;
        return compare_sums(n1, d1, n2, d2, fine);
    }
    // num and den as sums of error-free products: exact on fine values (fine); else each
    // product checked (exact_product) and the offset below 2^1000, `full` where not.
    static GrowingSum<8> num_sum(const PlaneValues& v, bool fine) {
        GrowingSum<8> s;
        if (!fine && std::abs(v.offset) >= 0x1p1000) {
            s.full = true;
            return s;
        }
        s.add(v.offset);
        for (int j = 0; j < 3; ++j) {
            if (fine)
                s.add_product(-v.n[j], v.o[j]);
            else
                s.add_product_checked(-v.n[j], v.o[j]);
        }
        s.compress();
        return s;
    }
    static GrowingSum<8> den_sum(const PlaneValues& v, bool fine) {
        GrowingSum<8> s;
        for (int j = 0; j < 3; ++j) {
            if (fine)
                s.add_product(v.n[j], v.d[j]);
            else
                s.add_product_checked(v.n[j], v.d[j]);
        }
        s.compress();
        return s;
    }
    const Ray<T>* r_;
    std::span<const Plane<T>> planes_;
    mutable int safe_ = -1;
    mutable std::optional<AffineShifts> shifts_;
    mutable double o_[3], d_[3];  // the origin and the direction, scaled by shifts_ where the input is not safe
};

static_assert(ExactQuotients<PolySource<float>> && ExactQuotients<PolySource<double>>);

// A plane whose normal is ±e_i (one component ±1, the others 0) is a box's slab plane:
// its crossing is (p - o_i)/d_i with p = ±offset (num and den multiplied by n_i = ±1,
// exactly). Such a crossing is rounded as the box rounds its slab values
// (faithful_slab_value, then exact arithmetic on p - o_i over d_i with the same exact
// type choice: every input expansion_safe), so that a polyhedron made of a box's planes
// answers as the box does, bit for bit.
template <class T> struct AxisCrossing {
    T p, o, d;
    bool all_safe;
    bool safe() const { return all_safe; }
    template <class E> E num(int = 0, int = 0) const { return E(double(p)) - E(double(o)); }
    template <class E> E den(int = 0) const { return E(double(d)); }
};
static_assert(ExactQuotients<AxisCrossing<float>> && ExactQuotients<AxisCrossing<double>>);

// Plane k's crossing faithfully rounded to T, given an enclosure v of it (den_k != 0).
// A slab plane as above; any other by the plane's own rounding (PlaneCrossing::faithful:
// for float the nearest float where the plane's enclosure gives one, then plane_pin's
// pinned candidate, else the interval when it pins one float, else exact),
// so that a one-plane polyhedron and the plane agree on t. For float the nearest float
// is tried here before the crossing's intervals are built (the same first step, so the
// same answer: the intervals cost more than the rest of a winner's rounding), and the
// crossing then goes on from its second step (faithful_after_nearest).
template <class T>
T poly_faithful(const Ray<T>& r, const Plane<T>& p, const PolySource<T>& src, const Interval<double>& v,
                bool& went_exact) {
    const T* n = p.normal.data();
    for (int i = 0; i < 3; ++i) {
        const int a = (i + 1) % 3, b = (i + 2) % 3;
        if ((n[i] == 1 || n[i] == -1) && n[a] == 0 && n[b] == 0) {
            const T q = n[i] > 0 ? p.offset : -p.offset;
            if (const std::optional<T> t = faithful_slab_value<T>(q, r.origin[i], r.direction[i])) return *t;
            RAYPROOF_COUNT_EXACT(went_exact);
            return exact_faithful<T>(AxisCrossing<T>{q, r.origin[i], r.direction[i], src.safe()}, 0, 0);
        }
    }
    if constexpr (std::is_same_v<T, float>)
        if (const Pinned<float> f = plane_nearest_float(plane_enclosure(plane_sums<double>(r, p))); f.ok) return f.t;
    return PlaneCrossing<T>(r, p).faithful_after_nearest(v, went_exact);
}

// The exact sign of den_k from its bound, else exactly; the same for num_k.
template <class T> int poly_den_sign(const PolyCrossing& c, const PolySource<T>& src, int k) {
    if (c.finite_D && c.D > c.eD) return 1;
    if (c.finite_D && c.D < -c.eD) return -1;
    return src.den_sign(k);
}
// num_k >= 0: the origin lies in the closed half-space (decides a parallel plane).
template <class T> bool poly_inside(const PolyCrossing& c, const PolySource<T>& src, int k) {
    if (c.finite_N && c.N >= c.eN) return true;
    if (c.finite_N && c.N < -c.eN) return false;
    return src.num_sign(k) >= 0;
}

// The conservative and certified passes vouch for the planes as fast mode's does, so that
// prepare()'s loop over every plane's validity goes unevaluated (it cost 8-11% of these
// queries on uniform input): the queries are inlined wrappers that do not read the flag,
// around the passes out of line. With the ray valid (checked first), a plane holding a
// NaN or infinite number makes its bound's sum of |n_j|·|o_j| and |offset| NaN or
// infinite (|n_j|·|o_j| is NaN for an infinite n_j and o_j == 0), so the crossing's
// finite_N fails: such a plane is judged by the rules before anything is computed from
// it, and a valid one that merely overflows goes on as before (the exact stage decides
// it). A plane with finite numbers has a nonzero normal when its den's exact sign is
// nonzero, and the parallel branch (sign 0) tests the normal. So every plane the pass
// reached is valid when it goes on, the exact stage sees only those (PolySource's
// planes of other indices enter only its range check, safe(), which any value fails
// safely), and a pass that stops early on a miss checks the planes after it by the
// rules.
template <class T>
RAYPROOF_ALWAYS_INLINE bool poly_plane_checked(const PolyCrossing& c, const Plane<T>& p) {
    if (c.finite_N && c.finite_D) [[likely]]
        return true;
    return valid(p);
}
// A miss found before the last plane: the planes after it checked by the rules, out of
// line (the passes' loops stay as tight as they were).
template <class T>
[[gnu::noinline]] Hit<T> poly_miss_checked(std::span<const Plane<T>> planes, std::size_t from) {
    return poly_checked(planes, from, T(0), Hit<T>{});
}

// Conservative: the latest entry's lower enclosure bound and the earliest exit's upper
// one. Every sign that decides a side (den_k's, and num_k's for a parallel plane) is
// exact (from the bound, else exact arithmetic), so no plane is put on the wrong side; a
// crossing whose den may be tiny has an enclosure unbounded on one side
// (divide_signed). So the verdict can only err towards hit, [t_enter, t_exit] encloses
// the exact interval, and the face (the plane of the largest lower bound) may differ from
// the exact one on near ties. A plane whose quick enclosure holds
// (crossing_enclosure_quick: its den far from its bound, so den's sign is certain and the
// plane valid) updates the entry or the exit at once; any other plane takes the checked
// path with exact signs. (Picks instead of the branches on the side, a coin toss on
// random planes, measured slower: they chain every plane's update to the one before.)
// The conservative pass's state: the latest entry's lower bound and the earliest exit's
// upper bound so far, and the plane of the first. A crossing enclosed in [a, b] raises
// the entry bound if it is an entry (den < 0), else lowers the exit bound.
template <class C> struct PolyPass {
    C lo, hi;
    int face = -1;
    RAYPROOF_ALWAYS_INLINE void take(bool entry, C a, C b, int k) {
        if (entry) {
            if (a > lo) {
                lo = a;
                face = k;
            }
        } else if (b < hi) {
            hi = b;
        }
    }
    bool empty() const { return lo > hi; }  // the exact entry exceeds the exact exit
};

// Float input: the pass in float first (poly_crossing<float>, crossing_enclosure_quick<float>:
// no conversion, float divisions), every plane by its quick enclosure. A plane it
// declines (den near its bound, an overflow, an invalid plane) sends the whole query to
// the double pass. Its entry bound above its exit bound is a miss (certain, as in the
// double pass; the planes after are checked by the rules); a hit where certain_hit
// (detail/certified.hpp) proves one, with E_max the largest crossing bound: the exact
// entry lies below the entry bound plus 2·E_max, the exact exit above the exit bound
// less 2·E_max. The rest (near a graze, where float's bounds, some 2^29 times double's,
// would add false hits) goes to the double pass, so every hit of the float stage is a
// hit of the double pass. Its ends are wider than the double pass's (one float step
// from the exact value on general input): on the `general` cases 39 float steps at the
// median, 599 at the 99th percentile.
RAYPROOF_ALWAYS_INLINE std::optional<Hit<float>> poly_conservative_float(const Ray<float>& r,
                                                                         std::span<const Plane<float>> planes) {
    PolyPass<float> pass{r.t_min, r.t_max};
    float e_max = 0;
    for (std::size_t k = 0; k < planes.size(); ++k) {
        const Crossing<float> c = poly_crossing<float>(r, planes[k]);
        const QuickCrossing<float> w = crossing_enclosure_quick(c);
        if (!w.ok) [[unlikely]]
            return std::nullopt;
        e_max = w.E > e_max ? w.E : e_max;
        pass.take(c.D < 0, w.lo, w.hi, int(k));
        if (pass.empty()) return poly_miss_checked(planes, k + 1);
    }
    if (!certain_hit(pass.lo, pass.hi, e_max)) return std::nullopt;
    return hit_when(true, pass.lo, pass.hi, pass.face);
}
template <class T> Hit<T> poly_conservative_double(const Ray<T>& r, std::span<const Plane<T>> planes) {
    const PolySource<T> src(r, planes);
    Hit<T> h;
    PolyPass<double> pass{r.t_min, r.t_max};
    for (std::size_t k = 0; k < planes.size(); ++k) {
        const PolyCrossing c = poly_crossing(r, planes[k]);
        const QuickCrossing<double> w = crossing_enclosure_quick(c);
        if (w.ok) [[likely]] {
            pass.take(c.D < 0, w.lo, w.hi, int(k));
        } else {
            if (!poly_plane_checked(c, planes[k])) return invalid_hit<T>();
            const int s = poly_den_sign(c, src, int(k));
            if (s == 0) {
                if (!nonzero3(planes[k].normal.data())) return invalid_hit<T>();
                if (!poly_inside(c, src, int(k))) return poly_miss_checked(planes, k + 1);
                continue;
            }
            const Interval<double> v = crossing_enclosure_conservative(c, s);
            pass.take(s < 0, v.lo, v.hi, int(k));
        }
        if (pass.empty()) return poly_miss_checked(planes, k + 1);
    }
    h.verdict = Verdict::hit;
    h.t_enter = round_down_to<T>(pass.lo);
    h.t_exit = round_up_to<T>(pass.hi);
    h.face = pass.face;
    return h;
}
// The conservative answer: for float input the float stage first; otherwise, and for
// double input, the pass in double.
template <class T> Hit<T> poly_conservative(const Ray<T>& r, std::span<const Plane<T>> planes) {
    if constexpr (std::is_same_v<T, float>)
        if (const std::optional<Hit<float>> h = poly_conservative_float(r, planes)) return *h;
    return poly_conservative_double(r, planes);
}
template <class T>
RAYPROOF_ALWAYS_INLINE Hit<T> query(const Ray<T>& r, const PreparedPolyhedron<T>& p, conservative_t) {
    if (!valid(r)) return invalid_hit<T>();
    return poly_conservative(r, p.shape.planes);
}

// Certified: one pass over the planes, the slab method's certified form
// (detail/slab_certified.hpp) over k planes instead of three axes, kept without any
// array (no allocation, any number of planes): the current entry and exit are each
// either the limit (t_min, t_max) or a plane index, with its enclosure; a plane
// replaces the entry only when its crossing is strictly greater (t_min first, then the
// planes in order: the lowest index wins ties, duplicates included), the exit when
// strictly smaller. Each comparison is decided by the enclosures when they are disjoint
// (the filter) and exactly otherwise (exact_compare: the sign of num_a·den_b -
// num_b·den_a times the signs of the dens, or of num - c·den against a limit). With
// Full, the winners are then rounded faithfully (poly_faithful); without, only the
// verdict is answered, by the same decisions.
template <class T, bool Full> Hit<T> poly_certified(const Ray<T>& r, std::span<const Plane<T>> planes) {
    RAYPROOF_COUNT_QUERY();
    bool went_exact = false;
    const PolySource<T> src(r, planes);
    Hit<T> h;
    SlabRef in{-1, 0, double(r.t_min)}, out{-1, 0, double(r.t_max)};
    Interval<double> vin(double(r.t_min)), vout(double(r.t_max));
    for (std::size_t k = 0; k < planes.size(); ++k) {
        const PolyCrossing c = poly_crossing(r, planes[k]);
        if (!poly_plane_checked(c, planes[k])) {
            RAYPROOF_COUNT_FLUSH(went_exact);
            return invalid_hit<T>();
        }
        const int s = poly_den_sign(c, src, int(k));
        if (s == 0) {
            const bool normal_ok = nonzero3(planes[k].normal.data());
            if (!normal_ok || !poly_inside(c, src, int(k))) {
                RAYPROOF_COUNT_FLUSH(went_exact);
                return normal_ok ? poly_miss_checked(planes, k + 1) : invalid_hit<T>();
            }
            continue;
        }
        const Interval<double> v = crossing_enclosure(c, s);
        const SlabRef x{int(k), 0, 0};
        if (s < 0) {  // entering: replace on a strictly greater crossing
            bool greater;
            if (v.lo > vin.hi) {
                greater = true;
            } else if (v.hi <= vin.lo) {
                greater = false;
            } else {
                RAYPROOF_COUNT_EXACT(went_exact);
                greater = exact_compare(src, x, in) > 0;
            }
            if (greater) in = x, vin = v;
        } else {  // leaving: replace on a strictly smaller crossing (ties: same value)
            bool less;
            if (v.hi < vout.lo) {
                less = true;
            } else if (v.lo >= vout.hi) {
                less = false;
            } else {
                RAYPROOF_COUNT_EXACT(went_exact);
                less = exact_compare(src, x, out) < 0;
            }
            if (less) out = x, vout = v;
        }
        if (vin.lo > vout.hi) {  // certainly entry > exit: a miss, whatever follows
            RAYPROOF_COUNT_FLUSH(went_exact);
            return poly_miss_checked(planes, k + 1);
        }
    }
    int order;  // sign(entry - exit)
    if (vin.hi < vout.lo) {
        order = -1;
    } else if (vin.lo > vout.hi) {
        order = 1;
    } else {
        RAYPROOF_COUNT_EXACT(went_exact);
        order = exact_compare(src, in, out);
    }
    if (order > 0) {
        RAYPROOF_COUNT_FLUSH(went_exact);
        return h;
    }
    h.verdict = Verdict::hit;
    h.face = in.axis;  // -1 for t_min
    if constexpr (Full) {
        h.t_enter = in.axis < 0 ? r.t_min : poly_faithful(r, planes[std::size_t(in.axis)], src, vin, went_exact);
        h.t_exit = out.axis < 0 ? r.t_max
                   : order == 0 ? h.t_enter
                                : poly_faithful(r, planes[std::size_t(out.axis)], src, vout, went_exact);
        // Two different exact values in one gap between adjacent floats may round apart
        // the wrong way; the smaller rounding is faithful for both then.
        if (h.t_enter > h.t_exit) h.t_enter = h.t_exit;
    }
    RAYPROOF_COUNT_FLUSH(went_exact);
    return h;
}

template <class T>
RAYPROOF_ALWAYS_INLINE Hit<T> query(const Ray<T>& r, const PreparedPolyhedron<T>& p, certified_t) {
    if (!valid(r)) return invalid_hit<T>();
    return poly_certified<T, true>(r, p.shape.planes);
}

// The certified verdict alone: the full query's decisions, without the rounding of t.
template <class T>
RAYPROOF_ALWAYS_INLINE Verdict verdict_query(const Ray<T>& r, const PreparedPolyhedron<T>& p, certified_t) {
    if (!valid(r)) return Verdict::invalid;
    return poly_certified<T, false>(r, p.shape.planes).verdict;
}

}  // namespace rayproof::detail
