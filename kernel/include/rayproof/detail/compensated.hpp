// rayproof/detail/compensated.hpp — a quotient t = N/D of two short sums of products of
// doubles, pinned between two adjacent doubles in double-word arithmetic with proven
// error bounds, with no interval and no branch. It sits between the interval filter,
// whose enclosures of t are a few ulps wide (too wide to pin a faithful rounding), and
// exact arithmetic (detail/exact.hpp): it answers when its bounds decide, and otherwise
// says so, never a guess. Used by the plane (N = offset - n·o, D = n·d) and by the
// oriented box (each slab value, N = ±h_i - a_i·(o - c), D = a_i·d).
//
// Sums (quotient_sums): N in lane 0 and D in lane 1 (detail/lanes.hpp), each a start
// value plus P products held exactly as hi + lo (exact_product). s cascades the start and
// the P high parts by two_sum, whose errors q_k are exact; c = fl(q_1 + lo_1 + ... + q_P
// + lo_P) in that order (Sum2 of Ogita, Rump and Oishi, "Accurate sum and dot product",
// SIAM J. Sci. Comput. 26(6), 2005). Then the sum is s + Σq_k + Σlo_k exactly, and the
// recursive sum c of the 2P small terms is off by at most gamma(2P - 1)·S, S = Σ|q_k| +
// Σ|lo_k| (Higham, ASNA, 4.2); bound = fl(2·gamma(2P - 1)·fl(S)) covers it (fl(S) >=
// (1 - gamma(2P - 1))·S; the doubling covers that and the product's rounding). The bound
// is 0 exactly when every small term is, and then s + c is the exact sum: integer-like
// input (exact products) is decided exactly, zeros included. s and c are then
// renormalized by fast_two_sum (exact when |c| <= |s| or s == 0, checked; the same exact
// sum, its high part fl(s + c), |c| <= u|s| after it): below, s_N + c_N and s_D + c_D
// name the renormalized pairs, b_N and b_D their bounds.
// Range (in_range, checked by the caller on every factor and the start): each factor 0
// or of magnitude in [2^-450, 2^490], the start 0 or in [2^-450, 2^1000], P <= 6. Then
// every product is exact (exact_product's conditions: a nonzero product is at least
// 2^-900), nothing overflows (every partial sum below 2^1001), every term and partial sum
// is a multiple of 2^-1004 (so 0 or normal, and the additions' relative error bound
// holds), and a nonzero S is at least 2^-1004 (the bound's rounding, even subnormal,
// stays far inside the doubling's slack).
//
// Pin (pin_quotient): pinned means that t lies strictly between the two neighbours of c,
// so c is one of the two doubles enclosing t (t itself when t is a double), and D != 0.
// Candidate: tt = fl(s_N/s_D) cut to 26 bits and s_D = d26 + d27 (d26 cut the same way,
// d27 = s_D - d26 exact, at most 27 bits): under the guards |tt| >= 2^-490 and |s_D| >=
// 2^-500 (both finite; |s_D| < 2^1001 by the range) the products tt·d26 and tt·d27 (at
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
//
// Contraction (detail/eft.hpp, classes C1-C3): the sums' products come from
// exact_product, whose hi is rounded() (C3), so the two_sum cascade adds fl(a_k·b_k) as
// the derivation says; the bound S·K and the pin's error terms are class C1 (a fused
// fl(nl - tt·dl), fl(rho - (c - tt)·s_D), or a fused step of e, lhs and rhs, is the
// separate form with that product's rounding 0, which each bound above already allows
// for, and lhs and rhs only gain by it); tt·d26 and tt·d27 are exact (C2), so x1 and x2
// are the same fused or not. The candidate's product rho·fl(1/s_D) is rounded() (C3):
// the proof holds for any candidate, but the plane's and the Obb's two paths round t by
// this routine and must get the same bits, whatever the compiler fuses in each copy.
#pragma once

#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/lanes.hpp>
#include <rayproof/detail/rounding.hpp>

#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>

