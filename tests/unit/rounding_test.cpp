// The branch-free helpers of detail/rounding.hpp and detail/certified.hpp that every
// mode's answer passes through: pick and pick_int (a select without a jump), the ordered
// keys float_key / key_float, the outward roundings round_down_to / round_up_to of a
// double enclosure end to T, outward_to (both ends of an enclosure rounded outward and
// clamped to [t_min, t_max], with its verdict `meets`) and nearest_float (the float
// nearest every value of an enclosure, where its ends round alike). Each is checked
// against a definition written another way (std::nextafter, comparisons, the step_up /
// step_down it must agree with, the nearest float found by distance), over float and
// double, on the special values (signed zeros, subnormals, the largest finite value,
// infinities, NaN) and on seeded random values spanning every binade. Also
// detail/interval.hpp's product with a point (times_point) against the full product.
#include "seeded.hpp"

#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/detail/rounding.hpp>

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace rayproof::detail;
using rayproof::testing::env_seed_or;
using rayproof::testing::rng_for_current_test;

namespace {

std::uint64_t base_seed() {
    static const std::uint64_t s = env_seed_or(20261204);
    return s;
}

template <class T> std::string hex(T x) {
    char b[64];
    std::snprintf(b, sizeof b, "%a", double(x));
    return b;
}
template <class T> bool same_bits(T a, T b) { return std::bit_cast<FloatBits<T>>(a) == std::bit_cast<FloatBits<T>>(b); }

// Special values of T, and doubles around the float range's edges.
template <class T> std::vector<T> specials() {
    using L = std::numeric_limits<T>;
    return {T(0),         -T(0),          L::denorm_min(), -L::denorm_min(), L::min(),           -L::min(),
            L::max(),     -L::max(),      L::infinity(),   -L::infinity(),   L::quiet_NaN(),     -L::quiet_NaN(),
            T(1),         -T(1),          T(1.5),          -T(0.75),         L::min() / T(3),    -L::min() / T(5)};
}
// A random T with a random sign, its exponent uniform over every binade (subnormals too).
template <class T> T random_value(std::mt19937_64& rng) {
    using L = std::numeric_limits<T>;
    const int lo = L::min_exponent - L::digits, hi = L::max_exponent;
    const T m = std::uniform_real_distribution<T>(T(1), T(2))(rng);
    const T x = std::ldexp(m, int(rng() % unsigned(hi - lo)) + lo - 1);
    return rng() & 1 ? -x : x;
}
// A random double around the float range, where the outward roundings to float act: the
// float binades, subnormal floats and values beyond them, each with a random fraction.
double random_double_for_float(std::mt19937_64& rng) {
    const double m = std::uniform_real_distribution<double>(1, 2)(rng);
    const double x = std::ldexp(m, int(rng() % 300) - 165);
    return rng() & 1 ? -x : x;
}

}  // namespace

template <class T> class Rounding : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Rounding, Scalars);

// pick(c, a, b) is c ? a : b, bit for bit: signed zeros and NaN payloads survive.
TYPED_TEST(Rounding, PickIsTheTernaryBitForBit) {
    using T = TypeParam;
    RAYPROOF_SEED_TRACE(base_seed());
    std::mt19937_64 rng = rng_for_current_test(base_seed());
    std::vector<T> values = specials<T>();
    for (int i = 0; i < 200; ++i) values.push_back(random_value<T>(rng));
    for (const T a : values)
        for (const T b : {T(0), -T(0), std::numeric_limits<T>::quiet_NaN(), T(2.5)}) {
            EXPECT_TRUE(same_bits(pick(true, a, b), a)) << hex(a) << " " << hex(b);
            EXPECT_TRUE(same_bits(pick(false, a, b), b)) << hex(a) << " " << hex(b);
        }
    for (const int a : {0, -1, 5, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()})
        for (const int b : {0, -1, 3}) {
            EXPECT_EQ(pick_int(true, a, b), a);
            EXPECT_EQ(pick_int(false, a, b), b);
        }
}

