// Seeded randomness for the unit suites checked against GMP (exact_test,
// compensated_test). Each suite has a default base seed; RAYPROOF_SEED=<decimal> in the
// environment replaces it, to replay a failure. Every test draws from a generator of its
// own, derived from the base seed and the test's full name, so adding or reordering tests
// does not change another test's cases. A suite defines, with its default seed,
//     std::uint64_t base_seed() { static const std::uint64_t s = env_seed_or(D); return s; }
//     std::mt19937_64 make_rng() { return rng_for_current_test(base_seed()); }
// and prints the seed with every failure by RAYPROOF_SEED_TRACE(base_seed()).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>

namespace rayproof::testing {

// RAYPROOF_SEED from the environment (decimal), else `fallback`.
inline std::uint64_t env_seed_or(std::uint64_t fallback) {
    const char* env = std::getenv("RAYPROOF_SEED");
    return env ? std::strtoull(env, nullptr, 10) : fallback;
}

// The running test's generator: the base seed mixed with "Suite.Name" (FNV-1a steps).
inline std::mt19937_64 rng_for_current_test(std::uint64_t base) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string name = std::string(info->test_suite_name()) + "." + info->name();
    std::uint64_t h = base;
    for (char c : name) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ull;
    return std::mt19937_64(h);
}

}  // namespace rayproof::testing

#define RAYPROOF_SEED_TRACE(seed) SCOPED_TRACE("RAYPROOF_SEED=" + std::to_string(seed))
