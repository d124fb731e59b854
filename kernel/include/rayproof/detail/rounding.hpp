// rayproof/detail/rounding.hpp — the rounding primitives every error bound of the kernel
// is written in: the unit roundoff u, gamma(n), stepping to the adjacent float, and the
// search over the ordered floats, and narrow, the one conversion to a narrower type.
//
// u is the unit roundoff of T (half an ulp of 1): 2^-24 for float, 2^-53 for double.
// gamma(n) = n·u / (1 − n·u) bounds the relative error of n successive correctly
// rounded operations whose results neither overflow nor leave the normal range
// (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed., Lemma 3.1;
// pbrt-v4 section 6.8.1 uses the same notation).
#pragma once

#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/fp_model.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace rayproof::detail {

template <class T> inline constexpr T unit_roundoff = std::numeric_limits<T>::epsilon() / 2;

// x converted to T (rounded to nearest): every conversion of the kernel to a narrower
// floating-point type goes through here (double to float; the test generators use it
// for integers too). g++ before 13 at -O2 can drop such a rounding when the result is
// widened again: its SLP vectorizer fuses the conversion and the widening and keeps the
// unrounded double (docs/compiler-bugs.md). An empty asm statement that takes the
// rounded value in a floating-point register and gives it back makes the rounded value
// an input the compiler cannot see through, so the conversion has to happen; it emits no
// instruction and changes no result. Other compilers and T = the source type get the
// plain conversion.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13
#define RAYPROOF_NARROW_BARRIER 1
#endif
template <class T, class X> [[nodiscard]] inline T narrow(X x) noexcept {
    T y = static_cast<T>(x);
#ifdef RAYPROOF_NARROW_BARRIER
    if constexpr (!std::is_same_v<T, X>) {
#if defined(__SSE__)
        __asm__("" : "+x"(y));
#elif defined(__aarch64__)
        __asm__("" : "+w"(y));
#else
        __asm__("" : "+m"(y));
#endif
    }
#endif
    return y;
}

// A value a straight-line path has proven to be the answer (ok), or not ok (the general
// path answers).
template <class T> struct Pinned {
    T t;
    bool ok;
};

// gamma(n) = n·u/(1 − n·u) (Higham, ASNA, Lemma 3.1).
template <class T> constexpr T gamma(int n) {
    return (T(n) * unit_roundoff<T>) / (T(1) - T(n) * unit_roundoff<T>);
}

// The unsigned integer type of T's bits.
template <class T> using FloatBits = std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>;

// first ? a : b for floats, without a branch. Where the outcome is a coin toss (the sign
// of a random direction, hit or miss), a ternary that the compiler turns into a jump
// is mispredicted half the time.
template <class T> RAYPROOF_ALWAYS_INLINE T pick(bool first, T a, T b) {
    using U = FloatBits<T>;
    const U m = U(0) - U(first);
    return std::bit_cast<T>(U((std::bit_cast<U>(a) & m) | (std::bit_cast<U>(b) & ~m)));
}

// first ? a : b for ints, without a branch (as pick; the slab loops' face update, written
// as a ternary or as face += later·(...), became such a jump).
RAYPROOF_ALWAYS_INLINE int pick_int(bool first, int a, int b) {
    const int m = -int(first);
    return (a & m) | (b & ~m);
}

// The next representable value above / below x, by bit manipulation (no errno, inline).
// step_up(+inf) is +inf and step_down(-inf) is -inf; step_up(±0) is the smallest
// positive subnormal, step_down(±0) its negation.
template <class T> RAYPROOF_ALWAYS_INLINE T step_up(T x) {
    static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>);
    if (std::isinf(x) && x > 0) return x;
    if (x == 0) return std::numeric_limits<T>::denorm_min();
    FloatBits<T> b = std::bit_cast<FloatBits<T>>(x);
    b = x > 0 ? b + 1 : b - 1;
    return std::bit_cast<T>(b);
}
template <class T> RAYPROOF_ALWAYS_INLINE T step_down(T x) {
    static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>);
    if (std::isinf(x) && x < 0) return x;
    if (x == 0) return -std::numeric_limits<T>::denorm_min();
    FloatBits<T> b = std::bit_cast<FloatBits<T>>(x);
    b = x > 0 ? b - 1 : b + 1;
    return std::bit_cast<T>(b);
}

// Floats as ordered integers (-0 and +0 share key 0), for searching over the floats.
template <class T> std::int64_t float_key(T x) {
    if constexpr (std::is_same_v<T, double>) {
        const std::int64_t b = std::bit_cast<std::int64_t>(x);
        return b < 0 ? -(b & INT64_MAX) : b;
    } else {
        const std::int32_t b = std::bit_cast<std::int32_t>(x);
        return b < 0 ? -std::int64_t(b & INT32_MAX) : std::int64_t(b);
    }
}
template <class T> T key_float(std::int64_t k) {
    if constexpr (std::is_same_v<T, double>) {
        return k < 0 ? -std::bit_cast<double>(-k) : std::bit_cast<double>(k);
    } else {
        return k < 0 ? -std::bit_cast<float>(std::int32_t(-k)) : std::bit_cast<float>(std::int32_t(k));
    }
}

// The least key in (lo, hi] where a monotone predicate (false ... false true ... true)
// turns true, given pred(lo) false and pred(hi) true, starting the search near `guess`.
// Key differences are taken in unsigned arithmetic: hi - lo can exceed INT64_MAX.
template <class P> std::int64_t first_true(std::int64_t lo, std::int64_t hi, std::int64_t guess, P&& pred) {
    if (guess > lo && guess < hi) {  // gallop outwards from the guess, then bisect
        if (pred(guess)) {
            hi = guess;
            for (std::int64_t step = 1; step < (std::int64_t(1) << 62) && std::uint64_t(step) < std::uint64_t(hi) - std::uint64_t(lo);
                 step *= 2) {
                if (!pred(hi - step)) {
                    lo = hi - step;
                    break;
                }
                hi -= step;
            }
        } else {
            lo = guess;
            for (std::int64_t step = 1; step < (std::int64_t(1) << 62) && std::uint64_t(step) < std::uint64_t(hi) - std::uint64_t(lo);
                 step *= 2) {
                if (pred(lo + step)) {
                    hi = lo + step;
                    break;
                }
                lo += step;
            }
        }
    }
    // hi - lo may exceed INT64_MAX (keys of opposite signs): differences in unsigned.
    while (std::uint64_t(hi) - std::uint64_t(lo) > 1) {
        const std::int64_t m = lo + std::int64_t((std::uint64_t(hi) - std::uint64_t(lo)) / 2);
        if (pred(m))
            hi = m;
        else
            lo = m;
    }
    return hi;
}

}  // namespace rayproof::detail