// The keys order the values as < does (both zeros at key 0), one key per float: the key
// of step_up(x) is one more than x's, and key_float gives the value back (+0 for key 0).
TYPED_TEST(Rounding, KeysOrderTheValuesOneApart) {
    using T = TypeParam;
    RAYPROOF_SEED_TRACE(base_seed());
    std::mt19937_64 rng = rng_for_current_test(base_seed());
    std::vector<T> values = specials<T>();
    for (int i = 0; i < 20000; ++i) values.push_back(random_value<T>(rng));
    for (std::size_t i = 0; i < values.size(); ++i) {
        const T x = values[i];
        if (std::isnan(x)) continue;
        SCOPED_TRACE(hex(x));
        const std::int64_t k = float_key(x);
        if (x == 0) {
            EXPECT_EQ(k, 0);
            EXPECT_TRUE(same_bits(key_float<T>(k), T(0)));
        } else {
            EXPECT_TRUE(same_bits(key_float<T>(k), x));
        }
        if (!(std::isinf(x) && x > 0)) {
            EXPECT_EQ(float_key(step_up(x)), k + 1);
            EXPECT_EQ(float_key(std::nextafter(x, std::numeric_limits<T>::infinity())), k + 1);
        }
        const T y = values[(i * 7919 + 13) % values.size()];
        if (!std::isnan(y)) {
            EXPECT_EQ(x < y, k < float_key(y)) << hex(y);
        }
    }
}

// For T = float: round_down_to(x) is the largest float <= x and round_up_to(x) the
// smallest float >= x (±inf beyond the range), with the signed zero that step_down /
// step_up give (the step from ±0 down is -denorm_min, from -denorm_min up is -0; a
// value rounded to nearest onto ±0 that needs no step keeps that zero); NaN stays NaN.
// For T = double both are the identity.
TYPED_TEST(Rounding, OutwardRoundingIsTheNeighbourTowardTheEnd) {
    using T = TypeParam;
    RAYPROOF_SEED_TRACE(base_seed());
    std::mt19937_64 rng = rng_for_current_test(base_seed());
    std::vector<double> xs;
    for (const double x : specials<double>()) xs.push_back(x);
    for (const float f : specials<float>()) {
        xs.push_back(double(f));
        // Just beside each float and each half-way point (ties of the rounding to float).
        const double up = std::nextafter(double(f), 1e300), down = std::nextafter(double(f), -1e300);
        xs.insert(xs.end(), {up, down, (double(f) + up) / 2, double(std::nextafter(f, 1.0f)) / 2 + double(f) / 2});
    }
    xs.insert(xs.end(), {1e39, -1e39, 0x1p-150, -0x1p-150, 0x1.8p-150, -0x1.8p-150, 0x1p-160, -0x1p-160});
    for (int i = 0; i < 200000; ++i) xs.push_back(random_double_for_float(rng));
    constexpr double inf = std::numeric_limits<double>::infinity();
    for (const double x : xs) {
        SCOPED_TRACE(hex(x));
        const T dn = round_down_to<T>(x), up = round_up_to<T>(x);
        if (std::isnan(x)) {
            EXPECT_TRUE(std::isnan(dn));
            EXPECT_TRUE(std::isnan(up));
            continue;
        }
        if constexpr (std::is_same_v<T, double>) {
            EXPECT_TRUE(same_bits(dn, x));
            EXPECT_TRUE(same_bits(up, x));
        } else {
            // Bounds on the right side, and the neighbour beyond them on the other.
            EXPECT_LE(double(dn), x);
            EXPECT_GE(double(up), x);
            if (dn != std::numeric_limits<float>::infinity()) {
                EXPECT_GT(double(std::nextafter(dn, float(inf))), x);
            }
            if (up != -std::numeric_limits<float>::infinity()) {
                EXPECT_LT(double(std::nextafter(up, -float(inf))), x);
            }
            // And the very bits of the definition by step_down / step_up.
            const float y = float(x);
            EXPECT_TRUE(same_bits(dn, double(y) > x ? step_down(y) : y)) << hex(dn);
            EXPECT_TRUE(same_bits(up, double(y) < x ? step_up(y) : y)) << hex(up);
        }
    }
}