namespace rayproof::detail {

// Each lane 0 or of magnitude in [2^-450, top] (false for NaN and infinities).
RAYPROOF_ALWAYS_INLINE lanes::M2 in_range(lanes::D2 x, lanes::D2 top) {
    return lanes::in_band(x, lanes::splat(0x1p-450), top);
}
RAYPROOF_ALWAYS_INLINE lanes::M2 in_range(lanes::D2 x) { return in_range(x, lanes::splat(0x1p490)); }

// N (lane 0) and D (lane 1) with |X - (hi + lo)| <= bound, |lo| <= u|hi|; ok when the
// inputs were in range (the caller's mask) and the renormalization exact.
struct QuotientSums {
    lanes::D2 hi, lo, bound;
    bool ok;
};
template <std::size_t P>
RAYPROOF_ALWAYS_INLINE QuotientSums quotient_sums(lanes::D2 start, const lanes::D2 (&a)[P], const lanes::D2 (&b)[P],
                                                  lanes::M2 inputs_in_range) {
    using namespace lanes;
    static_assert(P >= 1 && P <= 6);
    constexpr double K = 2 * gamma<double>(2 * static_cast<int>(P) - 1);
    D2 s = start, c = splat(0.0), S = splat(0.0);
    for (std::size_t k = 0; k < P; ++k) {
        const Product q = exact_product(a[k], b[k]);
        const SumOf<D2> x = two_sum(s, q.hi);
        s = x.hi;
        c = (c + x.lo) + q.lo;
        S = (S + abs(x.lo)) + abs(q.lo);
    }
    const SumOf<D2> r = fast_two_sum(s, c);
    const M2 renormal = (abs(c) <= abs(s)) | (s == splat(0.0));
    return {r.hi, r.lo, S * splat(K), bits(inputs_in_range & renormal) == 3};
}

// quotient_sums, with the products taken as they stand where every factor has at most
// 26 significant bits (high26(x) == x): each product is then exact (at most 52 bits,
// no underflow in the range), so exact_product would give hi = fl(a·b) = a·b and lo =
// +0 (its error terms cancel exactly, and a sum of exact zeros led by +0 is +0), and
// these are the same sums bit for bit, without the splits. In range every factor is
// normal or 0, where the test means the same under any denormal mode; out of range the
// sums are not ok either way. Contraction (class C1 of eft.hpp) cannot change an
// exact product. For the exact stages' comparisons, where integer-like input (rays
// through a box's corners) is the common case; the straight-line paths keep
// quotient_sums (the test would cost them more than it saves on general input).
template <std::size_t P>
RAYPROOF_ALWAYS_INLINE QuotientSums quotient_sums_short_first(lanes::D2 start, const lanes::D2 (&a)[P],
                                                              const lanes::D2 (&b)[P], lanes::M2 inputs_in_range) {
    using namespace lanes;
    static_assert(P >= 1 && P <= 6);
    int short_factors = 3;
    for (std::size_t k = 0; k < P; ++k) short_factors &= bits(high26(a[k]) == a[k]) & bits(high26(b[k]) == b[k]);
    if (short_factors != 3) return quotient_sums(start, a, b, inputs_in_range);
    constexpr double K = 2 * gamma<double>(2 * static_cast<int>(P) - 1);
    D2 s = start, c = splat(0.0), S = splat(0.0);
    for (std::size_t k = 0; k < P; ++k) {
        const SumOf<D2> x = two_sum(s, a[k] * b[k]);
        s = x.hi;
        c = (c + x.lo) + splat(0.0);
        S = (S + abs(x.lo)) + splat(0.0);
    }
    const SumOf<D2> r = fast_two_sum(s, c);
    const M2 renormal = (abs(c) <= abs(s)) | (s == splat(0.0));
    return {r.hi, r.lo, S * splat(K), bits(inputs_in_range & renormal) == 3};
}

// t = N/D pinned: t lies strictly between the two neighbours of c when pinned.
struct PinnedQuotient {
    double c;
    bool pinned;
};
RAYPROOF_ALWAYS_INLINE PinnedQuotient pin_quotient(const QuotientSums& s) {
    using namespace lanes;
    constexpr double u = unit_roundoff<double>;
    const double nh = lane0(s.hi), nl = lane0(s.lo), dh = lane1(s.hi), dl = lane1(s.lo), bn = lane0(s.bound),
                 bd = lane1(s.bound);
    // R(tt) and the candidate.
    const double inv = 1 / dh, tt = high26(nh / dh), d26 = high26(dh);
    const double x1 = nh - tt * d26, x2 = x1 - tt * (dh - d26), e1 = tt * dl, x3 = nl - e1, rho = x2 + x3;
    const double cand = tt + rounded(rho * inv);
    const D2 scale = abs(make(tt, dh));
    const M2 scale_ok = (scale >= make(0x1p-490, 0x1p-500)) & (scale <= splat(std::numeric_limits<double>::max()));
    // R(cand) ~ v within e, and the test |t - cand| < u|cand| (see the proof above).
    const double ac = std::abs(cand), w = (cand - tt) * dh, v = rho - w;
    const double e = (bn + u * ((((std::abs(x1) + std::abs(x2)) + std::abs(e1)) + std::abs(x3)) + std::abs(rho))) +
                     (ac * bd + 5 * u * std::abs(w));
    const double lhs = (std::abs(v) * (1 + 2 * u) + (2 * e + 0x1p-1020)) * (1 + 0x1p-40);
    const double rhs = (u * ac) * (std::abs(dh) * (1 - 0x1p-40) - 4 * bd);
    const bool pinned = int(s.ok) & int(bits(scale_ok) == 3) & int(ac >= 0x1p-900) & int(lhs < rhs);
    return {cand, pinned};
}

// Comparisons from the pairs (word_sign, word_compare): the exact sign of N, of N1/D1 -
// N2/D2 and of N/D - c, or none where the bounds do not decide it; between the interval
// filter and the exact sums, for the comparisons of the slab method's general path
// (an entry against the latest one, an exit against the earliest, each against t_min
// or t_max) where two values are equal or nearly so (rays through edges and corners).
// WordQuotient: N = n + nl + e_N with |nl| <= u|n| and |e_N| <= bn, D alike.
// Fine sums: quotient_sums over inputs each 0 or a multiple of 2^-152 of magnitude at
// most 2^128 (expansion_safe doubles, 0 or in [2^-100, 2^100]; every float), P <= 6.
// Then every component of a pair is 0 or a multiple of 2^-304 below 2^260 (sums of at
// most seven such products), every nonzero bound at least 2^-360 (K·S, S a nonzero sum
// of such components, K >= 2u): every product of two components is exact by two_prod
// (its error a multiple of 2^-608) and every rounded product below normal (>= 2^-720):
// no underflow anywhere in what follows.
struct WordQuotient {
    double n, nl, bn, d, dl, bd;
};
RAYPROOF_ALWAYS_INLINE WordQuotient unpack(const QuotientSums& q) {
    using lanes::lane0, lanes::lane1;
    return {lane0(q.hi), lane0(q.lo), lane0(q.bound), lane1(q.hi), lane1(q.lo), lane1(q.bound)};
}

// The exact sign of x = hi + lo + e with |lo| <= u|hi| and |e| <= b, or none: sign(hi)
// when b == 0 (hi == 0 forces lo == 0), or when |x - hi| <= u|hi| + b < |hi|, which the
// test implies: fl(|hi|·(1 - 2u)) <= |hi|(1 - 2u)(1 + u) < |hi|(1 - u).
inline std::optional<int> word_sign(double hi, double b) {
    constexpr double u = unit_roundoff<double>;
    if (b == 0 || std::abs(hi) * (1 - 2 * u) > b) return (hi > 0) - (hi < 0);
    return std::nullopt;
}

// X = N1·D2 - N2·D1 for fine sums x and y as s + r within B: the pairs' part n1'·d2' -
// n2'·d1' (n1' = n1 + nl1, ...) is s + s' + Σ_k t_k exactly, with (p, p') = two_prod(n1,
// d2), (q, q') = two_prod(n2, d1), (s, s') = two_sum(p, -q) (each exact: the ranges
// above) and the nine terms t = s', p', -q', n1·dl2, nl1·d2, -n2·dl1, -nl2·d1, nl1·dl2,
// -nl2·dl1; r, their sum in that order, is within gamma(9)·T of the exact one, T =
// Σ|t_k| (a term sees one product's rounding and at most eight additions'; Higham, ASNA,
// 3.1 and 4.2; contraction, class C1, only removes roundings). The bounds' part:
//     |N1·D2 - n1'·d2'| <= |n1'|·bd2 + bn1·|d2'| + bn1·bd2, |n1'| <= (1 + u)|n1|,
// and alike for N2·D1. So |X - (s + r)| <= gamma(9)·T + (1 + u)(|n1|·bd2 + bn1·|d2| +
// |n2|·bd1 + bn2·|d1|) + bn1·bd2 + bn2·bd1, and the computed B doubles that (covering
// the factors 1 + u, the terms' roundings and the additions of B). B == 0 means every
// term and every bound is 0 (none underflows: the ranges above), and then X == s.
struct WordDifference {
    double s, r, B;
};
inline WordDifference word_difference(const WordQuotient& x, const WordQuotient& y) {
    constexpr double u = unit_roundoff<double>;
    const Pair p = two_prod(x.n, y.d), q = two_prod(y.n, x.d), s = two_sum(p.hi, -q.hi);
    const double t[9] = {s.lo, p.lo, -q.lo, x.n * y.dl, x.nl * y.d, -(y.n * x.dl), -(y.nl * x.d), x.nl * y.dl, -(y.nl * x.dl)};
    double r = 0, T = 0;
    for (const double v : t) {
        r += v;
        T += std::abs(v);
    }
    const double B = 2 * (gamma<double>(9) * T + ((1 + u) * ((std::abs(x.n) * y.bd + x.bn * std::abs(y.d)) +
                                                             (std::abs(y.n) * x.bd + y.bn * std::abs(x.d))) +
                                                  (x.bn * y.bd + y.bn * x.bd)));
    return {s.hi, r, B};
}
// Y = N - c·D for a fine sum x and a constant c == 0 or 2^-300 <= |c| <= 2^300 (so that
// c·d is exact by two_prod and c·dl, |c|·bd normal) as s + r within B: (p, p') =
// two_prod(c, d), (s, s') = two_sum(n, -p), the terms s', nl, -p', -c·dl (gamma(4)),
// B = 2(gamma(4)·T + bn + |c|·bd) as above.
inline WordDifference word_difference(const WordQuotient& x, double c) {
    const Pair p = two_prod(c, x.d), s = two_sum(x.n, -p.hi);
    const double t[4] = {s.lo, x.nl, -p.lo, -(c * x.dl)};
    double r = 0, T = 0;
    for (const double v : t) {
        r += v;
        T += std::abs(v);
    }
    return {s.hi, r, 2 * (gamma<double>(4) * T + (x.bn + std::abs(c) * x.bd))};
}
// The sign of a difference s + r + E, |E| <= B: z = fl(s + r) has the sign of s + r and
// |s + r| >= |z|/(1 + u), so |z| > B (which B's doubling leaves room for) gives sign(z);
// and B == 0 gives it exactly (0 at a tie). None otherwise.
inline std::optional<int> word_difference_sign(const WordDifference& w) {
    const double z = w.s + w.r;
    if (!(w.B == 0 || std::abs(z) > w.B)) return std::nullopt;
    return (z > 0) - (z < 0);
}

// sign(N1/D1 - N2/D2) = sign(X)·sign(D1)·sign(D2) for fine sums x and y, the signs of
// D1 and D2 from word_sign; none where one is unknown or 0, or where X's is.
inline std::optional<int> word_compare(const WordQuotient& x, const WordQuotient& y) {
    const std::optional<int> sx = word_sign(x.d, x.bd), sy = word_sign(y.d, y.bd);
    if (!sx || !sy || *sx == 0 || *sy == 0) return std::nullopt;
    const std::optional<int> s = word_difference_sign(word_difference(x, y));
    if (!s) return std::nullopt;
    return *s * *sx * *sy;
}
// sign(N/D - c) = sign(Y)·sign(D) for a fine sum x and a constant c (0, or of magnitude
// in [2^-300, 2^300]), or none.
inline std::optional<int> word_compare(const WordQuotient& x, double c) {
    const double ac = std::abs(c);
    const std::optional<int> sx = word_sign(x.d, x.bd);
    if (!sx || *sx == 0 || !(c == 0 || (ac >= 0x1p-300 && ac <= 0x1p300))) return std::nullopt;
    const std::optional<int> s = word_difference_sign(word_difference(x, c));
    if (!s) return std::nullopt;
    return *s * *sx;
}

}  // namespace rayproof::detail
