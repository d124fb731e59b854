// rayproof/detail/limbs.hpp — the two-limb arithmetic under BigDyadic (detail/exact.hpp):
// a 64×64-bit product plus two 64-bit addends as a 128-bit (hi, lo) pair, and an
// addition with carry.
//
// mul_add_add(a, b, c, d) = a·b + c + d exactly. It fits in 128 bits:
// (2^64 − 1)^2 + 2·(2^64 − 1) = 2^128 − 1.
//
// Two implementations give the same bits:
//   - unsigned __int128 where the compiler has it (64-bit g++ and clang: __SIZEOF_INT128__);
//   - a portable one on 32-bit halves (schoolbook): each partial product of two halves is
//     below 2^64, and the middle sum (p00 >> 32) + lo32(p01) + lo32(p10) is below 3·2^32.
// The portable one is used where __int128 is missing, or everywhere when
// RAYPROOF_PORTABLE_LIMBS is defined; the unit tests compare the two on edge and random
// limbs and run the exact-arithmetic suite with the portable one forced on.
#pragma once

#include <cstdint>

#if defined(__SIZEOF_INT128__) && !defined(RAYPROOF_PORTABLE_LIMBS)
#define RAYPROOF_INT128_LIMBS 1
#else
#define RAYPROOF_INT128_LIMBS 0
#endif

namespace rayproof::detail {

struct LimbPair {
    std::uint64_t lo = 0, hi = 0;
    friend constexpr bool operator==(const LimbPair&, const LimbPair&) = default;
};

[[nodiscard]] constexpr LimbPair mul_add_add_portable(std::uint64_t a, std::uint64_t b, std::uint64_t c,
                                                      std::uint64_t d) noexcept {
    constexpr std::uint64_t low32 = 0xffffffffu;
    const std::uint64_t a0 = a & low32, a1 = a >> 32, b0 = b & low32, b1 = b >> 32;
    const std::uint64_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
    const std::uint64_t mid = (p00 >> 32) + (p01 & low32) + (p10 & low32);  // < 3·2^32
    LimbPair r{(mid << 32) | (p00 & low32), p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32)};
    r.lo += c;
    r.hi += r.lo < c ? 1u : 0u;  // the total stays below 2^128, so hi never wraps
    r.lo += d;
    r.hi += r.lo < d ? 1u : 0u;
    return r;
}

#if defined(__SIZEOF_INT128__)
[[nodiscard]] inline LimbPair mul_add_add_int128(std::uint64_t a, std::uint64_t b, std::uint64_t c,
                                                 std::uint64_t d) noexcept {
    __extension__ typedef unsigned __int128 u128;
    const u128 t = u128(a) * b + c + d;
    return {static_cast<std::uint64_t>(t), static_cast<std::uint64_t>(t >> 64)};
}
#endif

[[nodiscard]] inline LimbPair mul_add_add(std::uint64_t a, std::uint64_t b, std::uint64_t c,
                                          std::uint64_t d) noexcept {
#if RAYPROOF_INT128_LIMBS
    return mul_add_add_int128(a, b, c, d);
#else
    return mul_add_add_portable(a, b, c, d);
#endif
}

// a + b + carry (carry 0 or 1) = lo + 2^64·hi, hi 0 or 1. Plain 64-bit arithmetic on
// every target (compilers emit add-with-carry for it).
[[nodiscard]] constexpr LimbPair add_carry(std::uint64_t a, std::uint64_t b, std::uint64_t carry) noexcept {
    const std::uint64_t s = a + b;
    const std::uint64_t t = s + carry;
    return {t, (s < a ? 1u : 0u) + (t < s ? 1u : 0u)};
}

}  // namespace rayproof::detail
