// rayproof/detail/eft.hpp — error-free transformations: a sum or a product of two
// floating-point numbers as an unevaluated sum hi + lo that equals it exactly (two_sum,
// fast_two_sum, two_prod, Dekker's product on Veltkamp's split), and x·y - z with one
// rounding (mul_sub). Written once for double and, where marked, for the two-lane
// type lanes::D2 (detail/lanes.hpp), whose operations are the same IEEE operations in
// each lane.
//
// References: Knuth, TAOCP vol. 2, 4.2.2 (TwoSum); Dekker, "A floating-point technique
// for extending the available precision", Numer. Math. 18, 1971 (FastTwoSum, the exact
// product and Veltkamp's split); Higham, ASNA, 4.3.
#pragma once

#include <rayproof/detail/float_util.hpp>

#include <cmath>

namespace rayproof::detail {

// An unevaluated sum hi + lo: of two doubles (Pair), or lane by lane of two
// lanes::D2 (the certified box's two-lane path).
template <class V> struct SumOf {
    V hi, lo;
};
using Pair = SumOf<double>;

// Knuth's TwoSum: hi = fl(a + b) and lo = (a + b) − hi exactly. Branch-free, 6 flops,
// no precondition on the order of a and b. Exact whenever no operation overflows,
// subnormals included (the error of a floating-point addition is always
// representable); that holds for |a|, |b| <= 2^1022. Near ±max the intermediate
// s − a can overflow although s does not: lo is then NaN (expansions catch it as a
// non-finite component), never a wrong finite value. V is double, or lanes::D2 (the same
// operations in each lane).
template <class V> inline SumOf<V> two_sum(V a, V b) {
    const V s = a + b;
    const V bv = s - a;
    const V av = s - bv;
    return {s, (a - av) + (b - bv)};
}

// Dekker's FastTwoSum: hi = fl(a + b), lo = (a + b) − hi, 3 flops. Exact when
// a == 0 or exponent(a) >= exponent(b) (in particular when |a| >= |b|) and fl(a + b)
// does not overflow (then s − a is exact, no intermediate can overflow). V as for
// two_sum.
template <class V> inline SumOf<V> fast_two_sum(V a, V b) {
    const V s = a + b;
    const V bv = s - a;
    return {s, b - bv};
}

// TwoProduct with a fused multiply-add: hi = fl(a·b), lo = a·b − hi exactly.
// Exact when the product does not overflow and its error term is representable. The
// error is an integer multiple of 2^(la+lb) below 2^53 units, la and lb the exponents
// of the last bits of a and b, so it is representable exactly when la + lb >= −1074;
// a sufficient condition is |hi| >= 2^(emin + 2p) = 2^-916, i.e. the error term is not
// subnormal (then exponent(a) + exponent(b) >= −918, la + lb >= −1022).
inline Pair two_prod(double a, double b) {
    const double p = a * b;
    return {p, std::fma(a, b, -p)};
}

// Veltkamp's split of a into a high part of at most 26 significant bits: c = f·a with
// f = 2^27 + 1, high = c - (c - a); then a - high is exact and has at most 27 bits.
// Exact while f·a does not overflow (|a| <= 2^995 is ample). V is double, or lanes::D2
// with `factor` the splatted constant.
inline constexpr double kVeltkampFactor = 134217729.0;  // 2^27 + 1
template <class V> RAYPROOF_ALWAYS_INLINE V veltkamp_high(V a, V factor) {
    const V c = factor * a;
    return c - (c - a);
}

// Dekker's product on Veltkamp's split: hi = fl(a·b) and lo = a·b - hi exactly. With
// a = ah + al and b = bh + bl (veltkamp_high) the four partial products are exact and
// so is every step of the error's sum, while nothing overflows or underflows (see the
// users for their ranges). For a target without a fused multiply-add; V as above.
template <class V> RAYPROOF_ALWAYS_INLINE SumOf<V> dekker_product(V a, V b, V factor) {
    const V ah = veltkamp_high(a, factor), bh = veltkamp_high(b, factor), al = a - ah, bl = b - bh, p = a * b;
    return {p, (((ah * bh - p) + ah * bl) + al * bh) + al * bl};
}

// x·y - z with one rounding: the fused multiply-add where the target has one, else
// Dekker's exact product (x·y = ph + pl; exact when nothing overflows or underflows)
// followed by (ph - z) + pl, where ph - z must be exact (Sterbenz: ph and z within a
// factor 2 of each other, as in the Aabb's faithful_slab_double) so that the last
// subtraction rounds once.
RAYPROOF_ALWAYS_INLINE double mul_sub(double x, double y, double z) {
#if defined(__FMA__) || defined(__FP_FAST_FMA)
    return std::fma(x, y, -z);
#else
    const Pair p = dekker_product(x, y, kVeltkampFactor);
    return (p.hi - z) + p.lo;
#endif
}

}  // namespace rayproof::detail