// outward_to(lo, hi, t_min, t_max), the conservative answers' ends: for any enclosure
// [lo, hi] (lo not +inf, hi not -inf) and range t_min <= t_max (floats of T, t_min not
// +inf, t_max not -inf), the ends lie in the range, hold [lo, hi] clamped to it, and
// are in order whenever that clamped interval is not empty, which is exactly when meets
// (the verdict the callers answer) is true. For T = double they are the
// clamped values themselves; for float at most three floats wider than the closest
// ones (round_down_to / round_up_to of the clamped values): the shift 2^-23|x| is one to
// two float steps, and near the subnormal range its 2^-149 is one step more.
TYPED_TEST(Rounding, OutwardEndsEncloseTheClampedInterval) {
    using T = TypeParam;
    using L = std::numeric_limits<T>;
    RAYPROOF_SEED_TRACE(base_seed());
    std::mt19937_64 rng = rng_for_current_test(base_seed());
    std::vector<double> ends;
    for (const double x : specials<double>())
        if (!std::isnan(x)) ends.push_back(x);
    for (const float f : specials<float>())
        if (!std::isnan(f)) {
            ends.push_back(double(f));
            ends.push_back(std::nextafter(double(f), 1e300));
            ends.push_back(std::nextafter(double(f), -1e300));
        }
    std::vector<T> limits;
    for (const T t : specials<T>())
        if (!std::isnan(t)) limits.push_back(t);
    const auto end = [&] { return rng() % 4 == 0 ? ends[rng() % ends.size()] : random_double_for_float(rng); };
    const auto limit = [&]() -> T {
        if (rng() % 3 == 0) return limits[rng() % limits.size()];
        return std::is_same_v<T, float> ? T(random_double_for_float(rng)) : random_value<T>(rng);
    };
    const auto three_down = [](T x) { return x == -L::infinity() ? x : step_down(step_down(step_down(x))); };
    const auto three_up = [](T x) { return x == L::infinity() ? x : step_up(step_up(step_up(x))); };
    int nonempty = 0;
    for (int i = 0; i < 400000; ++i) {
        double lo = end(), hi = end();
        if (hi < lo) std::swap(lo, hi);
        if (rng() % 8 == 0) hi = lo;
        T t_min = limit(), t_max = limit();
        if (t_max < t_min) std::swap(t_min, t_max);
        if (lo == L::infinity() || hi == -L::infinity() || t_min == L::infinity() || t_max == -L::infinity())
            continue;
        char where[160];
        std::snprintf(where, sizeof where, "[%a, %a] in [%a, %a]", lo, hi, double(t_min), double(t_max));
        SCOPED_TRACE(where);
        const OutwardEnds<T> e = outward_to<T>(lo, hi, t_min, t_max);
        const double clo = lo > double(t_min) ? lo : double(t_min), chi = hi < double(t_max) ? hi : double(t_max);
        ASSERT_GE(e.lo, t_min);
        ASSERT_LE(e.hi, t_max);
        ASSERT_LE(double(e.lo), clo);
        ASSERT_GE(double(e.hi), chi);
        // The verdict: [lo, hi] meets [t_min, t_max] exactly when the clamped interval is
        // not empty (t_min <= t_max here).
        ASSERT_EQ(e.meets, clo <= chi);
        if (clo <= chi) {
            ++nonempty;
            ASSERT_LE(e.lo, e.hi);
        }
        if constexpr (std::is_same_v<T, double>) {
            ASSERT_TRUE(same_bits(e.lo, clo)) << hex(e.lo);
            ASSERT_TRUE(same_bits(e.hi, chi)) << hex(e.hi);
        } else {
            ASSERT_GE(e.lo, three_down(round_down_to<T>(clo))) << hex(e.lo);
            ASSERT_LE(e.hi, three_up(round_up_to<T>(chi))) << hex(e.hi);
        }
    }
    EXPECT_GT(nonempty, 100000);
}

