// rayproof/detail/affine_quotients.hpp — the exact side of the slab frames whose values
// are quotients of two affine forms: (s_i - a_i·(o - c)) / (a_i·d) for rows i < R, with
// s_i = -h_i (side 0) or +h_i (side 1). The oriented box's three slabs (a_i its axes, c
// its centre, h_i its half-extents; ray_obb.hpp) and the plane's crossing (R = 1, a_0 the
// normal, c = 0, h_0 = -offset, side 0: (offset - n·o)/(n·d); ray_plane.hpp).
// As a source of exact quotients (detail/certified.hpp, ExactQuotients) over the input
// in double: as given (widened), or rescaled into the range where the Expansion type
// and quick_compare are exact (rescaled()); quick_compare, quick_faithful and the exact
// signs of num and den without an expansion type, from fixed-size sums of error-free
// products (GrowingSum, exact.hpp). AffineSource serves a frame both, each made on first
// use, and before them the exact rows of integer-like input (num and den as plain
// doubles, exactly: affine_exact_row), and for input too wide to rescale a balanced
// copy (balanced(): each group scaled to its own largest magnitude, for the checked
// sums).
// Rescaling: the positions (o, c) by 2^sp, the rows a_i by 2^sa, the h_i by 2^(sp + sa)
// and the direction by 2^sd (each exact: every scaled value is a normal double) multiply
// every num by 2^(sp + sa), every den by 2^(sa + sd) and every quotient by
// 2^(sp - sd) = 2^shift(), so that every sign of a num or a den, and of a difference of
// two quotients or of one and a constant scaled alike, is unchanged.
#pragma once

#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/compensated.hpp>
#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/lanes.hpp>
#include <rayproof/detail/rounding.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <optional>
#include <utility>

