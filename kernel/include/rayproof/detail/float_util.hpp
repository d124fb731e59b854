// rayproof/detail/float_util.hpp — the compiler hints of the hot paths, infinity and a
// finiteness test. The rounding primitives (u, gamma(n), stepping) live in
// detail/rounding.hpp.
#pragma once

#include <rayproof/detail/fp_model.hpp>

#include <cmath>
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

template <class T> inline constexpr T inf = std::numeric_limits<T>::infinity();

template <class T> inline bool finite3(const T* v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

}  // namespace rayproof::detail
