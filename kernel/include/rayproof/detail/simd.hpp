// rayproof/detail/simd.hpp — a small fixed-width vector of W floats or doubles for the
// box packets (ray_aabb_packet.hpp) and the certified batches (ray_aabb_batch.hpp,
// ray_plane_batch.hpp), in two backends with one interface:
//   portable — plain arrays, one scalar operation per lane; always compiled;
//   native   — SSE2 registers (double×2, float×4) on x86-64, AVX2 registers (double×4,
//              float×8) where the compiler targets AVX2 (__AVX2__); a vector of W lanes
//              is W / L registers of L lanes. Elsewhere native is the portable backend.
// Both can be instantiated in one translation unit (Vec<T, W, portable> next to
// Vec<T, W, native>), so a test compares them directly; the packets use the native one.
//
// Each operation is the correctly rounded IEEE operation in each lane, so both backends
// compute the same bits from the same operands. min and max follow the SSE rule in both:
// min(a, b) = a < b ? a : b, max(a, b) = a > b ? a : b (a NaN in either operand gives
// b, and of two zeros b); division is the correctly rounded one too, negation (unary -)
// flips the sign bit exactly, and high26 cuts a double's significand to its leading 26
// bits (lanes::high26). Comparisons are ordered (false on a NaN) and give a Mask, whose
// bits() has bit i for lane i. rounded(v) is the barrier against contraction of
// detail/eft.hpp (class C3) for a whole vector: an empty asm statement on each register.
// Contraction: a compiler may fuse a product into a later sum in either backend (g++
// implements the intrinsics as vector operators); the packet code says at each product
// whether that matters, as the scalar kernel does.
#pragma once

#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/float_util.hpp>

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#if defined(__SSE2__) && (defined(__x86_64__) || defined(__i386__) || defined(_M_X64))
#include <emmintrin.h>
#define RAYPROOF_SIMD_SSE2 1
#endif
#if defined(RAYPROOF_SIMD_SSE2) && defined(__AVX2__)
#include <immintrin.h>
#define RAYPROOF_SIMD_AVX2 1
#endif

