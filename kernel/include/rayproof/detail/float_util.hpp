// rayproof/detail/float_util.hpp — the compiler hints of the hot paths, infinity, a
// finiteness test, and a double's binary exponent and exact scaling by powers of two
// from its bits (no library call). The rounding primitives (u, gamma(n), stepping) live in
// detail/rounding.hpp.
#pragma once

#include <rayproof/detail/fp_model.hpp>

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

// Inlining and unrolling hints for the few hot straight-line routines whose speed is
// measured in bench/ (they change no result).
#if defined(__GNUC__) || defined(__clang__)
#define RAYPROOF_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define RAYPROOF_ALWAYS_INLINE inline
#endif
// A lambda forced inline likewise (placed after its parameter list): a query's helper
// lambdas, and the lambda handed to in_default_fp_env_inline (detail/fp_env.hpp), so
// that the guarded query is the same inline code as the plain one.
#if defined(__GNUC__) || defined(__clang__)
#define RAYPROOF_INLINE_LAMBDA __attribute__((always_inline))
#else
#define RAYPROOF_INLINE_LAMBDA
#endif
// A loop over the three axes unrolled in full (g++ -O2 keeps it rolled, with its
// arrays in memory).
#if defined(__clang__)
#define RAYPROOF_UNROLL3 _Pragma("clang loop unroll(full)")
#elif defined(__GNUC__)
#define RAYPROOF_UNROLL3 _Pragma("GCC unroll 3")
#else
#define RAYPROOF_UNROLL3
#endif
// A loop over the W lanes of a batch block (W <= 8) unrolled in full: rolled, g++ -O2
// keeps the block's lane values in memory (the certified lane batches took 1.3-2× the
// scalar loop's time at -O2 against 0.65-0.85× unrolled).
#if defined(__clang__)
#define RAYPROOF_UNROLL_LANES _Pragma("clang loop unroll(full)")
#elif defined(__GNUC__)
#define RAYPROOF_UNROLL_LANES _Pragma("GCC unroll 8")
#else
#define RAYPROOF_UNROLL_LANES
#endif

namespace rayproof::detail {

// A hint to load the cache lines of [p, p + bytes) (no effect on any answer): the BVH's
// next nodes and leaves, and a batch's rays some way ahead of the one answered.
RAYPROOF_ALWAYS_INLINE void prefetch([[maybe_unused]] const void* p, [[maybe_unused]] std::size_t bytes) noexcept {
#if defined(__GNUC__) || defined(__clang__)
    const char* c = static_cast<const char*>(p);
    for (std::size_t k = 0; k < bytes; k += 64) __builtin_prefetch(c + k);
    __builtin_prefetch(c + bytes - 1);
#endif
}

template <class T> inline constexpr T inf = std::numeric_limits<T>::infinity();

template <class T> inline bool finite3(const T* v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

// ilogb(x) for a finite nonzero double x, subnormals included (their true exponent,
// down to -1074).
inline int binary_exponent(double x) noexcept {
    const auto b = std::bit_cast<std::uint64_t>(x);
    const int e = int((b >> 52) & 0x7ff);
    if (e != 0) return e - 1023;
    return (63 - std::countl_zero(b & ((std::uint64_t(1) << 52) - 1))) - 1074;
}

// x = m·2^e exactly, |m| in [1, 2) with x's sign, for a finite nonzero double x
// (subnormals included: first scaled by 2^52, exactly): m is x's bits with the exponent
// field set to that of 1.
struct SplitDouble {
    double m;
    int e;
};
inline SplitDouble split_exponent(double x) noexcept {
    constexpr std::uint64_t field = std::uint64_t(0x7ff) << 52;
    int shift = 0;
    if ((std::bit_cast<std::uint64_t>(x) & field) == 0) {
        x *= 0x1p52;
        shift = 52;
    }
    const auto b = std::bit_cast<std::uint64_t>(x);
    return {std::bit_cast<double>((b & ~field) | (std::uint64_t(1023) << 52)), int((b & field) >> 52) - 1023 - shift};
}

// The exponent k of the last nonzero bit of a finite nonzero double x (x = m·2^k, m an
// odd integer), subnormals included: every multiple of x is a multiple of 2^k.
inline int last_bit_exponent(double x) noexcept {
    const auto b = std::bit_cast<std::uint64_t>(x) & ~(std::uint64_t(1) << 63);
    const int e = int(b >> 52);
    const std::uint64_t m = b & ((std::uint64_t(1) << 52) - 1);
    if (e == 0) return std::countr_zero(m) - 1074;
    return std::countr_zero(m | (std::uint64_t(1) << 52)) + e - 1075;
}

// 2^j for -1022 <= j <= 1023, from its bits.
inline double pow2(int j) noexcept { return std::bit_cast<double>(std::uint64_t(j + 1023) << 52); }

// x·2^k for -2044 <= k <= 2046, as two products by normal powers of two: exact where the
// result is a normal double (or 0). For k >= 0 the intermediate lies between x and the
// result in magnitude (no underflow, no overflow before the result's); for k < 0 it
// lies between the result and x (no underflow before the result's).
inline double times_pow2(double x, int k) noexcept {
    const int h = k / 2;
    return (x * pow2(h)) * pow2(k - h);
}

}  // namespace rayproof::detail