namespace rayproof::detail {

// The shifts that put affine quotients' input into [2^-100, 2^100] (or 0): the positions
// by 2^sp, the rows by 2^sa, the h_i by 2^(sp + sa), the directions by 2^sd, from each
// group's binary exponents, where such shifts exist (each group's shifts form a range,
// ExponentSpan, and the h_i's range bounds sp + sa); none where a range is empty.
struct AffineShifts {
    int sp, sa, sd;
};
inline std::optional<AffineShifts> affine_shifts(const ExponentSpan& positions, const ExponentSpan& rows,
                                                 const ExponentSpan& halves, const ExponentSpan& directions) {
    const std::optional<int> sd = directions.safe_shift();
    const ShiftRange p = positions.shift_range(), a = rows.shift_range(), h = halves.shift_range();
    // sp + sa in [p.lo + a.lo, p.hi + a.hi] ∩ [h.lo, h.hi]; then sp and sa within their own
    const int lo = std::max(p.lo + a.lo, h.lo), hi = std::min(p.hi + a.hi, h.hi);
    if (!sd || p.lo > p.hi || a.lo > a.hi || lo > hi) return std::nullopt;
    const int sum = std::clamp(0, lo, hi), sp = std::max(p.lo, sum - a.hi);
    return AffineShifts{sp, sum - sp, *sd};
}
// Shifts for input too wide for affine_shifts (some group spans more than 199 binades),
// for the checked sums alone (AffineQuotients::balanced): each group's largest magnitude
// brought to [1, 2) (sa = -top(rows), sd = -top(directions)), and sp = -top(positions),
// lowered where the halves need it so that the largest h_i·2^(sp + sa) is below 2 too. An
// exact product's checks (exact_product: the two last bits' exponents, the two binary
// exponents) then see each group's exponents relative to its largest, not the input's
// absolute ones. None where a scaled value would not be a normal double (every scaled
// value of a group lies in [2^(lo - top), 2)) or a shift leaves times_pow2's range; an
// empty group (zeros only) takes shift 0 where its own top decides it.
inline std::optional<AffineShifts> balanced_affine_shifts(const ExponentSpan& positions, const ExponentSpan& rows,
                                                          const ExponentSpan& halves, const ExponentSpan& directions) {
    const auto empty = [](const ExponentSpan& e) { return e.hi < e.lo; };
    const int sa = empty(rows) ? 0 : -rows.hi, sd = empty(directions) ? 0 : -directions.hi;
    int sp = empty(positions) ? 0 : -positions.hi;
    if (!empty(halves)) sp = empty(positions) ? -halves.hi - sa : std::min(sp, -halves.hi - sa);
    const auto fits = [&](const ExponentSpan& e, int s) {
        return s >= -2044 && s <= 2046 && (empty(e) || e.lo + s >= -1022);
    };
    if (!(fits(positions, sp) && fits(rows, sa) && fits(halves, sp + sa) && fits(directions, sd))) return std::nullopt;
    return AffineShifts{sp, sa, sd};
}

// The four groups of an affine input (positions, rows, halves, directions) gathered in
// one pass, two values at a time: a position beside a direction, a row's first two
// components, its third beside its half. Each lane keeps the largest magnitude and the
// smallest nonzero one, a NaN or an infinity taken as infinity. binary_exponent is
// monotone in the magnitude and gives 1024 for both, so the ends' exponents are the
// group's ExponentSpan value by value, and shifts() is affine_shifts of those spans.
class AffineSpans {
public:
    void ray(double position, double direction) { take(ray_, lanes::make(position, direction)); }
    void row(double a0, double a1, double a2, double h) {
        take(pair_, lanes::make(a0, a1));
        take(last_, lanes::make(a2, h));
    }
    // Every value 0 or of magnitude in [lo, hi] (false on a NaN or an infinity when hi
    // is finite), as lanes::in_band.
    bool within(double lo, double hi) const {
        using namespace lanes;
        const D2 l = splat(lo), u = splat(hi);
        return bits((ray_.top <= u) & (ray_.bottom >= l) & (pair_.top <= u) & (pair_.bottom >= l) &
                    (last_.top <= u) & (last_.bottom >= l)) == 3;
    }
    std::optional<AffineShifts> shifts() const { return with_spans(affine_shifts); }
    std::optional<AffineShifts> balanced_shifts() const { return with_spans(balanced_affine_shifts); }

private:
    struct Ends {
        lanes::D2 top = lanes::splat(0.0), bottom = lanes::splat(std::numeric_limits<double>::infinity());
    };
    static void take(Ends& e, lanes::D2 x) {
        using namespace lanes;
        const D2 inf = splat(std::numeric_limits<double>::infinity()), a = abs(x),
                 m = select(a <= splat(std::numeric_limits<double>::max()), a, inf);
        e.top = max(e.top, m);
        e.bottom = min(e.bottom, select(m == splat(0.0), inf, m));
    }
    // f(positions, rows, halves, directions) over the groups' spans
    template <class F> std::optional<AffineShifts> with_spans(F&& f) const {
        using namespace lanes;
        const double rows_top = std::max({lane0(pair_.top), lane1(pair_.top), lane0(last_.top)}),
                     rows_bottom = std::min({lane0(pair_.bottom), lane1(pair_.bottom), lane0(last_.bottom)});
        return f(span(lane0(ray_.top), lane0(ray_.bottom)), span(rows_top, rows_bottom),
                 span(lane1(last_.top), lane1(last_.bottom)), span(lane1(ray_.top), lane1(ray_.bottom)));
    }
    static ExponentSpan span(double top, double bottom) {
        ExponentSpan e;
        if (top != 0) e.hi = binary_exponent(top), e.lo = binary_exponent(bottom);
        return e;
    }
    Ends ray_, pair_, last_;
};

// sign(n1/d1 - n2/d2) for exact sums (GrowingSum, not full; d1 and d2 nonzero):
// sign(n1·d2 - n2·d1)·sign(d1·d2) from their components' products (sign_cross_difference),
// which the caller vouches exact (products_exact) or which are checked here
// (exact_products); where they are not exact as they stand, the numerators are scaled
// alike by 2^kn and the denominators by 2^kd (exactly, GrowingSum::scale) to bring their
// largest components near 1, which multiplies n1·d2 - n2·d1 by 2^(kn + kd): the
// directions' and the positions' binades then need not fit one range together. None
// where a check or the capacity fails.
template <class N, class D> std::optional<int> compare_sums(N n1, D d1, N n2, D d2, bool products_exact) {
    if (!products_exact && !(exact_products(n1, d2) && exact_products(n2, d1))) {
        const int kn = -std::max(n1.top(), n2.top()), kd = -std::max(d1.top(), d2.top());
        if (!(n1.scale(kn) && n2.scale(kn) && d1.scale(kd) && d2.scale(kd) && exact_products(n1, d2) &&
              exact_products(n2, d1)))
            return std::nullopt;
    }
    const std::optional<int> s = sign_cross_difference<32>(n1, d2, n2, d1);
    if (!s) return std::nullopt;
    return *s * d1.sign() * d2.sign();
}
// sign(n/d - c) for a finite constant c: sign(n - c·d)·sign(d), each product c·d_k
// checked (exact_product); none where one is not exact or the capacity fails.
template <class N, class D> std::optional<int> compare_sums(const N& n, const D& d, double c) {
    GrowingSum<32> s;
    for (int k = 0; k < n.n; ++k) s.add(n.e[k]);
    for (int k = 0; k < d.n; ++k) {
        if (!exact_product(c, d.e[k])) return std::nullopt;
        s.add_product(-c, d.e[k]);
    }
    if (s.full) return std::nullopt;
    return s.sign() * d.sign();
}

// The sums of the quotient (s - a·(o - c))/(a·d), s = -h (side 0) or h (side 1), for
// pin_quotient and the comparisons of detail/compensated.hpp: o_j - c_j split exactly by
// two_sum, the products -a_j·(o_j - c_j) in two parts in lane 0 and a_j·d_j in lane 1 of
// quotient_sums; where every o_j - c_j is a double, without the three zero products (the
// same sums, with the bound of three products). Shared by ray_obb.hpp's obb_slab_sums
// and AffineQuotients::sums (ShortFirst: quotient_sums_short_first, the same bits), so
// that the two give the same bits on the same input.
template <bool ShortFirst = false>
RAYPROOF_ALWAYS_INLINE QuotientSums affine_row_sums(double h, int side, const double (&a)[3], const double (&o)[3],
                                                    const double (&c)[3], const double (&d)[3]) {
    using namespace lanes;
    D2 x[6], f[6];
    M2 inputs = in_range(make(h, 0.0));
    bool split = false;  // some o_j - c_j is not a double
    for (int j = 0; j < 3; ++j) {
        const Pair oc = two_sum(o[j], -c[j]);
        x[j] = make(-a[j], a[j]);
        f[j] = make(oc.hi, d[j]);
        x[3 + j] = make(-a[j], 0.0);
        f[3 + j] = make(oc.lo, 0.0);
        inputs = inputs & in_range(x[j]) & in_range(f[j]) & in_range(f[3 + j]);
        split = split || oc.lo != 0;
    }
    const D2 start = make(side ? h : -h, 0.0), x3[3] = {x[0], x[1], x[2]}, f3[3] = {f[0], f[1], f[2]};
    if constexpr (ShortFirst)
        return split ? quotient_sums_short_first(start, x, f, inputs) : quotient_sums_short_first(start, x3, f3, inputs);
    else
        return split ? quotient_sums(start, x, f, inputs) : quotient_sums(start, x3, f3, inputs);
}

// The input of AffineQuotients in double: a[i][j] is row i's component j.
template <int R> struct AffineValues {
    double o[3], c[3], d[3], a[std::size_t(R)][3], h[std::size_t(R)];
};

// Row i's num(i, side) and den(i) as doubles, each the exact value, where plain
// arithmetic gives them exactly, in the order of affine_row_sums' cascade
// (quotient_sums_short_first on three products): num from ±h_i adding -a_ij·(o_j - c_j)
// for j = 0, 1, 2, den from 0 adding a_ij·d_j, every addition exact (two_sum's error
// 0, finite). Each o_j - c_j must be a double (two_sum's error 0, affine_exact_deltas)
// and it, every a_ij and every d_j of at most 26 significant bits (high26(x) == x), so
// that each product, where it is 0 with a zero factor or of magnitude in [2^-1022,
// 2^1000], is exact (at most 52 bits, the last of weight at least 2^-1073).
// Integer-like input (rays through a box's corners and edges, at any scale) is the
// common case. Where the input is also safe, these are the cascade's own partial sums
// with no error term at all, so that its sums are exactly (num, den) with zero low
// parts and bounds (exact_row_sums).
struct AffineExactRow {
    double num[2], den;
};
// Without a branch per check (the checks' outcomes alternate on mixed input, where
// branches on them would be mispredicted): each condition as an int, and'ed.
RAYPROOF_ALWAYS_INLINE int short_double(double x) { return int(lanes::high26(x) == x); }
struct AffineDeltas {
    double d[3];  // o_j - c_j
};
template <int R> std::optional<AffineDeltas> affine_exact_deltas(const AffineValues<R>& v) {
    AffineDeltas x;
    int ok = 1;
    for (int j = 0; j < 3; ++j) {
        const Pair t = two_sum(v.o[j], -v.c[j]);
        x.d[j] = t.hi;
        ok &= int(t.lo == 0) & short_double(t.hi) & short_double(v.d[j]);
    }
    if (!ok) return std::nullopt;
    return x;
}
// Both sides' numerators in the two lanes of detail/lanes.hpp (each addition of
// -a_ij·(o_j - c_j) one two_sum for the pair) and den in lane 0 of a second pair, the
// two products of a_ij in one multiplication: the same products, sums and checks as
// each value computed on its own, two at a time. Contraction: every product kept is
// exact (class C2: a fused product and sum is the same sum).
template <int R>
std::optional<AffineExactRow> affine_exact_row(const AffineValues<R>& v, const AffineDeltas& delta, int i) {
    using namespace lanes;
    const D2 zero = splat(0.0), smallest = splat(std::numeric_limits<double>::min()), largest = splat(0x1p1000),
             finite = splat(std::numeric_limits<double>::max());
    D2 num = make(-v.h[i], v.h[i]), den = zero;  // (side 0, side 1), (den, 0)
    M2 ok = zero == zero;
    int a_ok = 1;
    for (int j = 0; j < 3; ++j) {
        const double a = v.a[i][j];
        a_ok &= short_double(a);
        // (-a_ij·(o_j - c_j), a_ij·d_j), each exact: a zero factor, or of magnitude in [2^-1022, 2^1000]
        const D2 f = make(-delta.d[j], v.d[j]), p = splat(a) * f, m = abs(p);
        ok = ok & ((splat(a) == zero) | (f == zero) | ((m >= smallest) & (m <= largest)));
        // every addition exact: two_sum's error 0 and the sum finite
        const SumOf<D2> x = two_sum(num, splat(lane0(p))), y = two_sum(den, make(lane1(p), 0.0));
        num = x.hi;
        den = y.hi;
        ok = ok & (x.lo == zero) & (abs(x.hi) <= finite) & (y.lo == zero) & (abs(y.hi) <= finite);
    }
    if (!(a_ok & int(bits(ok) == 3))) return std::nullopt;
    return AffineExactRow{{lane0(num), lane1(num)}, lane0(den)};
}
// The cascade's sums for value (i, side) of an exact row on safe input, as
// affine_row_sums makes them there: every error term 0, so c = +0 and S = +0, and the
// renormalization gives hi = s + 0, lo = +0, bound +0; ok (the safe range lies within
// quotient_sums' ranges, and c = 0 passes the renormalization's test).
RAYPROOF_ALWAYS_INLINE QuotientSums exact_row_sums(const AffineExactRow& row, int side) {
    using namespace lanes;
    const SumOf<D2> r = fast_two_sum(make(row.num[side], row.den), splat(0.0));
    return {r.hi, r.lo, splat(0.0), true};
}

template <int R> class AffineQuotients {
public:
    // floats: the values are floats widened (every float is safe for expansions).
    // Safe: every value expansion_safe (0 or of magnitude in [2^-100, 2^100]).
    AffineQuotients(const AffineValues<R>& v, bool floats) : v_(v), shift_(0), safe_(floats || safe_values(v)) {}
    // Whether every value is expansion_safe, tested two at a time (lanes::in_band) over
    // the values as one array.
    static bool safe_values(const AffineValues<R>& v) {
        using namespace lanes;
        constexpr std::size_t n = 9 + 4 * std::size_t(R);
        static_assert(sizeof(AffineValues<R>) == n * sizeof(double));
        double x[n + 1];
        std::memcpy(x, &v, sizeof v);
        x[n] = 0;
        M2 ok = splat(0.0) == splat(0.0);
        for (std::size_t k = 0; k < n; k += 2) ok = ok & in_band(load2(x + k), splat(0x1p-100), splat(0x1p100));
        return bits(ok) == 3;
    }
    // The input rescaled as above with every scaled value in [2^-100, 2^100] or 0, where
    // such shifts exist (affine_shifts); none otherwise.
    static std::optional<AffineQuotients> rescaled(const AffineValues<R>& v) {
        const std::optional<AffineShifts> s = spans_of(v).shifts();
        if (!s) return std::nullopt;
        return AffineQuotients(shifted(v, *s), s->sp - s->sd, true);
    }
    // The input rescaled group by group (balanced_affine_shifts) where rescaled() finds
    // no shifts: not safe() (its checked sums and products decide what they can, the
    // exact types the rest), every scaled value a normal double or 0, so that the scaling
    // is exact and changes no sign; none where such shifts do not exist.
    static std::optional<AffineQuotients> balanced(const AffineValues<R>& v) {
        const std::optional<AffineShifts> s = spans_of(v).balanced_shifts();
        if (!s) return std::nullopt;
        const AffineValues<R> w = shifted(v, *s);
        return AffineQuotients(w, s->sp - s->sd, safe_values(w));
    }
    int shift() const { return shift_; }
    bool safe() const { return safe_; }
    const AffineValues<R>& values() const { return v_; }
    template <class E> E num(int i, int side) const { return E(side ? v_.h[i] : -v_.h[i]) - oprime<E>(i); }
    template <class E> E den(int i) const {
        E s(0.0);
        for (int j = 0; j < 3; ++j) s = s + E(v_.a[i][j]) * E(v_.d[j]);
        return s;
    }
    template <class E> E oprime(int i) const {  // a_i·(o - c)
        E s(0.0);
        for (int j = 0; j < 3; ++j) s = s + E(v_.a[i][j]) * (E(v_.o[j]) - E(v_.c[j]));
        return s;
    }
    // The exact signs of num(i, side) and den(i) from their sums (quick_compare's), or
    // none where a checked product is not exact.
    std::optional<int> num_sign(int i, int side) const {
        if (const std::optional<WordQuotient> w = word(i, side))
            if (const std::optional<int> s = word_sign(w->n, w->bn)) return s;
        const GrowingSum<16> s = num_sum(i, side);
        if (s.full) return std::nullopt;
        return s.sign();
    }
    std::optional<int> den_sign(int i) const {
        if (const std::optional<WordQuotient> w = word(i, 0))
            if (const std::optional<int> s = word_sign(w->d, w->bd)) return s;
        const GrowingSum<8> s = den_sum(i);
        if (s.full) return std::nullopt;
        return s.sign();
    }
    // exact_compare's sign without an expansion type: from the double-word pairs where
    // they decide (word_compare), else from num = ±h_i - Σ_j a_ij o_j + Σ_j a_ij c_j and
    // den = Σ_j a_ij d_j as sums of error-free products (13 and 6 doubles), compressed
    // (compare_sums). For safe() input (every value 0 or a multiple of 2^-152 below
    // 2^100; every float a multiple of 2^-149 below 2^128) every product of two inputs is
    // exact by two_prod (its error term a multiple of 2^-304), and so is every product
    // of the sums' components (multiples of 2^-608, far above the 2^-916 two_prod needs,
    // and below 2^410). For other input every product is checked instead (exact_product;
    // h_i below 2^1000) and compare_sums checks theirs. None where a check or a
    // capacity fails.
    std::optional<int> quick_compare(const SlabRef& a, const SlabRef& b) const {
        if (a.axis < 0) {
            const std::optional<int> s = quick_compare(b, a);
            if (!s) return std::nullopt;
            return -*s;
        }
        if (const std::optional<int> s = word_compare(a, b)) return s;
        const GrowingSum<16> n1 = num_sum(a.axis, a.side);
        const GrowingSum<8> d1 = den_sum(a.axis);
        if (n1.full || d1.full) return std::nullopt;
        if (b.axis < 0) return compare_sums(n1, d1, b.c);
        const GrowingSum<16> n2 = num_sum(b.axis, b.side);
        const GrowingSum<8> d2 = den_sum(b.axis);
        if (n2.full || d2.full) return std::nullopt;
        return compare_sums(n1, d1, n2, d2, safe_);
    }

    // num(i, side)/den(i) pinned from the double-word pairs (pin_quotient on sums(i,
    // side)): a faithful double for the quotient of this input (times 2^shift() for the
    // rescaled one), or none.
    std::optional<double> pinned(int i, int side) const {
        if (const QuotientSums* q = sums(i, side))
            if (const PinnedQuotient p = pin_quotient(*q); p.pinned) return p.c;
        return std::nullopt;
    }
    // sign(value(a) - value(b)) from the double-word pairs (a.axis >= 0; a constant as it
    // stands, already scaled by 2^shift() for the rescaled input; word_compare), or none.
    std::optional<int> word_compare(const SlabRef& a, const SlabRef& b) const {
        const std::optional<WordQuotient> x = word(a.axis, a.side);
        if (!x) return std::nullopt;
        if (b.axis < 0) return detail::word_compare(*x, b.c);
        const std::optional<WordQuotient> y = word(b.axis, b.side);
        if (!y) return std::nullopt;
        return detail::word_compare(*x, *y);
    }

    // num(i, side)/den(i) faithfully rounded to T without an expansion type: pinned()
    // first, else as faithful_quotient finds it (exact_impl::quotient): from a candidate,
    // the sums' estimates divided (rounded to T), stepped one T at a time towards the
    // quotient until sign(num - g·den) changes (at most four steps), each sign from the
    // sums and the products g·den_k (checked: exact_product). The answer is the
    // candidate's neighbour on its own side of the quotient, or the quotient itself. None
    // where a sum or a product is not exact, the candidate is not a normal T, or four
    // steps do not suffice.
    template <class T> std::optional<T> quick_faithful(int i, int side) const {
        if (const std::optional<double> c = pinned(i, side)) return faithful_to<T>(*c);
        const GrowingSum<16> n = num_sum(i, side);
        const GrowingSum<8> d = den_sum(i);
        if (n.full || d.full || d.n == 0) return std::nullopt;
        if (n.n == 0) return T(0);
        const int sd = d.sign();
        // sign(quotient - g), or 2 where a product is not exact
        const auto above = [&](T g) {
            GrowingSum<48> s;
            for (int k = 0; k < n.n; ++k) s.add(n.e[k]);
            for (int k = 0; k < d.n; ++k) {
                if (!exact_product(double(g), d.e[k])) return 2;
                s.add_product(-double(g), d.e[k]);
            }
            return s.full ? 2 : s.sign() * sd;
        };
        T q = T(n.estimate() / d.estimate());
        if (!(std::abs(q) >= std::numeric_limits<T>::min() && std::abs(q) <= std::numeric_limits<T>::max()))
            return std::nullopt;
        const int s = above(q);
        if (s == 2) return std::nullopt;
        if (s == 0) return q;
        for (int step = 0; step < 4; ++step) {
            const T next = s > 0 ? step_up(q) : step_down(q);
            if (std::isinf(next)) return std::nullopt;
            const int s1 = above(next);
            if (s1 == 2) return std::nullopt;
            if (s1 != s) return s1 == 0 ? next : q;  // next == quotient, or quotient strictly between q and next
            q = next;
        }
        return std::nullopt;
    }

private:
    // A rescaled input (rescaled(): every value 0 or in [2^-100, 2^100], safe by
    // construction; balanced(): as its values are).
    AffineQuotients(const AffineValues<R>& v, int shift, bool safe) : v_(v), shift_(shift), safe_(safe) {}
    static AffineSpans spans_of(const AffineValues<R>& v) {
        AffineSpans spans;
        for (int j = 0; j < 3; ++j) {
            spans.ray(v.o[j], v.d[j]);
            spans.ray(v.c[j], v.d[j]);
        }
        for (int i = 0; i < R; ++i) spans.row(v.a[i][0], v.a[i][1], v.a[i][2], v.h[i]);
        return spans;
    }
    static AffineValues<R> shifted(const AffineValues<R>& v, const AffineShifts& s) {
        AffineValues<R> w = v;
        for (int j = 0; j < 3; ++j) {
            w.o[j] = times_pow2(v.o[j], s.sp);
            w.c[j] = times_pow2(v.c[j], s.sp);
            w.d[j] = times_pow2(v.d[j], s.sd);
            for (int i = 0; i < R; ++i) w.a[i][j] = times_pow2(v.a[i][j], s.sa);
        }
        for (int i = 0; i < R; ++i) w.h[i] = times_pow2(v.h[i], s.sp + s.sa);
        return w;
    }
    // The double-word tier, first in quick_compare, num_sign, den_sign and quick_faithful
    // on safe() input: num(i, side) and den(i) as affine_row_sums makes them (so that on
    // the box's input as given they are ray_obb.hpp's obb_slab_sums bit for bit), fine
    // sums there (detail/compensated.hpp; safe() input, the rescaled one included), made
    // once per value, on first use; none where the sums are not ok.
    const QuotientSums* sums(int i, int side) const {
        if (!safe_) return nullptr;
        const int k = 2 * i + side;
        if (!((made_ >> k) & 1u)) {
            sums_[k] = affine_row_sums<true>(v_.h[i], side, v_.a[i], v_.o, v_.c, v_.d);
            made_ |= 1u << k;
        }
        return sums_[k].ok ? &sums_[k] : nullptr;
    }
    std::optional<WordQuotient> word(int i, int side) const {
        if (const QuotientSums* q = sums(i, side)) return unpack(*q);
        return std::nullopt;
    }
    // num(i, side) and den(i) as quick_compare takes them (its derivation): exact, with
    // room for every term; `full` where a checked product is not exact.
    GrowingSum<16> num_sum(int i, int side) const {
        GrowingSum<16> s;
        if (!safe_ && std::abs(v_.h[i]) >= 0x1p1000) {
            s.full = true;
            return s;
        }
        s.add(side ? v_.h[i] : -v_.h[i]);
        for (int j = 0; j < 3; ++j) {
            if (safe_) {
                s.add_product(-v_.a[i][j], v_.o[j]);
                s.add_product(v_.a[i][j], v_.c[j]);
            } else {
                s.add_product_checked(-v_.a[i][j], v_.o[j]);
                s.add_product_checked(v_.a[i][j], v_.c[j]);
            }
        }
        s.compress();
        return s;
    }
    GrowingSum<8> den_sum(int i) const {
        GrowingSum<8> s;
        for (int j = 0; j < 3; ++j) {
            if (safe_)
                s.add_product(v_.a[i][j], v_.d[j]);
            else
                s.add_product_checked(v_.a[i][j], v_.d[j]);
        }
        s.compress();
        return s;
    }
    AffineValues<R> v_;
    int shift_;
    bool safe_;
    mutable QuotientSums sums_[2 * std::size_t(R)];
    mutable unsigned made_ = 0;  // bit 2i + side: sums_ made
};

// num(i, side)/den(i) faithfully rounded to T from q's pinned value (AffineQuotients::
// pinned), for q the input as given (shift() == 0) or rescaled: a pinned c' is faithful
// for 2^shift·t, and scaled back by unscaled_faithful (detail/exact.hpp) for a
// rescaled copy, which exists for double input only (float input is always safe); a
// faithful double rounded to nearest T is a faithful T (faithful_to). None otherwise.
template <class T, int R> std::optional<T> word_faithful(const AffineQuotients<R>& q, int i, int side) {
    std::optional<double> c = q.pinned(i, side);
    if (!c) return std::nullopt;
    if (q.shift() != 0) {
        if constexpr (!std::is_same_v<T, double>) return std::nullopt;
        c = unscaled_faithful(*c, q.shift());
        if (!c) return std::nullopt;
    }
    return faithful_to<T>(*c);
}

// The exact side of a frame whose slab values are affine quotients (ObbFrame, ray_obb.hpp;
// PlaneCrossing, ray_plane.hpp), as a source of exact quotients: the quotients on the
// given input, and the rescaled ones where those are not safe for expansions
// (exact_compare and exact_faithful use scaled() then). A query asks the exact side
// rarely and then several times, so each is made on first use, once, from the frame's
// Frame::affine_values() (CRTP: the frame derives from AffineSource<R, Frame>).
template <int R, class Frame> class AffineSource {
public:
    template <class E> E num(int i, int side) const { return given().template num<E>(i, side); }
    template <class E> E den(int i) const { return given().template den<E>(i); }
    bool safe() const { return given().safe(); }
    // exact_compare's sign at any scale (detail/certified.hpp), first of all, from the
    // exact rows (affine_exact_row) where both values have one: sign(n1·d2 -
    // n2·d1)·sign(d1·d2), or sign(n·1 - c·d)·sign(d) against a constant c, each by
    // compare_products (detail/exact.hpp: exact for every finite double, whatever the
    // products' range). None where a row is not exact or a den is 0.
    std::optional<int> compare_at_any_scale(const SlabRef& a, const SlabRef& b) const {
        if (a.axis < 0) {
            const std::optional<int> s = compare_at_any_scale(b, a);
            if (!s) return std::nullopt;
            return -*s;
        }
        const AffineExactRow* x = exact_row(a.axis);
        if (!x || x->den == 0) return std::nullopt;
        const int s1 = x->den > 0 ? 1 : -1;
        if (b.axis < 0) return compare_products(x->num[a.side], 1.0, b.c, x->den) * s1;
        const AffineExactRow* y = exact_row(b.axis);
        if (!y || y->den == 0) return std::nullopt;
        return compare_products(x->num[a.side], y->den, y->num[b.side], x->den) * s1 * (y->den > 0 ? 1 : -1);
    }
    // On the balanced copy first where there is one (its constants scaled alike, where
    // that is exact), else on the input as given.
    std::optional<int> quick_compare(const SlabRef& a, const SlabRef& b) const {
        if (const AffineQuotients<R>* w = wide()) {
            SlabRef wa = a, wb = b;
            if ((a.axis >= 0 || scale_exactly(a.c, w->shift(), wa.c)) &&
                (b.axis >= 0 || scale_exactly(b.c, w->shift(), wb.c)))
                if (const std::optional<int> s = w->quick_compare(wa, wb)) return s;
        }
        return given().quick_compare(a, b);
    }
    // For double, on the balanced copy first where there is one, scaled back
    // (unscaled_faithful, detail/exact.hpp). Float input is always safe().
    template <class U> std::optional<U> quick_faithful(int i, int side) const {
        if constexpr (std::is_same_v<U, double>)
            if (const AffineQuotients<R>* w = wide())
                if (const std::optional<double> f = w->template quick_faithful<double>(i, side))
                    if (const std::optional<double> q = unscaled_faithful(*f, w->shift())) return *q;
        return given().template quick_faithful<U>(i, side);
    }
    // word_faithful on the input as given where it is safe (from an exact row's sums
    // where it has one: exact_row_sums, the same bits), else on the rescaled one. On
    // input that is not safe (double), a value of an exact row n/d is first pinned with
    // n and d each scaled to [1, 2) (n·2^kn, d·2^kd: exact, the pin's ranges hold, the
    // sums exact with zero bounds) and scaled back by 2^(kd - kn) (unscaled_faithful);
    // n == 0 is t = +0 exactly.
    template <class U> std::optional<U> word_faithful(int i, int side) const {
        const AffineExactRow* x = exact_row(i);
        if (safe()) {
            if (x) {
                const PinnedQuotient p = pin_quotient(exact_row_sums(*x, side));
                if (!p.pinned) return std::nullopt;
                return faithful_to<U>(p.c);
            }
            return detail::word_faithful<U>(given(), i, side);
        }
        if constexpr (std::is_same_v<U, double>)
            if (x && x->den != 0) {
                const double n = x->num[side], d = x->den;
                if (n == 0) return 0.0;
                const int kn = -binary_exponent(n), kd = -binary_exponent(d);
                const PinnedQuotient p = pin_quotient(exact_row_sums({{times_pow2(n, kn), 0.0}, times_pow2(d, kd)}, 0));
                if (p.pinned)
                    if (const std::optional<double> q = unscaled_faithful(p.c, kn - kd)) return *q;
            }
        if (const std::optional<AffineQuotients<R>>& s = scaled()) return detail::word_faithful<U>(*s, i, side);
        return std::nullopt;
    }
    const std::optional<AffineQuotients<R>>& scaled() const {
        if (!scaled_made_) {
            scaled_made_ = true;
            scaled_ = AffineQuotients<R>::rescaled(values());
        }
        return scaled_;
    }
    // The exact signs of den(i) and num(i, side) without the interval filter: from the
    // fixed-size sums on the given input, else on the rescaled one (signs unchanged by
    // the scaling), else in an exact type.
    int exact_den_sign(int i) const {
        if (const AffineExactRow* x = exact_row(i)) return (x->den > 0) - (x->den < 0);
        if (const std::optional<int> s = from_sums([&](const AffineQuotients<R>& q) { return q.den_sign(i); }))
            return *s;
        return exact_sign(safe(), [&](auto tag) { return den<typename decltype(tag)::type>(i); });
    }
    int exact_num_sign(int i, int side) const {
        if (const AffineExactRow* x = exact_row(i)) return (x->num[side] > 0) - (x->num[side] < 0);
        if (const std::optional<int> s = from_sums([&](const AffineQuotients<R>& q) { return q.num_sign(i, side); }))
            return *s;
        return exact_sign(safe(), [&](auto tag) { return num<typename decltype(tag)::type>(i, side); });
    }

protected:
    explicit AffineSource(bool floats) : floats_(floats) {}

private:
    // What decide(q) answers (an optional) on the given quotients, else on the rescaled
    // ones when the given are not safe; nullopt where neither decides.
    template <class Decide> auto from_sums(Decide&& decide) const -> decltype(decide(std::declval<const AffineQuotients<R>&>())) {
        if (auto x = decide(given())) return x;
        if (!safe() && scaled()) return decide(*scaled());
        if (const AffineQuotients<R>* w = wide()) return decide(*w);
        return std::nullopt;
    }
    // The balanced copy (AffineQuotients::balanced) of input that is not safe() and has
    // no rescaled one, made on first use; null where there is none.
    const AffineQuotients<R>* wide() const {
        if (safe() || scaled()) return nullptr;
        if (!balanced_made_) {
            balanced_made_ = true;
            balanced_ = AffineQuotients<R>::balanced(values());
        }
        return balanced_ ? &*balanced_ : nullptr;
    }
    const AffineQuotients<R>& given() const {
        if (!given_) given_.emplace(values(), floats_);
        return *given_;
    }
    // Row i's exact values (affine_exact_row); null where it has none. Every row is made
    // on the first use of one, once (a query that asks one row mostly asks the others:
    // its comparisons and roundings run over the axes), from the deltas made once.
    const AffineExactRow* exact_row(int i) const {
        if (!rows_made_) {
            rows_made_ = true;
            const AffineValues<R>& v = given().values();
            if (const std::optional<AffineDeltas> delta = affine_exact_deltas(v))
                for (int k = 0; k < R; ++k)
                    if (const std::optional<AffineExactRow> x = affine_exact_row(v, *delta, k)) {
                        row_[k] = *x;
                        exact_rows_ |= 1u << k;
                    }
        }
        return ((exact_rows_ >> i) & 1u) ? &row_[i] : nullptr;
    }
    AffineValues<R> values() const { return static_cast<const Frame&>(*this).affine_values(); }
    mutable std::optional<AffineQuotients<R>> given_, scaled_, balanced_;
    mutable AffineExactRow row_[std::size_t(R)];
    mutable unsigned exact_rows_ = 0;  // bit i: row i is exact
    mutable bool rows_made_ = false, scaled_made_ = false, balanced_made_ = false;
    bool floats_;
};

}  // namespace rayproof::detail