// nearest_float(lo, hi, ok), the certified float answer from a double enclosure (the
// plane's and the oriented box's straight-line paths): where it answers, every double in
// [lo, hi] has the answer as its nearest float (checked against a nearest float found
// another way: the candidate and its two neighbours by distance, ties to the even
// significand), so it is t's nearest float for any t the enclosure holds; it answers +0
// for zero, never an infinity, never for an enclosure that is not ok; and it declines
// only when the two ends' nearest floats differ (or are infinite).
TEST(RoundingNearestFloat, AnswersTheNearestFloatOfEveryValueInTheEnclosure) {
    RAYPROOF_SEED_TRACE(base_seed());
    std::mt19937_64 rng = rng_for_current_test(base_seed());
    using L = std::numeric_limits<float>;
    const auto nearest = [](double y) -> float {
        if (std::abs(y) > double(L::max())) return std::abs(y) >= 0x1.ffffffp127 ? std::copysign(L::infinity(), float(y)) : std::copysign(L::max(), float(y));
        float best = 0;
        double dbest = L::infinity();
        const float c = static_cast<float>(y);
        for (const float f : {std::nextafter(c, -L::infinity()), c, std::nextafter(c, L::infinity())}) {
            const double d = std::abs(double(f) - y);
            const bool even = (std::bit_cast<std::uint32_t>(f) & 1) == 0;
            if (d < dbest || (d == dbest && even)) best = f, dbest = d;
        }
        return best;
    };
    int answered = 0, declined = 0;
    for (int i = 0; i < 400000; ++i) {
        double x = random_double_for_float(rng);
        if (rng() % 16 == 0) x = 0;
        if (rng() % 16 == 0) {  // a midpoint between two floats, or a float
            const float f = static_cast<float>(x);
            x = rng() & 1 ? double(f) : (double(f) + double(std::nextafter(f, L::infinity()))) / 2;
        }
        // An enclosure of x of relative width 2^-k (k from 10 to 70) or of width 0.
        const int k = 10 + int(rng() % 61);
        const double w = rng() % 8 == 0 ? 0 : std::ldexp(std::abs(x) + 0x1p-160, -k);
        const double u1 = std::uniform_real_distribution<double>(0, 1)(rng), u2 = std::uniform_real_distribution<double>(0, 1)(rng);
        const double lo = x - w * u1, hi = x + w * u2;
        char where[128];
        std::snprintf(where, sizeof where, "[%a, %a] around %a", lo, hi, x);
        SCOPED_TRACE(where);
        ASSERT_FALSE(nearest_float(lo, hi, false).ok);
        const Pinned<float> f = nearest_float(lo, hi, true);
        const float a = nearest(lo), b = nearest(hi);
        if (!f.ok) {
            ++declined;
            ASSERT_TRUE(a != b || std::isinf(a)) << hex(a) << " " << hex(b);
            continue;
        }
        ++answered;
        ASSERT_TRUE(std::isfinite(f.t));
        ASSERT_FALSE(f.t == 0 && std::signbit(f.t));
        for (int j = 0; j < 8; ++j) {
            const double y = j == 0 ? lo : j == 1 ? hi : j == 2 ? x : lo + (hi - lo) * std::uniform_real_distribution<double>(0, 1)(rng);
            ASSERT_EQ(nearest(y), f.t) << "at " << hex(y);
        }
    }
    EXPECT_GT(answered, 300000);
    EXPECT_GT(declined, 1000);
}

// detail/interval.hpp's times_point(a, y), the product with a point taken from two end
// products, is a * Interval(y) bit for bit: on intervals whose ends are special values
// (signed zeros, subnormals, the largest finite value, infinities) or random over every
// binade, and points alike, both ends' bits equal.
TYPED_TEST(Rounding, IntervalTimesPointIsTheProductWithThePoint) {
    using T = TypeParam;
    RAYPROOF_SEED_TRACE(base_seed());
    std::mt19937_64 rng = rng_for_current_test(base_seed());
    std::vector<T> values;
    for (const T x : specials<T>())
        if (!std::isnan(x)) values.push_back(x);
    for (int i = 0; i < 200; ++i) values.push_back(random_value<T>(rng));
    long checked = 0;
    for (const T a : values)
        for (const T b : values) {
            // an interval: ordered ends, not the empty [+inf, +inf] or [-inf, -inf]
            const Interval<T> x(std::min(a, b), std::max(a, b));
            if ((std::isinf(x.lo) && x.lo > 0) || (std::isinf(x.hi) && x.hi < 0)) continue;
            for (const T y : {values[rng() % values.size()], values[rng() % values.size()], T(0), -T(0), T(1)}) {
                const Interval<T> p = times_point(x, y), q = x * Interval<T>(y);
                ASSERT_TRUE(same_bits(p.lo, q.lo) && same_bits(p.hi, q.hi))
                    << "[" << hex(x.lo) << ", " << hex(x.hi) << "] times " << hex(y) << ": [" << hex(p.lo) << ", "
                    << hex(p.hi) << "] against [" << hex(q.lo) << ", " << hex(q.hi) << "]";
                ++checked;
            }
        }
    EXPECT_GT(checked, 50000);
}
