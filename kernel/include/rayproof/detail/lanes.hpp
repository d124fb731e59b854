// rayproof/detail/lanes.hpp — two doubles computed side by side, for the certified
// box path, which runs the entry and the (negated) exit problem in the two lanes
// (ray_aabb.hpp, aabb_certified_common).
//
// Each operation is the correctly rounded IEEE operation on each lane, so a lane
// computes exactly what the same scalar code computes: on x86-64 with SSE2 (every
// x86-64 processor) one instruction does both lanes, elsewhere two scalar operations
// do. min and max follow the SSE rule on both: min(a, b) = a < b ? a : b and max(a, b)
// = a > b ? a : b, so a NaN in either operand gives b. Comparisons are ordered (false
// on a NaN) and give a lane mask whose bits() are bit 0 for lane 0, bit 1 for lane 1.
#pragma once

#include <rayproof/detail/float_util.hpp>

#include <bit>
#include <cmath>
#include <cstdint>

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#define RAYPROOF_LANES_SSE2 1
#endif

namespace rayproof::detail::lanes {

#if defined(RAYPROOF_LANES_SSE2)

struct D2 {
    __m128d v;
};
struct M2 {
    __m128d v;
};
RAYPROOF_ALWAYS_INLINE D2 make(double lane0, double lane1) { return {_mm_set_pd(lane1, lane0)}; }
RAYPROOF_ALWAYS_INLINE D2 splat(double x) { return {_mm_set1_pd(x)}; }
RAYPROOF_ALWAYS_INLINE double lane0(D2 a) { return _mm_cvtsd_f64(a.v); }
RAYPROOF_ALWAYS_INLINE double lane1(D2 a) { return _mm_cvtsd_f64(_mm_unpackhi_pd(a.v, a.v)); }
RAYPROOF_ALWAYS_INLINE D2 swap(D2 a) { return {_mm_shuffle_pd(a.v, a.v, 1)}; }
// (lane 0 of a, lane 1 of b).
RAYPROOF_ALWAYS_INLINE D2 low_high(D2 a, D2 b) { return {_mm_shuffle_pd(a.v, b.v, 2)}; }
RAYPROOF_ALWAYS_INLINE D2 operator+(D2 a, D2 b) { return {_mm_add_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE D2 operator-(D2 a, D2 b) { return {_mm_sub_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE D2 operator*(D2 a, D2 b) { return {_mm_mul_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE D2 operator/(D2 a, D2 b) { return {_mm_div_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE D2 min(D2 a, D2 b) { return {_mm_min_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE D2 max(D2 a, D2 b) { return {_mm_max_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE D2 abs(D2 a) { return {_mm_andnot_pd(_mm_set1_pd(-0.0), a.v)}; }
// Lane 1 negated, both lanes negated (exact).
RAYPROOF_ALWAYS_INLINE D2 negate_lane1(D2 a) { return {_mm_xor_pd(a.v, _mm_set_pd(-0.0, 0.0))}; }
RAYPROOF_ALWAYS_INLINE D2 operator-(D2 a) { return {_mm_xor_pd(a.v, _mm_set1_pd(-0.0))}; }
RAYPROOF_ALWAYS_INLINE M2 operator<(D2 a, D2 b) { return {_mm_cmplt_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE M2 operator>(D2 a, D2 b) { return {_mm_cmpgt_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE M2 operator<=(D2 a, D2 b) { return {_mm_cmple_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE M2 operator>=(D2 a, D2 b) { return {_mm_cmpge_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE M2 operator==(D2 a, D2 b) { return {_mm_cmpeq_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE M2 operator&(M2 a, M2 b) { return {_mm_and_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE M2 operator|(M2 a, M2 b) { return {_mm_or_pd(a.v, b.v)}; }
RAYPROOF_ALWAYS_INLINE int bits(M2 a) { return _mm_movemask_pd(a.v); }
// The significand cut to its leading 26 bits (the last 27 stored bits cleared): exact
// truncation towards zero, |a - high26(a)| < 2^-25 |a| for normal a.
RAYPROOF_ALWAYS_INLINE D2 high26(D2 a) { return {_mm_and_pd(a.v, _mm_castsi128_pd(_mm_set1_epi64x(~std::int64_t(0x7ffffff))))}; }
// The lanes where the mask is set, +0 elsewhere.
RAYPROOF_ALWAYS_INLINE D2 keep(M2 m, D2 a) { return {_mm_and_pd(m.v, a.v)}; }

#else  // two scalars, the same semantics lane by lane

struct D2 {
    double a, b;
};
struct M2 {
    bool a, b;
};
RAYPROOF_ALWAYS_INLINE D2 make(double lane0, double lane1) { return {lane0, lane1}; }
RAYPROOF_ALWAYS_INLINE D2 splat(double x) { return {x, x}; }
RAYPROOF_ALWAYS_INLINE double lane0(D2 x) { return x.a; }
RAYPROOF_ALWAYS_INLINE double lane1(D2 x) { return x.b; }
RAYPROOF_ALWAYS_INLINE D2 swap(D2 x) { return {x.b, x.a}; }
RAYPROOF_ALWAYS_INLINE D2 low_high(D2 x, D2 y) { return {x.a, y.b}; }
RAYPROOF_ALWAYS_INLINE D2 operator+(D2 x, D2 y) { return {x.a + y.a, x.b + y.b}; }
RAYPROOF_ALWAYS_INLINE D2 operator-(D2 x, D2 y) { return {x.a - y.a, x.b - y.b}; }
RAYPROOF_ALWAYS_INLINE D2 operator*(D2 x, D2 y) { return {x.a * y.a, x.b * y.b}; }
RAYPROOF_ALWAYS_INLINE D2 operator/(D2 x, D2 y) { return {x.a / y.a, x.b / y.b}; }
RAYPROOF_ALWAYS_INLINE D2 min(D2 x, D2 y) { return {x.a < y.a ? x.a : y.a, x.b < y.b ? x.b : y.b}; }
RAYPROOF_ALWAYS_INLINE D2 max(D2 x, D2 y) { return {x.a > y.a ? x.a : y.a, x.b > y.b ? x.b : y.b}; }
RAYPROOF_ALWAYS_INLINE D2 abs(D2 x) { return {std::abs(x.a), std::abs(x.b)}; }
RAYPROOF_ALWAYS_INLINE D2 negate_lane1(D2 x) { return {x.a, -x.b}; }
RAYPROOF_ALWAYS_INLINE D2 operator-(D2 x) { return {-x.a, -x.b}; }
RAYPROOF_ALWAYS_INLINE M2 operator<(D2 x, D2 y) { return {x.a < y.a, x.b < y.b}; }
RAYPROOF_ALWAYS_INLINE M2 operator>(D2 x, D2 y) { return {x.a > y.a, x.b > y.b}; }
RAYPROOF_ALWAYS_INLINE M2 operator<=(D2 x, D2 y) { return {x.a <= y.a, x.b <= y.b}; }
RAYPROOF_ALWAYS_INLINE M2 operator>=(D2 x, D2 y) { return {x.a >= y.a, x.b >= y.b}; }
RAYPROOF_ALWAYS_INLINE M2 operator==(D2 x, D2 y) { return {x.a == y.a, x.b == y.b}; }
RAYPROOF_ALWAYS_INLINE M2 operator&(M2 x, M2 y) { return {x.a && y.a, x.b && y.b}; }
RAYPROOF_ALWAYS_INLINE M2 operator|(M2 x, M2 y) { return {x.a || y.a, x.b || y.b}; }
RAYPROOF_ALWAYS_INLINE int bits(M2 x) { return int(x.a) | (int(x.b) << 1); }
RAYPROOF_ALWAYS_INLINE double high26(double a) {
    return std::bit_cast<double>(std::bit_cast<std::uint64_t>(a) & ~std::uint64_t(0x7ffffff));
}
RAYPROOF_ALWAYS_INLINE D2 high26(D2 x) { return {high26(x.a), high26(x.b)}; }
RAYPROOF_ALWAYS_INLINE D2 keep(M2 m, D2 x) { return {m.a ? x.a : 0.0, m.b ? x.b : 0.0}; }

#endif

}  // namespace rayproof::detail::lanes
