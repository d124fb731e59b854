// limbs_test: the two-limb arithmetic under BigDyadic (rayproof/detail/limbs.hpp). The
// portable product on 32-bit halves must give the bits of the unsigned __int128 one on
// edge limbs (0, 1, 2^32 ± 1, 2^63, 2^64 − 1, ...) in every combination, and on seeded
// random limbs; add_carry must give the sum with its carry. The exact-arithmetic suite
// itself also runs with the portable product forced on (exact_test_portable_limbs).
#include <rayproof/detail/limbs.hpp>

#include "seeded.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <random>

namespace {

using rayproof::detail::add_carry;
using rayproof::detail::LimbPair;
using rayproof::detail::mul_add_add;
using rayproof::detail::mul_add_add_portable;

constexpr std::uint64_t max64 = ~std::uint64_t(0);

// The largest case fills all 128 bits: (2^64 − 1)^2 + 2·(2^64 − 1) = 2^128 − 1.
static_assert(mul_add_add_portable(max64, max64, max64, max64) == LimbPair{max64, max64});
static_assert(mul_add_add_portable(0, 0, 0, 0) == LimbPair{0, 0});
static_assert(mul_add_add_portable(std::uint64_t(1) << 32, std::uint64_t(1) << 32, 0, 0) == LimbPair{0, 1});
static_assert(mul_add_add_portable(max64, 2, 0, 0) == LimbPair{max64 - 1, 1});
static_assert(add_carry(max64, 1, 0) == LimbPair{0, 1});
static_assert(add_carry(max64, max64, 1) == LimbPair{max64, 1});

const std::array<std::uint64_t, 12> edges{0,
                                          1,
                                          2,
                                          0xffffffffu,
                                          std::uint64_t(1) << 32,
                                          (std::uint64_t(1) << 32) + 1,
                                          0x8000000000000000u,
                                          0x7fffffffffffffffu,
                                          0xffffffff00000000u,
                                          0x00000000ffffffffu | 0x8000000000000000u,
                                          max64 - 1,
                                          max64};

#if defined(__SIZEOF_INT128__)
using rayproof::detail::mul_add_add_int128;

TEST(Limbs, PortableProductEqualsInt128OnEdgeLimbs) {
    for (std::uint64_t a : edges)
        for (std::uint64_t b : edges)
            for (std::uint64_t c : edges)
                for (std::uint64_t d : edges)
                    ASSERT_EQ(mul_add_add_portable(a, b, c, d), mul_add_add_int128(a, b, c, d))
                        << std::hex << a << " * " << b << " + " << c << " + " << d;
}

TEST(Limbs, PortableProductEqualsInt128OnRandomLimbs) {
    const std::uint64_t seed = rayproof::testing::env_seed_or(20261202);
    RAYPROOF_SEED_TRACE(seed);
    std::mt19937_64 rng = rayproof::testing::rng_for_current_test(seed);
    for (int i = 0; i < 1000000; ++i) {
        // Mix full-width limbs with short ones and edge values, which carry differently.
        auto draw = [&] {
            switch (rng() % 4) {
                case 0: return edges[rng() % edges.size()];
                case 1: return rng() >> (rng() % 64);
                default: return rng();
            }
        };
        const std::uint64_t a = draw(), b = draw(), c = draw(), d = draw();
        ASSERT_EQ(mul_add_add_portable(a, b, c, d), mul_add_add_int128(a, b, c, d))
            << std::hex << a << " * " << b << " + " << c << " + " << d;
    }
}
#endif

TEST(Limbs, TheSelectedProductIsThePortableOneOrInt128) {
    // Whichever the build selects, it answers as the portable reference.
    for (std::uint64_t a : edges)
        for (std::uint64_t b : edges)
            EXPECT_EQ(mul_add_add(a, b, a, b), mul_add_add_portable(a, b, a, b));
}

TEST(Limbs, AddCarryIsTheSumWithItsCarry) {
    for (std::uint64_t a : edges)
        for (std::uint64_t b : edges)
            for (std::uint64_t carry : {0u, 1u}) {
                const LimbPair s = add_carry(a, b, carry);
                // Check against the sum split into halves, which cannot overflow.
                const std::uint64_t low = (a & 0xffffffffu) + (b & 0xffffffffu) + carry;
                const std::uint64_t high = (a >> 32) + (b >> 32) + (low >> 32);
                EXPECT_EQ(s.lo, (high << 32) | (low & 0xffffffffu));
                EXPECT_EQ(s.hi, high >> 32);
            }
}

}  // namespace
