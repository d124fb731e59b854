// rayproof/detail/eft.hpp — error-free transformations: a sum or a product of two
// floating-point numbers as an unevaluated sum hi + lo that equals it exactly (two_sum,
// fast_two_sum, two_prod, Dekker's product on Veltkamp's split), and x·y - z with one
// rounding (mul_sub). Written once for double and, where marked, for the two-lane
// type lanes::D2 (detail/lanes.hpp), whose operations are the same IEEE operations in
// each lane. Also rounded(x), the barrier against contraction that every routine of the
// kernel whose result depends on a product being rounded on its own goes through.
//
// References: Knuth, TAOCP vol. 2, 4.2.2 (TwoSum); Dekker, "A floating-point technique
// for extending the available precision", Numer. Math. 18, 1971 (FastTwoSum, the exact
// product and Veltkamp's split); Higham, ASNA, 4.3.
//
// Contraction. A compiler targeting a processor with a fused multiply-add may evaluate
// x·y ± z as fma(x, y, ±z), rounding once where the source rounds twice: g++ does it
// under -ffp-contract=fast (its default outside ISO mode) across statements, whenever
// every use of the product is an addition or a subtraction; clang does it within one
// expression by default (-ffp-contract=on) and across statements after inlining under
// -ffp-contract=fast; both need an FMA target (-mfma, -march=native, AArch64). A
// header cannot switch this off for its includer (g++ ignores
// #pragma STDC FP_CONTRACT OFF, and -ffp-contract is the includer's flag), so the
// kernel is written to be right either way. Every routine falls into one of three
// classes, and its comment says which:
//   (C1) error bounds in the standard model, fl(x op y) = (x op y)(1 + δ) + η with
//        |δ| <= u and |η| <= 2^-1075 (0 for additions), every operation with its own δ
//        and η (the gamma(n) bounds of Higham, ASNA, 3.1, and every bound derived term
//        by term from them). A fused fl(x·y ± z) = (x·y ± z)(1 + δ) + η is the separate
//        evaluation fl(fl(x·y) ± z) with the product's δ and η equal to 0, a case the
//        derivation already covers: each bound holds under contraction as written, with
//        one rounding to spare. That includes the bounds computed in floating point
//        (a bound evaluated with k roundings of non-negative terms is at least its exact
//        value times (1 - u)^k; fused, it has fewer than k) and the comparisons of a
//        value against the same sum of absolute values "rounded alike", which all carry
//        a factor of slack of at least 1 + 4u where the two may now differ by one
//        product's rounding (at most (1 + u)^2).
//   (C2) products that are exact (a product of two numbers of at most 26 and 27
//        significant bits, by a power of two, by a factor that is 0): fused or not, the
//        product contributes its exact value, so the result is the same bit for bit.
//   (C3) results that depend on one particular product being rounded by itself: the
//        product of an error-free transformation that later operations take apart
//        (two_prod's and exact_product's hi, Veltkamp's f·a), a value that a probe must
//        see exactly as its other users see it (an overflow to ±inf), and a candidate
//        that two code paths must compute bit for bit alike. Each such product is
//        passed through rounded(), after which the compiler has a number, not a
//        product, in hand and nothing to fuse.
// rounded(x) is an empty asm statement that takes x in a floating-point register and
// gives it back (g++ and clang honour it at every optimization level; the same device
// as detail::narrow in rounding.hpp); it emits no instruction. On a compiler without
// GNU asm the value goes through a volatile copy (MSVC contracts only under
// /fp:contract or /fp:fast, the latter refused by fp_model.hpp).
// The suites run under contraction in a CI stage (scripts/test.sh: -O3 -march=native
// -ffp-contract=fast, g++ and clang), including the split-product path forced on an FMA
// target (RAYPROOF_SPLIT_PRODUCTS, below), where the Veltkamp split is exposed to it.
#pragma once

#include <rayproof/detail/float_util.hpp>

#include <cmath>
#include <type_traits>

