// rayproof/detail/lanes.hpp — two doubles computed side by side, for the certified
// straight-line paths: the box runs the entry and the (negated) exit problem in the two
// lanes (ray_aabb.hpp, aabb_certified_common), the plane its numerator and denominator
// (ray_plane.hpp, plane_pin).
//
// Each operation is the correctly rounded IEEE operation on each lane, so a lane
// computes exactly what the same scalar code computes: on x86-64 with SSE2 (every
// x86-64 processor) one instruction does both lanes, elsewhere two scalar operations
// do. min and max follow the SSE rule on both: min(a, b) = a < b ? a : b and max(a, b)
// = a > b ? a : b, so a NaN in either operand gives b. Comparisons are ordered (false
// on a NaN) and give a lane mask whose bits() are bit 0 for lane 0, bit 1 for lane 1.
#pragma once

#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/float_util.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#define RAYPROOF_LANES_SSE2 1
#endif
#if defined(RAYPROOF_LANES_SSE2) && defined(RAYPROOF_FUSED_PRODUCTS) && defined(__FMA__)
#include <immintrin.h>
#endif

namespace rayproof::detail::lanes {

// The significand cut to its leading 26 bits (the last 27 stored bits cleared): exact
// truncation towards zero, |a - high26(a)| < 2^-25 |a| for normal a.
RAYPROOF_ALWAYS_INLINE double high26(double a) {
    return std::bit_cast<double>(std::bit_cast<std::uint64_t>(a) & ~std::uint64_t(0x7ffffff));
}

#if defined(RAYPROOF_LANES_SSE2)

struct D2 {
    __m128d v;
};
struct M2 {
    __m128d v;
};
RAYPROOF_ALWAYS_INLINE D2 make(double lane0, double lane1) { return {_mm_set_pd(lane1, lane0)}; }
RAYPROOF_ALWAYS_INLINE D2 splat(double x) { return {_mm_set1_pd(x)}; }
// (p[0], p[1]) as doubles (exact for float), in one load.
RAYPROOF_ALWAYS_INLINE D2 load2(const double* p) { return {_mm_loadu_pd(p)}; }
RAYPROOF_ALWAYS_INLINE D2 load2(const float* p) {
    return {_mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))))};
}
// The four floats in the 16 bytes at p as (p[0], p[1]) and (p[2], p[3]), exact, in one
// load (see float_quad below).
struct Quad {
    D2 lo, hi;
};
RAYPROOF_ALWAYS_INLINE Quad load4(const unsigned char* p) {
    const __m128 v = _mm_loadu_ps(reinterpret_cast<const float*>(p));
    return {{_mm_cvtps_pd(v)}, {_mm_cvtps_pd(_mm_movehl_ps(v, v))}};
}
// (lane 0 of a, lane 0 of b) and (lane 1 of a, lane 1 of b).
RAYPROOF_ALWAYS_INLINE D2 lows(D2 a, D2 b) { return {_mm_unpacklo_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE D2 highs(D2 a, D2 b) { return {_mm_unpackhi_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE double lane0(D2 a) { return _mm_cvtsd_f64(a.v); }
RAYPROOF_ALWAYS_INLINE double lane1(D2 a) { return _mm_cvtsd_f64(_mm_unpackhi_pd(a.v, a.v)); }
RAYPROOF_ALWAYS_INLINE D2 swap(D2 a) { return {_mm_shuffle_pd(a.v, a.v, 1)}; }
// (lane 0 of a, lane 1 of b).
RAYPROOF_ALWAYS_INLINE D2 low_high(D2 a, D2 b) { return {_mm_shuffle_pd(a.v, b.v, 2)}; }
// (lane 1 of a, lane 0 of b).
RAYPROOF_ALWAYS_INLINE D2 high_low(D2 a, D2 b) { return {_mm_shuffle_pd(a.v, b.v, 1)}; }
RAYPROOF_ALWAYS_INLINE D2 operator+(D2 a, D2 b) { return {_mm_add_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE D2 operator-(D2 a, D2 b) { return {_mm_sub_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE D2 operator*(D2 a, D2 b) { return {_mm_mul_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE D2 operator/(D2 a, D2 b) { return {_mm_div_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE D2 min(D2 a, D2 b) { return {_mm_min_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE D2 max(D2 a, D2 b) { return {_mm_max_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE D2 abs(D2 a) { return {_mm_andnot_pd(_mm_set1_pd(-0.0), a.v)}; }
// Lane 1 negated, both lanes negated (exact).
RAYPROOF_ALWAYS_INLINE D2 negate_lane1(D2 a) { return {_mm_xor_pd(a.v, _mm_set_pd(-0.0, 0.0))}; }
RAYPROOF_ALWAYS_INLINE D2 negate_lane0(D2 a) { return {_mm_xor_pd(a.v, _mm_set_pd(0.0, -0.0))}; }
// a with the sign bit of s added onto it (a·sign(s) exactly, for s not ±0 or NaN).
RAYPROOF_ALWAYS_INLINE D2 times_sign(D2 a, D2 s) { return {_mm_xor_pd(a.v, _mm_and_pd(s.v, _mm_set1_pd(-0.0)))}; }
RAYPROOF_ALWAYS_INLINE D2 operator-(D2 a) { return {_mm_xor_pd(a.v, _mm_set1_pd(-0.0))}; }
RAYPROOF_ALWAYS_INLINE M2 operator<(D2 a, D2 b) { return {_mm_cmplt_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE M2 operator>(D2 a, D2 b) { return {_mm_cmpgt_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE M2 operator<=(D2 a, D2 b) { return {_mm_cmple_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE M2 operator>=(D2 a, D2 b) { return {_mm_cmpge_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE M2 operator==(D2 a, D2 b) { return {_mm_cmpeq_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE M2 operator&(M2 a, M2 b) { return {_mm_and_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE M2 operator|(M2 a, M2 b) { return {_mm_or_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE int bits(M2 a) { return _mm_movemask_pd(a.v); }
// Lane 0's, lane 1's mask in both lanes.
RAYPROOF_ALWAYS_INLINE M2 both_lane0(M2 a) { return {_mm_unpacklo_pd(a.v, a.v)}; }
RAYPROOF_ALWAYS_INLINE M2 both_lane1(M2 a) { return {_mm_unpackhi_pd(a.v, a.v)}; }
// high26 in both lanes.
RAYPROOF_ALWAYS_INLINE D2 high26(D2 a) { return {_mm_and_pd(a.v, _mm_castsi128_pd(_mm_set1_epi64x(~std::int64_t(0x7ffffff))))}; }
// The lanes where the mask is set, +0 elsewhere.
RAYPROOF_ALWAYS_INLINE D2 keep(M2 m, D2 a) { return {_mm_and_pd(m.v, a.v)}; }
// a where the mask is set, b elsewhere.
RAYPROOF_ALWAYS_INLINE D2 select(M2 m, D2 a, D2 b) { return {_mm_or_pd(_mm_and_pd(m.v, a.v), _mm_andnot_pd(m.v, b.v))}; }

// Both lanes as values the compiler cannot see into (detail::rounded, eft.hpp): the
// SSE operations above are plain vector arithmetic to g++ and clang, which contract
// them like scalar code.
RAYPROOF_ALWAYS_INLINE D2 rounded(D2 a) {
#if defined(__GNUC__) || defined(__clang__)
    __asm__("" : "+x"(a.v));
    return a;
#else
    return {_mm_set_pd(detail::rounded(lane1(a)), detail::rounded(lane0(a)))};
#endif
}

// hi = fl(a·b) and lo = a·b - hi exactly, in each lane (see exact_product below).
using Product = SumOf<D2>;
#if defined(RAYPROOF_FUSED_PRODUCTS) && defined(__FMA__)
RAYPROOF_ALWAYS_INLINE Product exact_product(D2 a, D2 b) {
    const D2 p = rounded(D2{_mm_mul_pd(a.v, b.v)});
    return {p, {_mm_fmsub_pd(a.v, b.v, p.v)}};
}
#else
RAYPROOF_ALWAYS_INLINE Product exact_product(D2 a, D2 b) { return dekker_product(a, b, splat(kVeltkampFactor)); }
#endif

#else  // two scalars, the same semantics lane by lane

struct D2 {
    double a, b;
};
struct Quad {
    D2 lo, hi;
};
struct M2 {
    bool a, b;
};
RAYPROOF_ALWAYS_INLINE D2 make(double lane0, double lane1) { return {lane0, lane1}; }
RAYPROOF_ALWAYS_INLINE D2 splat(double x) { return {x, x}; }
template <class T> RAYPROOF_ALWAYS_INLINE D2 load2(const T* p) { return {double(p[0]), double(p[1])}; }
RAYPROOF_ALWAYS_INLINE D2 lows(D2 x, D2 y) { return {x.a, y.a}; }
RAYPROOF_ALWAYS_INLINE D2 highs(D2 x, D2 y) { return {x.b, y.b}; }
RAYPROOF_ALWAYS_INLINE double lane0(D2 x) { return x.a; }
RAYPROOF_ALWAYS_INLINE double lane1(D2 x) { return x.b; }
RAYPROOF_ALWAYS_INLINE D2 swap(D2 x) { return {x.b, x.a}; }
RAYPROOF_ALWAYS_INLINE D2 low_high(D2 x, D2 y) { return {x.a, y.b}; }
RAYPROOF_ALWAYS_INLINE D2 high_low(D2 x, D2 y) { return {x.b, y.a}; }
RAYPROOF_ALWAYS_INLINE D2 operator+(D2 x, D2 y) { return {x.a + y.a, x.b + y.b}; }
RAYPROOF_ALWAYS_INLINE D2 operator-(D2 x, D2 y) { return {x.a - y.a, x.b - y.b}; }
RAYPROOF_ALWAYS_INLINE D2 operator*(D2 x, D2 y) { return {x.a * y.a, x.b * y.b}; }
RAYPROOF_ALWAYS_INLINE D2 operator/(D2 x, D2 y) { return {x.a / y.a, x.b / y.b}; }
RAYPROOF_ALWAYS_INLINE D2 min(D2 x, D2 y) { return {x.a < y.a ? x.a : y.a, x.b < y.b ? x.b : y.b}; }
RAYPROOF_ALWAYS_INLINE D2 max(D2 x, D2 y) { return {x.a > y.a ? x.a : y.a, x.b > y.b ? x.b : y.b}; }
RAYPROOF_ALWAYS_INLINE D2 abs(D2 x) { return {std::abs(x.a), std::abs(x.b)}; }
RAYPROOF_ALWAYS_INLINE D2 negate_lane1(D2 x) { return {x.a, -x.b}; }
RAYPROOF_ALWAYS_INLINE D2 negate_lane0(D2 x) { return {-x.a, x.b}; }
RAYPROOF_ALWAYS_INLINE D2 times_sign(D2 x, D2 s) {
    return {std::signbit(s.a) ? -x.a : x.a, std::signbit(s.b) ? -x.b : x.b};
}
RAYPROOF_ALWAYS_INLINE D2 operator-(D2 x) { return {-x.a, -x.b}; }
RAYPROOF_ALWAYS_INLINE M2 operator<(D2 x, D2 y) { return {x.a < y.a, x.b < y.b}; }
RAYPROOF_ALWAYS_INLINE M2 operator>(D2 x, D2 y) { return {x.a > y.a, x.b > y.b}; }
RAYPROOF_ALWAYS_INLINE M2 operator<=(D2 x, D2 y) { return {x.a <= y.a, x.b <= y.b}; }
RAYPROOF_ALWAYS_INLINE M2 operator>=(D2 x, D2 y) { return {x.a >= y.a, x.b >= y.b}; }
RAYPROOF_ALWAYS_INLINE M2 operator==(D2 x, D2 y) { return {x.a == y.a, x.b == y.b}; }
RAYPROOF_ALWAYS_INLINE M2 operator&(M2 x, M2 y) { return {x.a && y.a, x.b && y.b}; }
RAYPROOF_ALWAYS_INLINE M2 operator|(M2 x, M2 y) { return {x.a || y.a, x.b || y.b}; }
RAYPROOF_ALWAYS_INLINE int bits(M2 x) { return int(x.a) | (int(x.b) << 1); }
RAYPROOF_ALWAYS_INLINE M2 both_lane0(M2 x) { return {x.a, x.a}; }
RAYPROOF_ALWAYS_INLINE M2 both_lane1(M2 x) { return {x.b, x.b}; }
RAYPROOF_ALWAYS_INLINE D2 high26(D2 x) { return {high26(x.a), high26(x.b)}; }
RAYPROOF_ALWAYS_INLINE D2 keep(M2 m, D2 x) { return {m.a ? x.a : 0.0, m.b ? x.b : 0.0}; }
RAYPROOF_ALWAYS_INLINE D2 select(M2 m, D2 x, D2 y) { return {m.a ? x.a : y.a, m.b ? x.b : y.b}; }

RAYPROOF_ALWAYS_INLINE D2 rounded(D2 x) { return {detail::rounded(x.a), detail::rounded(x.b)}; }

using Product = SumOf<D2>;
RAYPROOF_ALWAYS_INLINE Product exact_product(D2 a, D2 b) {
    const D2 p = rounded(a * b);
    return {p, {std::fma(a.a, b.a, -p.a), std::fma(a.b, b.b, -p.b)}};
}

#endif

// exact_product(a, b): the exact product split in two, by a fused multiply-add where the
// target has one, else by Dekker's product on Veltkamp's split (detail/eft.hpp: each
// factor a = ah + al exactly, ah and al of at most 26 significant bits, so the four
// partial products are exact and so is every step of the error's sum). Both are exact
// in a lane where |a|, |b| <= 2^995 (the split cannot overflow), neither is subnormal,
// and |hi| >= 2^-916 or a factor is 0: then the exponents of a and b add up to at least -918,
// every partial product is a multiple of 2^-1022 and nothing is lost to underflow. The
// fused form is written out with its own intrinsic; the split form is used where the
// target has no fused multiply-add (or under RAYPROOF_SPLIT_PRODUCTS, eft.hpp).
// Contraction (eft.hpp, class C3): hi is rounded(a·b) in both forms, so that no later
// addition (quotient_sums adds it with two_sum) can fuse the product and take it
// unrounded; the split form's Veltkamp products are rounded() too (veltkamp_high), and
// its partial products are exact (class C2).

// valid_range (validate.hpp) in the lanes, for ordered = (t_min, -t_max): t_min <= t_max,
// t_min != +inf and t_max != -inf, as the one test fl(t_min + (-t_max)) <= 0 (in both
// lanes, the same sum). A sum of two doubles rounds to a value of its exact sign, to 0
// only when it is 0 (no underflow in an addition) and to ±inf of its sign when it
// overflows, so for finite ends the test is t_min <= t_max. With an infinite end the sum
// is -inf (t_min = -inf or t_max = +inf, the other end finite or the other infinity:
// valid), +inf (t_min = +inf or t_max = -inf, the other end finite) or NaN (t_min =
// t_max = ±inf); NaN in an end gives NaN, which fails. Both bits set when the range is
// valid.
RAYPROOF_ALWAYS_INLINE M2 valid_range_lanes(D2 ordered) { return ordered + swap(ordered) <= splat(0.0); }

// Each lane 0 or of magnitude in [lo, hi] (ordered comparisons: false on a NaN): the
// range tests of the exact products' users (compensated.hpp's in_range, the sphere's
// residual, ray_sphere_residual.hpp).
RAYPROOF_ALWAYS_INLINE M2 in_band(D2 x, D2 lo, D2 hi) {
    const D2 a = abs(x);
    return ((a >= lo) | (a == splat(0.0))) & (a <= hi);
}

// Floats K to K + 3 of an object made of N floats and nothing else, as (f_K, f_K+1) and
// (f_K+2, f_K+3), exact: a Ray<float> is o0 o1 o2 d0 | d1 d2 t_min t_max, an
// Aabb<float> lo0 lo1 lo2 hi0 | hi1 hi2, a Plane<float> n0 n1 n2 offset. Standard layout
// and a size of N floats (checked) put float i at byte 4i. With SSE2 one 16-byte load of
// the object representation and two conversions (a scalar load and conversion per float
// costs about three instructions more); elsewhere the same bytes copied.
template <int N, int K, class S> RAYPROOF_ALWAYS_INLINE Quad float_quad(const S& s) {
    static_assert(std::is_standard_layout_v<S> && sizeof(S) == N * sizeof(float) && K >= 0 && K + 4 <= N);
    const auto* bytes = reinterpret_cast<const unsigned char*>(&s) + K * sizeof(float);
#if defined(RAYPROOF_LANES_SSE2)
    return load4(bytes);
#else
    float f[4];
    std::memcpy(f, bytes, sizeof f);
    return {make(f[0], f[1]), make(f[2], f[3])};
#endif
}

}  // namespace rayproof::detail::lanes
