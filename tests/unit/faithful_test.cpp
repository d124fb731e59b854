// The contract's tolerance helper (faithful.hpp) itself: for seeded random rationals at
// every exponent of float and double (quotients of log-uniform floats, beyond the largest
// finite value and below the smallest denormal included), the two enclosing floats pass
// and every float one, two or three steps outside them fails; a representable value
// passes alone; the ends of the range (max and inf, 0 and denorm_min, -0 as 0), ±inf
// values and NaN answers. And the reason for the helper: on the plane case of
// ray_plane_test whose t used to be checked within 2^-50·|t|, a certified answer moved
// two ulps off passes that old tolerance and fails the helper.
#include "faithful.hpp"
#include "seeded.hpp"

#include <rayproof/rayproof.hpp>

#include <gmpxx.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

using namespace rayproof;
using rayproof::testing::is_faithful;
using rayproof::testing::minus_rational;
using rayproof::testing::minus_value;

namespace {

std::uint64_t base_seed() {
    static const std::uint64_t s = rayproof::testing::env_seed_or(0xfa17);
    return s;
}

template <class T> T up(T x, int k = 1) {
    for (; k > 0; --k) x = std::nextafter(x, std::numeric_limits<T>::infinity());
    return x;
}
template <class T> T down(T x, int k = 1) {
    for (; k > 0; --k) x = std::nextafter(x, -std::numeric_limits<T>::infinity());
    return x;
}
mpq_class Q(double x) { return mpq_class(x); }

// A finite T with a uniformly random bit pattern (every exponent, denormals, ±0).
template <class T> T random_finite(std::mt19937_64& rng) {
    for (;;) {
        T x;
        if constexpr (sizeof(T) == 4)
            x = std::bit_cast<float>(std::uint32_t(rng()));
        else
            x = std::bit_cast<double>(std::uint64_t(rng()));
        if (std::isfinite(x)) return x;
    }
}

// The floats lo <= q <= hi enclosing q, found by walking from a nearby float with exact
// comparisons; hi is +inf (lo -inf) beyond the finite range.
template <class T> std::pair<T, T> enclosing(const mpq_class& q) {
    constexpr T inf = std::numeric_limits<T>::infinity(), mx = std::numeric_limits<T>::max();
    if (q > Q(mx)) return {mx, inf};
    if (q < Q(-mx)) return {-inf, -mx};
    T c = static_cast<T>(q.get_d());
    if (!std::isfinite(c)) c = c > 0 ? mx : -mx;
    while (Q(c) > q) c = down(c);
    while (up(c) <= mx && Q(up(c)) <= q) c = up(c);
    return {c, Q(c) == q ? c : up(c)};
}

template <class T> void check_random_rationals() {
    RAYPROOF_SEED_TRACE(base_seed());
    auto rng = rayproof::testing::rng_for_current_test(base_seed());
    int representable = 0, between = 0;
    for (int i = 0; i < 20000; ++i) {
        const T a = random_finite<T>(rng), b = random_finite<T>(rng);
        if (b == 0) continue;
        // a/b, and sometimes a itself (representable) or a/b scaled out of T's range.
        mpq_class q = i % 5 == 0 ? Q(a) : Q(a) / Q(b);
        if (i % 7 == 0) q *= mpq_class(1, 3);
        const auto [lo, hi] = enclosing<T>(q);
        SCOPED_TRACE(::testing::Message() << "q = " << q.get_d() << " lo " << std::hexfloat << lo << " hi " << hi);
        ASSERT_TRUE(is_faithful(lo, minus_rational(q)));
        ASSERT_TRUE(is_faithful(hi, minus_rational(q)));
        (lo == hi ? representable : between)++;
        for (int k = 1; k <= 3; ++k) {
            if (!std::isinf(lo)) {
                ASSERT_FALSE(is_faithful(down(lo, k), minus_rational(q))) << k;
            }
            if (!std::isinf(hi)) {
                ASSERT_FALSE(is_faithful(up(hi, k), minus_rational(q))) << k;
            }
        }
    }
    EXPECT_GT(representable, 1000);
    EXPECT_GT(between, 10000);
}

TEST(Faithful, RandomRationalsFloat) { check_random_rationals<float>(); }
TEST(Faithful, RandomRationalsDouble) { check_random_rationals<double>(); }

template <class T> void check_range_ends() {
    constexpr T inf = std::numeric_limits<T>::infinity(), mx = std::numeric_limits<T>::max(),
                dm = std::numeric_limits<T>::denorm_min();
    const mpq_class huge = Q(mx) * 2, tiny = Q(dm) / 3;
    EXPECT_TRUE(is_faithful(mx, minus_rational(huge)));
    EXPECT_TRUE(is_faithful(inf, minus_rational(huge)));
    EXPECT_FALSE(is_faithful(down(mx), minus_rational(huge)));
    EXPECT_FALSE(is_faithful(-inf, minus_rational(huge)));
    EXPECT_TRUE(is_faithful(T(0), minus_rational(tiny)));
    EXPECT_TRUE(is_faithful(-T(0), minus_rational(tiny)));
    EXPECT_TRUE(is_faithful(dm, minus_rational(tiny)));
    EXPECT_FALSE(is_faithful(-dm, minus_rational(tiny)));
    EXPECT_FALSE(is_faithful(2 * dm, minus_rational(tiny)));
    // Values that are floats: the value itself (±0 alike), ±inf only as themselves.
    EXPECT_TRUE(is_faithful(-T(0), minus_value(T(0))));
    EXPECT_FALSE(is_faithful(dm, minus_value(T(0))));
    EXPECT_TRUE(is_faithful(inf, minus_value(inf)));
    EXPECT_FALSE(is_faithful(mx, minus_value(inf)));
    EXPECT_FALSE(is_faithful(-inf, minus_value(-mx)));
    EXPECT_FALSE(is_faithful(std::numeric_limits<T>::quiet_NaN(), minus_value(T(1))));
    EXPECT_FALSE(is_faithful(up(T(1)), minus_value(T(1))));
}

TEST(Faithful, RangeEndsFloat) { check_range_ends<float>(); }
TEST(Faithful, RangeEndsDouble) { check_range_ends<double>(); }

// The plane case of ray_plane_test (RayPlaneExtreme): the old check accepted any t within
// 2^-50·|t| of the double N/D, about 4 ulps either way. A certified answer pushed two
// ulps away from the exact value is still accepted by it and rejected by the helper.
TEST(Faithful, RejectsTwoUlpsWhereTheOldToleranceAccepted) {
    const double inf = std::numeric_limits<double>::infinity();
    const double d_computed = std::ldexp(9.0, 26);
    const double t_min = -1.01 * std::ldexp(1.0, 1024 - 26) / 9.0;
    const Plane<double> plane{Vec3<double>(1, 1, 1), 0.97 * t_min * d_computed};
    const double d1 = std::ldexp(9 + 0.49, 26);  // the hit
    const Ray<double> ray{Vec3<double>(0, 0, 0), Vec3<double>(std::ldexp(1.0, 78), d1, -std::ldexp(1.0, 78)), t_min, inf};
    const Hit<double> h = intersect(ray, plane, certified);
    ASSERT_EQ(h.verdict, Verdict::hit);
    const mpq_class exact_t = Q(plane.offset) / (Q(std::ldexp(1.0, 78)) + Q(d1) - Q(std::ldexp(1.0, 78)));
    ASSERT_TRUE(is_faithful(h.t_enter, minus_rational(exact_t)));
    const double t = plane.offset / d1;
    const auto old_tolerance = [&](double x) { return std::abs(x - t) <= std::ldexp(std::abs(t), -50); };
    // Two ulps beyond the certified answer, away from the exact value.
    const double off = Q(h.t_enter) <= exact_t ? down(h.t_enter, 2) : up(h.t_enter, 2);
    EXPECT_TRUE(old_tolerance(off)) << std::hexfloat << off;
    EXPECT_FALSE(is_faithful(off, minus_rational(exact_t))) << std::hexfloat << off;
}

}  // namespace