namespace rayproof::detail {

// x as a value the compiler cannot see into (class C3 above): a product passed through
// here is rounded on its own, and no later addition can absorb it into a fused
// multiply-add. The two-lane overload is in detail/lanes.hpp.
template <class F> [[nodiscard]] RAYPROOF_ALWAYS_INLINE F rounded_scalar(F x) noexcept {
    static_assert(std::is_same_v<F, double> || std::is_same_v<F, float>);
#if defined(__GNUC__) || defined(__clang__)
#if defined(__SSE2__) && (defined(__x86_64__) || defined(__i386__))
    __asm__("" : "+x"(x));
#elif defined(__aarch64__)
    __asm__("" : "+w"(x));
#else
    __asm__("" : "+m"(x));
#endif
    return x;
#else
    volatile F v = x;
    return v;
#endif
}
RAYPROOF_ALWAYS_INLINE double rounded(double x) noexcept { return rounded_scalar(x); }
RAYPROOF_ALWAYS_INLINE float rounded(float x) noexcept { return rounded_scalar(x); }

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
// Contraction: no product inside; the theorem needs a and b to be the values every other
// user sees, so a caller passing a product passes it through rounded() first (class C3:
// fused into s = a + b, the product would enter s unrounded and lo would miss its
// rounding error). two_prod's and exact_product's hi already are. Likewise fast_two_sum.
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
// Contraction (class C3): hi is rounded(a·b), so that hi is fl(a·b) for every user (the
// expansions add it to other components with two_sum, which a fused hi would break),
// and lo is an explicit fused multiply-add of that very hi; std::fma is exact-rounding
// on every target (a library routine where the hardware has none).
inline Pair two_prod(double a, double b) {
    const double p = rounded(a * b);
    return {p, std::fma(a, b, -p)};
}

// Veltkamp's split of a into a high part of at most 26 significant bits: c = f·a with
// f = 2^27 + 1, high = c - (c - a); then a - high is exact and has at most 27 bits.
// Exact while f·a does not overflow (|a| <= 2^995 is ample). V is double, or lanes::D2
// with `factor` the splatted constant.
// Contraction (class C3): both uses of c are subtractions, so g++ -ffp-contract=fast
// would fuse each, fl(f·a - a) and fl(f·a - fl(f·a - a)) with the exact f·a, and the
// high part would no longer be c's leading bits (nor of 26 bits): c is rounded(f·a).
inline constexpr double kVeltkampFactor = 134217729.0;  // 2^27 + 1
template <class V> RAYPROOF_ALWAYS_INLINE V veltkamp_high(V a, V factor) {
    const V c = rounded(factor * a);
    return c - (c - a);
}

// Dekker's product on Veltkamp's split: hi = fl(a·b) and lo = a·b - hi exactly. With
// a = ah + al and b = bh + bl (veltkamp_high) the four partial products are exact and
// so is every step of the error's sum, while nothing overflows or underflows (see the
// users for their ranges). For a target without a fused multiply-add; V as above.
// Contraction: the four partial products are exact (class C2), so fusing them into the
// error's sum changes nothing; p is rounded(a·b) (class C3: fused into ah·bh - p, the
// error term would be taken from the exact a·b instead of hi).
template <class V> RAYPROOF_ALWAYS_INLINE SumOf<V> dekker_product(V a, V b, V factor) {
    const V ah = veltkamp_high(a, factor), bh = veltkamp_high(b, factor), al = a - ah, bl = b - bh,
            p = rounded(a * b);
    return {p, (((ah * bh - p) + ah * bl) + al * bh) + al * bl};
}

// x·y - z with one rounding: the fused multiply-add where the target has one, else
// Dekker's exact product (x·y = ph + pl; exact when nothing overflows or underflows)
// followed by (ph - z) + pl, where ph - z must be exact (Sterbenz: ph and z within a
// factor 2 of each other, as in the Aabb's faithful_slab_double) so that the last
// subtraction rounds once. Either form is one rounding of the exact x·y - z, whatever
// the compiler contracts.
// RAYPROOF_SPLIT_PRODUCTS, defined before the first include, takes the split forms here
// and in lanes::exact_product on a target with a fused multiply-add too: a test hook, so
// that the suites check the split forms where contraction can reach them.
#if (defined(__FMA__) || defined(__FP_FAST_FMA)) && !defined(RAYPROOF_SPLIT_PRODUCTS)
#define RAYPROOF_FUSED_PRODUCTS 1
#endif
RAYPROOF_ALWAYS_INLINE double mul_sub(double x, double y, double z) {
#if defined(RAYPROOF_FUSED_PRODUCTS)
    return std::fma(x, y, -z);
#else
    const Pair p = dekker_product(x, y, kVeltkampFactor);
    return (p.hi - z) + p.lo;
#endif
}

}  // namespace rayproof::detail