namespace rayproof::detail::simd {

struct portable {};
struct native {};

// One register of L lanes of T: the scalar chunk (L = 1, a plain T) of the portable
// backend, and the native registers.
template <class T, int L> struct Chunk;

template <class T> struct Chunk<T, 1> {
    using reg = T;
    using mreg = bool;
    static constexpr int lanes = 1;
    static reg load(const T* p) { return *p; }
    static reg load_widen(const float* p) { return T(*p); }
    static void store(T* p, reg a) { *p = a; }
    static void store_widened(double* p, reg a) { *p = double(a); }
    static reg splat(T x) { return x; }
    static reg add(reg a, reg b) { return a + b; }
    static reg sub(reg a, reg b) { return a - b; }
    static reg mul(reg a, reg b) { return a * b; }
    static reg div(reg a, reg b) { return a / b; }
    static reg neg(reg a) { return -a; }
    static reg high26(reg a) {
        if constexpr (std::is_same_v<T, double>)
            return std::bit_cast<double>(std::bit_cast<std::uint64_t>(a) & ~std::uint64_t(0x7ffffff));
        else
            return a;
    }
    static reg min(reg a, reg b) { return a < b ? a : b; }
    static reg max(reg a, reg b) { return a > b ? a : b; }
    static reg abs(reg a) { return std::fabs(a); }
    static reg rounded(reg a) { return rounded_scalar(a); }
    static mreg lt(reg a, reg b) { return a < b; }
    static mreg le(reg a, reg b) { return a <= b; }
    static mreg eq(reg a, reg b) { return a == b; }
    static mreg mand(mreg a, mreg b) { return a & b; }
    static mreg mor(mreg a, mreg b) { return a | b; }
    static mreg mandnot(mreg a, mreg b) { return a & !b; }  // a and not b
    static mreg mtrue() { return true; }
    static reg select(mreg m, reg a, reg b) { return m ? a : b; }
    static unsigned bits(mreg m) { return unsigned(m); }
};

#if defined(RAYPROOF_SIMD_SSE2)
template <> struct Chunk<double, 2> {
    using reg = __m128d;
    using mreg = __m128d;
    static constexpr int lanes = 2;
    static reg load(const double* p) { return _mm_loadu_pd(p); }
    static reg load_widen(const float* p) {
        return _mm_cvtps_pd(_mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(p))));
    }
    static void store(double* p, reg a) { _mm_storeu_pd(p, a); }
    static reg splat(double x) { return _mm_set1_pd(x); }
    static reg add(reg a, reg b) { return _mm_add_pd(a, b); }
    static reg sub(reg a, reg b) { return _mm_sub_pd(a, b); }
    static reg mul(reg a, reg b) { return _mm_mul_pd(a, b); }
    static reg div(reg a, reg b) { return _mm_div_pd(a, b); }
    static reg neg(reg a) { return _mm_xor_pd(a, _mm_set1_pd(-0.0)); }
    static reg high26(reg a) { return _mm_and_pd(a, _mm_castsi128_pd(_mm_set1_epi64x(~std::int64_t(0x7ffffff)))); }
    static reg min(reg a, reg b) { return _mm_min_pd(a, b); }
    static reg max(reg a, reg b) { return _mm_max_pd(a, b); }
    static reg abs(reg a) { return _mm_andnot_pd(_mm_set1_pd(-0.0), a); }
    static reg rounded(reg a) {
#if defined(__GNUC__) || defined(__clang__)
        __asm__("" : "+x"(a));
#endif
        return a;
    }
    static mreg lt(reg a, reg b) { return _mm_cmplt_pd(a, b); }
    static mreg le(reg a, reg b) { return _mm_cmple_pd(a, b); }
    static mreg eq(reg a, reg b) { return _mm_cmpeq_pd(a, b); }
    static mreg mand(mreg a, mreg b) { return _mm_and_pd(a, b); }
    static mreg mor(mreg a, mreg b) { return _mm_or_pd(a, b); }
    static mreg mandnot(mreg a, mreg b) { return _mm_andnot_pd(b, a); }
    static mreg mtrue() { return _mm_castsi128_pd(_mm_set1_epi32(-1)); }
    static reg select(mreg m, reg a, reg b) { return _mm_or_pd(_mm_and_pd(m, a), _mm_andnot_pd(m, b)); }
    static unsigned bits(mreg m) { return unsigned(_mm_movemask_pd(m)); }
};
template <> struct Chunk<float, 4> {
    using reg = __m128;
    using mreg = __m128;
    static constexpr int lanes = 4;
    static reg load(const float* p) { return _mm_loadu_ps(p); }
    static void store(float* p, reg a) { _mm_storeu_ps(p, a); }
    static void store_widened(double* p, reg a) {
        _mm_storeu_pd(p, _mm_cvtps_pd(a));
        _mm_storeu_pd(p + 2, _mm_cvtps_pd(_mm_movehl_ps(a, a)));
    }
    static reg splat(float x) { return _mm_set1_ps(x); }
    static reg add(reg a, reg b) { return _mm_add_ps(a, b); }
    static reg sub(reg a, reg b) { return _mm_sub_ps(a, b); }
    static reg mul(reg a, reg b) { return _mm_mul_ps(a, b); }
    static reg div(reg a, reg b) { return _mm_div_ps(a, b); }
    static reg neg(reg a) { return _mm_xor_ps(a, _mm_set1_ps(-0.0f)); }
    static reg min(reg a, reg b) { return _mm_min_ps(a, b); }
    static reg max(reg a, reg b) { return _mm_max_ps(a, b); }
    static reg abs(reg a) { return _mm_andnot_ps(_mm_set1_ps(-0.0f), a); }
    static reg rounded(reg a) {
#if defined(__GNUC__) || defined(__clang__)
        __asm__("" : "+x"(a));
#endif
        return a;
    }
    static mreg lt(reg a, reg b) { return _mm_cmplt_ps(a, b); }
    static mreg le(reg a, reg b) { return _mm_cmple_ps(a, b); }
    static mreg eq(reg a, reg b) { return _mm_cmpeq_ps(a, b); }
    static mreg mand(mreg a, mreg b) { return _mm_and_ps(a, b); }
    static mreg mor(mreg a, mreg b) { return _mm_or_ps(a, b); }
    static mreg mandnot(mreg a, mreg b) { return _mm_andnot_ps(b, a); }
    static mreg mtrue() { return _mm_castsi128_ps(_mm_set1_epi32(-1)); }
    static reg select(mreg m, reg a, reg b) { return _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b)); }
    static unsigned bits(mreg m) { return unsigned(_mm_movemask_ps(m)); }
};
#endif

