// rayproof/detail/float_util.hpp — rounding-error constants and float stepping.
//
// u is the unit roundoff of T (half an ulp of 1): 2^-24 for float, 2^-53 for double.
// gamma(n) = n·u / (1 − n·u) bounds the relative error of n successive correctly
// rounded operations whose results neither overflow nor leave the normal range
// (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed., Lemma 3.1;
// pbrt-v4 section 6.8.1 uses the same notation).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

// Inlining and unrolling hints for the few hot straight-line routines whose speed is
// measured in bench/ (they change no result).
#if defined(__GNUC__) || defined(__clang__)
#define RAYPROOF_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define RAYPROOF_ALWAYS_INLINE inline
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

namespace rayproof::detail {

template <class T> inline constexpr T unit_roundoff = std::numeric_limits<T>::epsilon() / 2;

template <class T> constexpr T gamma(int n) {
    return (T(n) * unit_roundoff<T>) / (T(1) - T(n) * unit_roundoff<T>);
}

template <class T> inline constexpr T inf = std::numeric_limits<T>::infinity();

// The next representable value towards +inf / -inf (nextafter without errno traffic).
template <class T> inline T next_up(T x) { return std::nextafter(x, inf<T>); }
template <class T> inline T next_down(T x) { return std::nextafter(x, -inf<T>); }

template <class T> inline bool finite3(const T* v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

}  // namespace rayproof::detail