#if defined(RAYPROOF_SIMD_AVX2)
template <> struct Chunk<double, 4> {
    using reg = __m256d;
    using mreg = __m256d;
    static constexpr int lanes = 4;
    static reg load(const double* p) { return _mm256_loadu_pd(p); }
    static reg load_widen(const float* p) { return _mm256_cvtps_pd(_mm_loadu_ps(p)); }
    static void store(double* p, reg a) { _mm256_storeu_pd(p, a); }
    static reg splat(double x) { return _mm256_set1_pd(x); }
    static reg add(reg a, reg b) { return _mm256_add_pd(a, b); }
    static reg sub(reg a, reg b) { return _mm256_sub_pd(a, b); }
    static reg mul(reg a, reg b) { return _mm256_mul_pd(a, b); }
    static reg div(reg a, reg b) { return _mm256_div_pd(a, b); }
    static reg neg(reg a) { return _mm256_xor_pd(a, _mm256_set1_pd(-0.0)); }
    static reg high26(reg a) {
        return _mm256_and_pd(a, _mm256_castsi256_pd(_mm256_set1_epi64x(~std::int64_t(0x7ffffff))));
    }
    static reg min(reg a, reg b) { return _mm256_min_pd(a, b); }
    static reg max(reg a, reg b) { return _mm256_max_pd(a, b); }
    static reg abs(reg a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }
    static reg rounded(reg a) {
        __asm__("" : "+x"(a));
        return a;
    }
    static mreg lt(reg a, reg b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
    static mreg le(reg a, reg b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
    static mreg eq(reg a, reg b) { return _mm256_cmp_pd(a, b, _CMP_EQ_OQ); }
    static mreg mand(mreg a, mreg b) { return _mm256_and_pd(a, b); }
    static mreg mor(mreg a, mreg b) { return _mm256_or_pd(a, b); }
    static mreg mandnot(mreg a, mreg b) { return _mm256_andnot_pd(b, a); }
    static mreg mtrue() { return _mm256_castsi256_pd(_mm256_set1_epi32(-1)); }
    static reg select(mreg m, reg a, reg b) { return _mm256_blendv_pd(b, a, m); }
    static unsigned bits(mreg m) { return unsigned(_mm256_movemask_pd(m)); }
};
template <> struct Chunk<float, 8> {
    using reg = __m256;
    using mreg = __m256;
    static constexpr int lanes = 8;
    static reg load(const float* p) { return _mm256_loadu_ps(p); }
    static void store(float* p, reg a) { _mm256_storeu_ps(p, a); }
    static void store_widened(double* p, reg a) {
        _mm256_storeu_pd(p, _mm256_cvtps_pd(_mm256_castps256_ps128(a)));
        _mm256_storeu_pd(p + 4, _mm256_cvtps_pd(_mm256_extractf128_ps(a, 1)));
    }
    static reg splat(float x) { return _mm256_set1_ps(x); }
    static reg add(reg a, reg b) { return _mm256_add_ps(a, b); }
    static reg sub(reg a, reg b) { return _mm256_sub_ps(a, b); }
    static reg mul(reg a, reg b) { return _mm256_mul_ps(a, b); }
    static reg div(reg a, reg b) { return _mm256_div_ps(a, b); }
    static reg neg(reg a) { return _mm256_xor_ps(a, _mm256_set1_ps(-0.0f)); }
    static reg min(reg a, reg b) { return _mm256_min_ps(a, b); }
    static reg max(reg a, reg b) { return _mm256_max_ps(a, b); }
    static reg abs(reg a) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), a); }
    static reg rounded(reg a) {
        __asm__("" : "+x"(a));
        return a;
    }
    static mreg lt(reg a, reg b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
    static mreg le(reg a, reg b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
    static mreg eq(reg a, reg b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
    static mreg mand(mreg a, mreg b) { return _mm256_and_ps(a, b); }
    static mreg mor(mreg a, mreg b) { return _mm256_or_ps(a, b); }
    static mreg mandnot(mreg a, mreg b) { return _mm256_andnot_ps(b, a); }
    static mreg mtrue() { return _mm256_castsi256_ps(_mm256_set1_epi32(-1)); }
    static reg select(mreg m, reg a, reg b) { return _mm256_blendv_ps(b, a, m); }
    static unsigned bits(mreg m) { return unsigned(_mm256_movemask_ps(m)); }
};
#endif

// The lanes per register of the native backend for W lanes of T: the widest register
// compiled in that W fills.
template <class T, int W> constexpr int native_lanes() {
#if defined(RAYPROOF_SIMD_AVX2)
    if constexpr (std::is_same_v<T, float>) return W >= 8 ? 8 : 4;
    else return W >= 4 ? 4 : 2;
#elif defined(RAYPROOF_SIMD_SSE2)
    if constexpr (std::is_same_v<T, float>) return 4;
    else return 2;
#else
    return 1;
#endif
}
template <class T, int W, class B> constexpr int chunk_lanes() {
    if constexpr (std::is_same_v<B, portable>) return 1;
    else return native_lanes<T, W>();
}

// The name of the backend that runs native vectors, for the tests and the bench.
constexpr const char* native_name() {
#if defined(RAYPROOF_SIMD_AVX2)
    return "avx2";
#elif defined(RAYPROOF_SIMD_SSE2)
    return "sse2";
#else
    return "portable";
#endif
}

template <class T, int W, class B> struct Mask;

// W lanes of T in backend B: W / L registers of L lanes.
template <class T, int W, class B> struct Vec {
    using C = Chunk<T, chunk_lanes<T, W, B>()>;
    static constexpr int n = W / C::lanes;
    static_assert(W % C::lanes == 0);
    typename C::reg r[std::size_t(n)];

    static RAYPROOF_ALWAYS_INLINE Vec load(const T* p) {
        Vec v;
        for (int k = 0; k < n; ++k) v.r[k] = C::load(p + k * C::lanes);
        return v;
    }
    // Floats widened to doubles (exactly): only for T = double.
    static RAYPROOF_ALWAYS_INLINE Vec load(const float* p)
        requires std::is_same_v<T, double>
    {
        Vec v;
        for (int k = 0; k < n; ++k) v.r[k] = C::load_widen(p + k * C::lanes);
        return v;
    }
    static RAYPROOF_ALWAYS_INLINE Vec splat(T x) {
        Vec v;
        for (int k = 0; k < n; ++k) v.r[k] = C::splat(x);
        return v;
    }
    RAYPROOF_ALWAYS_INLINE void store(T* p) const {
        for (int k = 0; k < n; ++k) C::store(p + k * C::lanes, r[k]);
    }
    // Every lane widened to double (exactly) and stored: p[i] = double(lane i).
    RAYPROOF_ALWAYS_INLINE void store_widened(double* p) const {
        if constexpr (std::is_same_v<T, double>)
            store(p);
        else
            for (int k = 0; k < n; ++k) C::store_widened(p + k * C::lanes, r[k]);
    }
};

template <class T, int W, class B> struct Mask {
    using C = typename Vec<T, W, B>::C;
    static constexpr int n = Vec<T, W, B>::n;
    typename C::mreg r[std::size_t(n)];

    static RAYPROOF_ALWAYS_INLINE Mask all() {
        Mask m;
        for (int k = 0; k < n; ++k) m.r[k] = C::mtrue();
        return m;
    }
    // Bit i set when lane i is true.
    RAYPROOF_ALWAYS_INLINE std::uint32_t bits() const {
        std::uint32_t b = 0;
        for (int k = 0; k < n; ++k) b |= std::uint32_t(C::bits(r[k])) << (k * C::lanes);
        return b;
    }
};

#define RAYPROOF_SIMD_BINARY(NAME, RET, OP)                                                       \
    template <class T, int W, class B>                                                            \
    RAYPROOF_ALWAYS_INLINE RET<T, W, B> NAME(const Vec<T, W, B>& a, const Vec<T, W, B>& b) {      \
        using C = typename Vec<T, W, B>::C;                                                       \
        RET<T, W, B> v;                                                                           \
        for (int k = 0; k < Vec<T, W, B>::n; ++k) v.r[k] = C::OP(a.r[k], b.r[k]);                 \
        return v;                                                                                 \
    }
RAYPROOF_SIMD_BINARY(operator+, Vec, add)
RAYPROOF_SIMD_BINARY(operator-, Vec, sub)
RAYPROOF_SIMD_BINARY(operator*, Vec, mul)
RAYPROOF_SIMD_BINARY(operator/, Vec, div)
RAYPROOF_SIMD_BINARY(min, Vec, min)
RAYPROOF_SIMD_BINARY(max, Vec, max)
RAYPROOF_SIMD_BINARY(operator<, Mask, lt)
RAYPROOF_SIMD_BINARY(operator<=, Mask, le)
RAYPROOF_SIMD_BINARY(operator==, Mask, eq)
#undef RAYPROOF_SIMD_BINARY

template <class T, int W, class B> RAYPROOF_ALWAYS_INLINE Mask<T, W, B> operator>(const Vec<T, W, B>& a, const Vec<T, W, B>& b) {
    return b < a;
}

#define RAYPROOF_SIMD_MASK(NAME, OP)                                                              \
    template <class T, int W, class B>                                                            \
    RAYPROOF_ALWAYS_INLINE Mask<T, W, B> NAME(const Mask<T, W, B>& a, const Mask<T, W, B>& b) {   \
        using C = typename Mask<T, W, B>::C;                                                      \
        Mask<T, W, B> v;                                                                          \
        for (int k = 0; k < Mask<T, W, B>::n; ++k) v.r[k] = C::OP(a.r[k], b.r[k]);                \
        return v;                                                                                 \
    }
RAYPROOF_SIMD_MASK(operator&, mand)
RAYPROOF_SIMD_MASK(operator|, mor)
RAYPROOF_SIMD_MASK(and_not, mandnot)  // a and not b
#undef RAYPROOF_SIMD_MASK

template <class T, int W, class B> RAYPROOF_ALWAYS_INLINE Vec<T, W, B> abs(const Vec<T, W, B>& a) {
    using C = typename Vec<T, W, B>::C;
    Vec<T, W, B> v;
    for (int k = 0; k < Vec<T, W, B>::n; ++k) v.r[k] = C::abs(a.r[k]);
    return v;
}
// Negation (exact: the sign bit flipped, zeros and NaNs included).
template <class T, int W, class B> RAYPROOF_ALWAYS_INLINE Vec<T, W, B> operator-(const Vec<T, W, B>& a) {
    using C = typename Vec<T, W, B>::C;
    Vec<T, W, B> v;
    for (int k = 0; k < Vec<T, W, B>::n; ++k) v.r[k] = C::neg(a.r[k]);
    return v;
}
// The significand cut to its leading 26 bits (lanes::high26, for doubles), per lane.
template <int W, class B> RAYPROOF_ALWAYS_INLINE Vec<double, W, B> high26(const Vec<double, W, B>& a) {
    using C = typename Vec<double, W, B>::C;
    Vec<double, W, B> v;
    for (int k = 0; k < Vec<double, W, B>::n; ++k) v.r[k] = C::high26(a.r[k]);
    return v;
}
template <class T, int W, class B> RAYPROOF_ALWAYS_INLINE Vec<T, W, B> rounded(const Vec<T, W, B>& a) {
    using C = typename Vec<T, W, B>::C;
    Vec<T, W, B> v;
    for (int k = 0; k < Vec<T, W, B>::n; ++k) v.r[k] = C::rounded(a.r[k]);
    return v;
}
// a where m, else b.
template <class T, int W, class B>
RAYPROOF_ALWAYS_INLINE Vec<T, W, B> select(const Mask<T, W, B>& m, const Vec<T, W, B>& a, const Vec<T, W, B>& b) {
    using C = typename Vec<T, W, B>::C;
    Vec<T, W, B> v;
    for (int k = 0; k < Vec<T, W, B>::n; ++k) v.r[k] = C::select(m.r[k], a.r[k], b.r[k]);
    return v;
}

}  // namespace rayproof::detail::simd
