// Unit tests of rayproof/detail/compensated.hpp (the double-word stage between the
// interval filter and exact arithmetic) against GMP rationals:
//   - quotient_sums: whenever ok, |hi + lo - exact sum| <= bound in both lanes, on
//     random sums of three and six products over a wide exponent range and on sums
//     built to cancel; exact sums get a zero bound; in_range rejects what it must;
//   - pin_quotient: whenever it pins, the candidate is a faithful rounding of N/D,
//     exactly N/D when that is a double; on generic input it does pin (the stage is not
//     dead), while exact midpoints never produce a wrong double;
//   - SphereQuadratic::residual().sign_at: whenever it decides, it is the exact sign of
//     q(g) (sign_at), at the floats around both roots, where q changes sign;
//   - lanes::exact_product: hi + lo is the exact product in both lanes, over the range
//     its callers guard (zeros, short and full mantissas, products near 2^-900);
//   - quotient_sums_short_first: the same bits as quotient_sums, short factors or not;
//   - AffineSpans (affine_quotients.hpp): the groups' shifts and range tests from one
//     pass, as affine_shifts, balanced_affine_shifts and expansion_safe give them value
//     by value, NaN, infinities, zeros and subnormals included;
//   - AffineQuotients::balanced: its quotients are the given ones scaled exactly;
//   - word_sign, word_difference and word_compare (the exact stages' comparisons from
//     the pairs): on fine sums, the enclosure of N1·D2 - N2·D1 and of N - c·D always
//     holds, and whenever they decide, the sign is the exact sign of N, of N1/D1 - N2/D2
//     and of N/D - c,
//     on random, nearly equal and exactly equal quotients (scaled copies) and against
//     the rounded quotient and its neighbours; exact ties of integer-like sums are
//     decided (not dead), and so is nearly every generic comparison;
//   - plane_pin (the certified plane's straight-line path): every claim it makes is
//     exact (t strictly between c's neighbours, the rough enclosure, t == 0, a ray in
//     or parallel to the plane), on generic, cancelling, nearly parallel, integer and
//     wide-exponent input; and it pins nearly every generic crossing (not dead).
// Every random test is seeded: RAYPROOF_SEED=<decimal> in the environment replays a run;
// the seed is printed with every failure.
#include <rayproof/detail/affine_quotients.hpp>
#include <rayproof/detail/compensated.hpp>
#include <rayproof/io.hpp>
#include <rayproof/rayproof.hpp>

#include "faithful.hpp"
#include "seeded.hpp"

#include <gmpxx.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace {

using namespace rayproof::detail;
using rayproof::testing::is_faithful;
using rayproof::testing::minus_rational;

std::uint64_t base_seed() {
    static const std::uint64_t s = rayproof::testing::env_seed_or(20261122);
    return s;
}
// One generator per test, derived from the base seed and the test's name (seeded.hpp).
std::mt19937_64 make_rng() { return rayproof::testing::rng_for_current_test(base_seed()); }
#define SEED_TRACE() RAYPROOF_SEED_TRACE(base_seed())

std::string hex(double x) {
    std::ostringstream os;
    os << std::hexfloat << x;
    return os.str();
}
mpq_class Q(double x) { return mpq_class(x); }
int sgn(const mpq_class& q) { return sgn(q.get_num()); }
mpq_class abs_q(const mpq_class& q) { return sgn(q) < 0 ? mpq_class(-q) : q; }

// A random double: sign, a 53-bit mantissa (sometimes short, to make exact
// cancellations likely) and an exponent in [-e, e].
double random_double(std::mt19937_64& rng, int e) {
    const int bits = (rng() % 4 == 0) ? 1 + int(rng() % 8) : 53;
    const std::uint64_t m = (rng() >> (64 - bits)) | (std::uint64_t(1) << (bits - 1));
    const int ex = int(rng() % std::uint64_t(2 * e + 1)) - e;
    const double v = std::ldexp(double(m), ex - bits);
    return (rng() & 1) ? -v : v;
}

// N (lane 0) and D (lane 1) as quotient_sums takes them, with their exact values: a start
// and P products per lane (unused products of a lane are 0·0).
struct Sums {
    QuotientSums qs;
    mpq_class N = 0, D = 0;
    std::string text;
};
template <int P> Sums make_sums(double n0, double d0, const double (&x)[2][P], const double (&y)[2][P]) {
    using namespace rayproof::detail::lanes;
    Sums s;
    D2 a[P], b[P];
    M2 in = in_range(make(n0, d0), splat(0x1p1000));
    s.N = Q(n0);
    s.D = Q(d0);
    s.text = "N = " + hex(n0) + ", D = " + hex(d0);
    for (int k = 0; k < P; ++k) {
        a[k] = make(x[0][k], x[1][k]);
        b[k] = make(y[0][k], y[1][k]);
        in = in & in_range(a[k]) & in_range(b[k]);
        s.N += Q(x[0][k]) * Q(y[0][k]);
        s.D += Q(x[1][k]) * Q(y[1][k]);
        s.text += " | " + hex(x[0][k]) + "*" + hex(y[0][k]) + ", " + hex(x[1][k]) + "*" + hex(y[1][k]);
    }
    s.qs = quotient_sums(make(n0, d0), a, b, in);
    return s;
}
// Random sums over exponents [-e, e], P products per lane; `cancel` makes N's start the
// rounded negative of its products' sum, so N cancels to its rounding errors.
template <int P> Sums random_sums(std::mt19937_64& rng, int e, bool cancel) {
    double x[2][P], y[2][P];
    double approx = 0;
    for (int l = 0; l < 2; ++l)
        for (int k = 0; k < P; ++k) {
            x[l][k] = (rng() % 8 == 0) ? 0.0 : random_double(rng, e);
            y[l][k] = random_double(rng, e);
            if (l == 0) approx += x[l][k] * y[l][k];
        }
    const double n0 = cancel ? -approx : random_double(rng, 2 * e), d0 = (rng() % 2) ? 0.0 : random_double(rng, 2 * e);
    return make_sums<P>(n0, d0, x, y);
}

TEST(QuotientSums, BoundHoldsWheneverOk) {
    SEED_TRACE();
    auto rng = make_rng();
    int ok = 0, inexact = 0;
    for (int it = 0; it < 40000; ++it) {
        const int e = (it % 3 == 0) ? 220 : (it % 3 == 1 ? 30 : 4);
        const bool cancel = it % 4 == 0;
        const Sums s = (it % 2) ? random_sums<3>(rng, e, cancel) : random_sums<6>(rng, e, cancel);
        if (!s.qs.ok) continue;
        ++ok;
        using namespace rayproof::detail::lanes;
        const mpq_class en = abs_q(Q(lane0(s.qs.hi)) + Q(lane0(s.qs.lo)) - s.N);
        const mpq_class ed = abs_q(Q(lane1(s.qs.hi)) + Q(lane1(s.qs.lo)) - s.D);
        inexact += en != 0;
        ASSERT_LE(en, Q(lane0(s.qs.bound))) << s.text;
        ASSERT_LE(ed, Q(lane1(s.qs.bound))) << s.text;
        ASSERT_LE(std::abs(lane0(s.qs.lo)), 0x1p-53 * std::abs(lane0(s.qs.hi))) << s.text;  // renormalized
    }
    EXPECT_GT(ok, 30000);       // most random sums are in range (the test checks something)
    EXPECT_GT(inexact, 10000);  // the bound is exercised, not only exact sums
}

TEST(QuotientSums, ExactSumsHaveZeroBoundAndOutOfRangeIsRejected) {
    using namespace rayproof::detail::lanes;
    // Small integers: every product and partial sum exact, bound 0, the exact value.
    const double x[2][3] = {{3, -5, 7}, {2, 2, -4}}, y[2][3] = {{1, 2, 3}, {1, 1, 1}};
    const Sums s = make_sums<3>(-14, 0, x, y);
    ASSERT_TRUE(s.qs.ok);
    EXPECT_EQ(lane0(s.qs.bound), 0.0);
    EXPECT_EQ(lane1(s.qs.bound), 0.0);
    EXPECT_EQ(lane0(s.qs.hi), 0.0);  // -14 + 3 - 10 + 21 = 0 exactly
    EXPECT_EQ(lane1(s.qs.hi), 0.0);  // 2 + 2 - 4 = 0
    // in_range: 0, [2^-450, top]; not below 2^-450, above top, NaN or infinite.
    EXPECT_EQ(bits(in_range(make(0.0, -0x1p-450))), 3);
    EXPECT_EQ(bits(in_range(make(0x1p-451, 0x1p490))), 2);
    EXPECT_EQ(bits(in_range(make(0x1p491, -0x1p490))), 2);
    EXPECT_EQ(bits(in_range(make(std::nan(""), std::numeric_limits<double>::infinity()))), 0);
    EXPECT_EQ(bits(in_range(make(0x1p1000, 0x1p1001), splat(0x1p1000))), 1);
    const double tiny[2][3] = {{0x1p-600, 1, 1}, {1, 1, 1}}, one[2][3] = {{1, 1, 1}, {1, 1, 1}};
    EXPECT_FALSE((make_sums<3>(1, 1, tiny, one).qs.ok));  // a product whose error term could be lost
}

TEST(QuotientSumsShortFirst, SameBitsAsQuotientSums) {
    SEED_TRACE();
    auto rng = make_rng();
    using namespace rayproof::detail::lanes;
    const auto same = [](D2 a, D2 b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    int short_inputs = 0;
    for (int it = 0; it < 40000; ++it) {
        const int e = (it % 2) ? 99 : 20;
        D2 a[6], b[6];
        bool all_short = true;
        M2 in = in_range(splat(1.0));
        for (int k = 0; k < 6; ++k) {
            double v[4];
            for (double& x : v) {
                x = (rng() % 8 == 0) ? 0.0 : random_double(rng, e);
                if (it % 3 == 0)  // often short: the leading 20 bits
                    x = std::bit_cast<double>(std::bit_cast<std::uint64_t>(x) & ~((std::uint64_t(1) << 33) - 1));
                all_short = all_short && lanes::high26(x) == x;
            }
            a[k] = make(v[0], v[1]);
            b[k] = make(v[2], v[3]);
            in = in & in_range(a[k]) & in_range(b[k]);
        }
        short_inputs += all_short;
        const D2 start = make(random_double(rng, e), 0.0);
        const QuotientSums x = quotient_sums(start, a, b, in), y = quotient_sums_short_first(start, a, b, in);
        ASSERT_TRUE(same(x.hi, y.hi) && same(x.lo, y.lo) && same(x.bound, y.bound) && x.ok == y.ok) << "case " << it;
    }
    EXPECT_GT(short_inputs, 1000);  // the shortcut is taken
}

// AffineSpans (affine_quotients.hpp: one pass over an affine input's four groups, two
// values at a time) against its definition value by value: shifts() is affine_shifts of
// the groups' ExponentSpans, within(2^-100, 2^100) is every value expansion_safe and
// within(0, max) every value finite; on groups of 1 to 12 rows whose values are zeros of
// either sign, subnormals, values anywhere in the exponent range, near the safe range's
// ends, infinities and NaNs.
TEST(AffineSpans, AreTheGroupsExponentSpans) {
    SEED_TRACE();
    auto rng = make_rng();
    // A case's values lie around 2^centre, within 2^±width, some of them special (a case
    // of every third is kept free of them, and centred at 1 every other time).
    const auto value = [&](int centre, int width, bool plain) {
        switch (plain ? 9 : rng() % 24) {
            case 0: return (rng() & 1) ? -0.0 : 0.0;
            case 1: return std::ldexp(double(1 + rng() % 1000), -1074);  // subnormal
            case 2: return (rng() & 1) ? std::numeric_limits<double>::infinity() : std::nan("");
            case 3: return std::ldexp((rng() & 1) ? 1.0 : -1.0, (rng() & 1) ? -100 : 100) * ((rng() & 1) ? 1.0 : 1.5);
            case 4: return random_double(rng, 1020);
            default: return std::ldexp(random_double(rng, 2), centre + int(rng() % std::uint64_t(2 * width + 1)) - width);
        }
    };
    int shifted = 0, safe = 0, unscalable = 0;
    for (int it = 0; it < 100000; ++it) {
        const bool plain = it % 3 == 0;
        const int centre = (it % 2) ? int(rng() % 1801) - 900 : 0, width = 10 + int(rng() % 200);
        const auto draw = [&] { return value(centre, width, plain); };
        AffineSpans spans;
        ExponentSpan positions, rows, halves, directions;
        bool all_safe = true, all_finite = true;
        const auto note = [&](ExponentSpan& group, double x) {
            group.add(x);
            all_safe = all_safe && expansion_safe(x);
            all_finite = all_finite && std::isfinite(x);
        };
        std::vector<double> given;  // the case's values in call order, for a failure's message
        for (int j = 0; j < 3; ++j) {
            const double o = draw(), d = draw();
            spans.ray(o, d);
            note(positions, o);
            note(directions, d);
            given.insert(given.end(), {o, d});
        }
        const int n = 1 + int(rng() % 12);
        for (int i = 0; i < n; ++i) {
            const double a0 = draw(), a1 = draw(), a2 = draw(), h = draw();
            spans.row(a0, a1, a2, h);
            note(rows, a0);
            note(rows, a1);
            note(rows, a2);
            note(halves, h);
            given.insert(given.end(), {a0, a1, a2, h});
        }
        // Formatted only when an assertion fails (gtest streams the message then alone).
        const auto what = [&] {
            std::ostringstream os;
            os << std::hexfloat << "case " << it << ":";
            for (std::size_t k = 0; k < 6; k += 2) os << " ray(" << given[k] << ", " << given[k + 1] << ")";
            for (std::size_t k = 6; k < given.size(); k += 4)
                os << " row(" << given[k] << ", " << given[k + 1] << ", " << given[k + 2] << ", " << given[k + 3] << ")";
            return os.str();
        };
        ASSERT_EQ(spans.within(0x1p-100, 0x1p100), all_safe) << what();
        ASSERT_EQ(spans.within(0, std::numeric_limits<double>::max()), all_finite) << what();
        const auto same = [](const std::optional<AffineShifts>& got, const std::optional<AffineShifts>& want) {
            return got.has_value() == want.has_value() &&
                   (!want || (got->sp == want->sp && got->sa == want->sa && got->sd == want->sd));
        };
        const std::optional<AffineShifts> want = affine_shifts(positions, rows, halves, directions);
        ASSERT_TRUE(same(spans.shifts(), want)) << what() << ": the shifts into the safe range";
        if (want)
            shifted += want->sp != 0 || want->sa != 0 || want->sd != 0;
        else
            ++unscalable;
        ASSERT_TRUE(same(spans.balanced_shifts(), balanced_affine_shifts(positions, rows, halves, directions)))
            << what() << ": the balanced shifts";
        safe += all_safe;
    }
    // Every outcome reached: safe input, input scaled into the range, input no scaling fits.
    EXPECT_GT(safe, 1000);
    EXPECT_GT(shifted, 5000);
    EXPECT_GT(unscalable, 10000);
}

// AffineQuotients::balanced (affine_quotients.hpp: the copy for input too wide to
// rescale, each group's largest magnitude brought to [1, 2)): wherever it exists, every
// quotient num(i, side)/den(i) of it is the given one times 2^shift() exactly, with the
// signs of num and den unchanged (so every value was scaled exactly); on random finite
// input whose groups lie around random centres within up to 2^±600 (so that most are
// too wide for rescaled()), subnormals and zeros included, of one row (a plane's
// crossing) or three (a box's slabs).
template <int R> void balanced_scales_exactly(std::mt19937_64& rng, int& made, int& too_wide) {
    const auto value = [&](int centre, int width) {
        switch (rng() % 16) {
            case 0: return (rng() & 1) ? -0.0 : 0.0;
            case 1: return std::ldexp(double(1 + rng() % 1000), -1074);  // subnormal
            default: {
                const int e = std::clamp(centre + int(rng() % std::uint64_t(2 * width + 1)) - width, -1074, 1000);
                return std::ldexp(random_double(rng, 2), e);
            }
        }
    };
    const auto mul2 = [](mpq_class v, int e) {
        if (e >= 0)
            mpq_mul_2exp(v.get_mpq_t(), v.get_mpq_t(), static_cast<mp_bitcnt_t>(e));
        else
            mpq_div_2exp(v.get_mpq_t(), v.get_mpq_t(), static_cast<mp_bitcnt_t>(-e));
        return v;
    };
    for (int it = 0; it < 20000; ++it) {
        AffineValues<R> v;
        const auto group = [&] { return std::pair{int(rng() % 2001) - 1000, int(rng() % 601)}; };
        const auto [cp, wp] = group();
        const auto [ca, wa] = group();
        const auto [ch, wh] = group();
        const auto [cd, wd] = group();
        for (int j = 0; j < 3; ++j) {
            v.o[j] = value(cp, wp);
            v.c[j] = value(cp, wp);
            v.d[j] = value(cd, wd);
            for (int i = 0; i < R; ++i) v.a[i][j] = value(ca, wa);
        }
        for (int i = 0; i < R; ++i) v.h[i] = value(ch, wh);
        const std::optional<AffineQuotients<R>> w = AffineQuotients<R>::balanced(v);
        if (!w) continue;
        ++made;
        too_wide += !AffineQuotients<R>::rescaled(v);
        const AffineQuotients<R> given(v, false);
        const auto what = [&] {
            std::ostringstream os;
            os << std::hexfloat << "case " << it << ", shift " << w->shift() << ": o c d";
            for (int j = 0; j < 3; ++j) os << " (" << v.o[j] << ", " << v.c[j] << ", " << v.d[j] << ")";
            for (int i = 0; i < R; ++i) os << " row " << v.a[i][0] << " " << v.a[i][1] << " " << v.a[i][2] << " h " << v.h[i];
            return os.str();
        };
        for (int i = 0; i < R; ++i) {
            const mpq_class d = given.template den<mpq_class>(i), wd_ = w->template den<mpq_class>(i);
            ASSERT_EQ(sgn(wd_), sgn(d)) << what();
            for (int side = 0; side < 2; ++side) {
                const mpq_class n = given.template num<mpq_class>(i, side), wn = w->template num<mpq_class>(i, side);
                ASSERT_EQ(sgn(wn), sgn(n)) << what();
                ASSERT_TRUE(wn * d == mul2(n * wd_, w->shift())) << what() << ": value (" << i << ", " << side << ")";
            }
        }
    }
}
TEST(AffineQuotients, BalancedCopyScalesExactly) {
    SEED_TRACE();
    auto rng = make_rng();
    int made = 0, too_wide = 0;
    balanced_scales_exactly<1>(rng, made, too_wide);
    balanced_scales_exactly<3>(rng, made, too_wide);
    EXPECT_GT(made, 5000) << "balanced copies should be made";
    EXPECT_GT(too_wide, 2000) << "input too wide to rescale should be among them";
}

// Fine sums (compensated.hpp's word_compare): N and D of P products each, every input 0
// or in [2^-100, 2^99), mantissas short or full; `integers` makes every input a small
// integer (exact sums, bound 0).
template <int P> Sums fine_sums(std::mt19937_64& rng, bool integers) {
    double x[2][P], y[2][P];
    const auto value = [&] {
        if (integers) return double(int(rng() % 17) - 8);
        return (rng() % 8 == 0) ? 0.0 : random_double(rng, 99);
    };
    for (int l = 0; l < 2; ++l)
        for (int k = 0; k < P; ++k) x[l][k] = value(), y[l][k] = value();
    return make_sums<P>(value(), 0.0, x, y);
}
// The same sums with N and D both times f (a power of two, or 3), every start and one
// factor of each product multiplied (exactly for a power of two; for 3 only where the
// products stay exact: the comparison's truth is computed from the inputs anyway).
template <int P> Sums scaled_copy(const double (&x)[2][P], const double (&y)[2][P], double n0, double f) {
    double x2[2][P];
    for (int l = 0; l < 2; ++l)
        for (int k = 0; k < P; ++k) x2[l][k] = x[l][k] * f;
    return make_sums<P>(n0 * f, 0.0, x2, y);
}
WordQuotient word_of(const Sums& s) { return unpack(s.qs); }

TEST(WordCompare, ExactWheneverDecided) {
    SEED_TRACE();
    auto rng = make_rng();
    int decided[5] = {}, tried[5] = {}, signs_decided = 0, integer_ties = 0, integer_ties_decided = 0;
    for (int it = 0; it < 50000; ++it) {
        // 0 random, 1 integers, 2 a scaled copy (a tie), 3 one input nudged by an ulp, 4
        // the same with N cancelling to its rounding errors (the sums' bounds matter)
        const int kind = it % 5;
        constexpr int P = 3;
        double x[2][P], y[2][P], n0;
        const bool integers = kind == 1 || (kind == 2 && it % 8 == 2);
        const auto value = [&] {  // for nudged copies, terms of like magnitude (a nudge not lost below u^2)
            if (integers) return double(int(rng() % 17) - 8);
            return (rng() % 8 == 0) ? 0.0 : random_double(rng, kind >= 3 ? 4 : 90);
        };
        for (int l = 0; l < 2; ++l)
            for (int k = 0; k < P; ++k) x[l][k] = value(), y[l][k] = value();
        n0 = value();
        if (kind == 4) {
            n0 = 0;
            for (int k = 0; k < P; ++k) n0 -= x[0][k] * y[0][k];
        }
        const Sums a = make_sums<P>(n0, 0.0, x, y);
        Sums b;
        if (kind == 2) {
            b = scaled_copy<P>(x, y, n0, (it % 3 == 0) ? 3.0 : std::ldexp(1.0, int(rng() % 9) - 4));
        } else if (kind >= 3) {
            double x2[2][P];
            std::memcpy(x2, x, sizeof x2);
            double& v = x2[rng() % 2][rng() % P];
            if (v != 0) v = (rng() % 2) ? std::nextafter(v, HUGE_VAL) : std::nextafter(v, -HUGE_VAL);
            b = make_sums<P>(n0, 0.0, x2, y);
        } else {
            b = fine_sums<P>(rng, integers);
        }
        if (!a.qs.ok || !b.qs.ok) continue;
        const std::string what = "case " + std::to_string(it) + ": " + a.text + " against " + b.text;
        // word_sign of each lane
        for (const auto& [hi, bound, exact] : {std::tuple{word_of(a).n, word_of(a).bn, a.N}, std::tuple{word_of(a).d, word_of(a).bd, a.D}})
            if (const std::optional<int> sg = word_sign(hi, bound)) {
                ASSERT_EQ(*sg, sgn(exact)) << what << ": word_sign";
                ++signs_decided;
            }
        if (sgn(a.D) == 0 || sgn(b.D) == 0) continue;
        // the difference's enclosure holds, decided or not
        const WordDifference wd = word_difference(word_of(a), word_of(b));
        const mpq_class X = a.N * b.D - b.N * a.D;
        ASSERT_LE(abs_q(X - Q(wd.s) - Q(wd.r)), Q(wd.B)) << what << ": word_difference";
        const int truth = sgn(X) * sgn(a.D) * sgn(b.D);
        // a nudge that changed nothing (a zero factor beside it) is a tie of inexact
        // sums, which the pairs cannot tell from a tiny difference: not counted
        const bool counted = !(kind >= 3 && truth == 0);
        tried[kind] += counted;
        const bool integer_tie = kind == 2 && integers && truth == 0;
        integer_ties += integer_tie;
        if (const std::optional<int> s = word_compare(word_of(a), word_of(b))) {
            ASSERT_EQ(*s, truth) << what;
            decided[kind] += counted;
            integer_ties_decided += integer_tie;
        }
        // against the rounded quotient, its neighbours and a constant in range
        const double q = mpq_class(a.N / a.D).get_d();
        for (const double c : {q, std::nextafter(q, -HUGE_VAL), std::nextafter(q, HUGE_VAL), 0.0, random_double(rng, 60)}) {
            if (!std::isfinite(c)) continue;
            if (c != 0 && !(std::abs(c) >= 0x1p-300 && std::abs(c) <= 0x1p300)) continue;
            const WordDifference wc = word_difference(word_of(a), c);
            ASSERT_LE(abs_q(a.N - Q(c) * a.D - Q(wc.s) - Q(wc.r)), Q(wc.B)) << what << ": word_difference against " << hex(c);
            if (const std::optional<int> s = word_compare(word_of(a), c)) {
                ASSERT_EQ(*s, sgn(mpq_class(a.N / a.D - Q(c)))) << what << ": against " << hex(c);
            }
        }
    }
    // Not dead: generic comparisons, exact ties of integer-like sums and one-ulp
    // differences are nearly all decided from the pairs.
    EXPECT_GT(decided[0], tried[0] * 99 / 100);
    EXPECT_GT(decided[1], tried[1] * 99 / 100);
    EXPECT_GT(integer_ties, 1000);
    EXPECT_EQ(integer_ties_decided, integer_ties);
    EXPECT_GT(decided[3], tried[3] * 9 / 10);
    EXPECT_GT(decided[4], tried[4] / 2);
    EXPECT_GT(signs_decided, 40000);
}

// r is q faithfully rounded (the shared helper, faithful.hpp) and finite.
::testing::AssertionResult faithful(double r, const mpq_class& q) {
    if (!std::isfinite(r)) return ::testing::AssertionFailure() << "non-finite " << hex(r);
    return is_faithful(r, minus_rational(q)) << " (" << q.get_d() << ")";
}

TEST(PinQuotient, FaithfulWheneverPinned) {
    SEED_TRACE();
    auto rng = make_rng();
    int pinned = 0, generic = 0, generic_pinned = 0;
    for (int it = 0; it < 40000; ++it) {
        const int e = (it % 4 == 0) ? 220 : 30;
        const bool cancel = it % 5 == 0;
        const Sums s = (it % 2) ? random_sums<3>(rng, e, cancel) : random_sums<6>(rng, e, cancel);
        const PinnedQuotient x = pin_quotient(s.qs);
        const bool is_generic = s.qs.ok && it % 4 != 0 && !cancel;
        generic += is_generic;
        if (!x.pinned) continue;
        ++pinned;
        generic_pinned += is_generic;
        ASSERT_NE(sgn(s.D), 0) << s.text;
        ASSERT_TRUE(faithful(x.c, s.N / s.D)) << s.text;
    }
    // Generic, well-scaled input is the stage's whole purpose: it must pin nearly always.
    EXPECT_GT(generic_pinned, generic * 99 / 100) << generic_pinned << " of " << generic;
    EXPECT_GT(pinned, 20000);
}

// Exactly representable quotients come back exactly; exact midpoints between two doubles
// give one of the two.
TEST(PinQuotient, RepresentableAndMidpointQuotients) {
    SEED_TRACE();
    auto rng = make_rng();
    int answered = 0;
    for (int it = 0; it < 5000; ++it) {
        const double x = random_double(rng, 40), y = random_double(rng, 40), z = random_double(rng, 40);
        const Pair yz = two_prod(y, z);  // D = y·z, N = x·D: t = x exactly
        const double nx[2][2] = {{x, x}, {y, 0}}, ny[2][2] = {{yz.hi, yz.lo}, {z, 0}};
        const Sums s = make_sums<2>(0, 0, nx, ny);
        if (const PinnedQuotient p = pin_quotient(s.qs); p.pinned) {
            ++answered;
            EXPECT_EQ(p.c, x) << s.text;
        }
        // midpoint: N = (2x + gap)·D, D' = 2·D, t = x + gap/2
        const double gap = step_up(x) - x;
        const double mx[2][4] = {{2 * x, 2 * x, gap, gap}, {2 * y, 0, 0, 0}},
                     my[2][4] = {{yz.hi, yz.lo, yz.hi, yz.lo}, {z, 0, 0, 0}};
        const Sums m = make_sums<4>(0, 0, mx, my);
        if (const PinnedQuotient p = pin_quotient(m.qs); p.pinned) {
            EXPECT_TRUE(faithful(p.c, m.N / m.D)) << m.text;
        }
    }
    // At a representable t the residual is D times one gap away from deciding: pinned.
    EXPECT_GT(answered, 4500);
}

TEST(CompensatedSphere, SignAtRootsIsExactWhenDecided) {
    SEED_TRACE();
    auto rng = make_rng();
    int decided = 0, tried = 0;
    for (int it = 0; it < 4000; ++it) {
        const int e = (it % 2) ? 8 : 200;
        rayproof::Ray<double> r;
        rayproof::Sphere<double> sp;
        for (int j = 0; j < 3; ++j) {
            r.origin[j] = random_double(rng, e);
            r.direction[j] = random_double(rng, e / 2);
            sp.center[j] = r.origin[j] + std::ldexp(random_double(rng, 2), e / 2) * r.direction[j] + random_double(rng, e / 4);
        }
        sp.radius = std::abs(random_double(rng, e));
        r.t_min = -std::numeric_limits<double>::infinity();
        const rayproof::Hit<double> h = rayproof::intersect(r, sp, rayproof::certified);
        if (h.verdict != rayproof::Verdict::hit) continue;
        const SphereQuadratic<double> q(r, sp);
        for (double root : {h.t_enter, h.t_exit}) {
            for (double g : {step_down(root), root, step_up(root)}) {
                if (!std::isfinite(g)) continue;
                ++tried;
                const int c = q.residual().sign_at(g);
                if (c == 2) continue;
                ++decided;
                ASSERT_EQ(c, q.sign_at(g)) << "ray " << r << " sphere " << sp << " g = " << hex(g);
            }
        }
    }
    EXPECT_GT(decided, tried * 9 / 10) << decided << " of " << tried;
}

TEST(LanesExactProduct, HiPlusLoIsTheProduct) {
    SEED_TRACE();
    auto rng = make_rng();
    using namespace rayproof::detail::lanes;
    int checked = 0;
    for (int it = 0; it < 50000; ++it) {
        double a[2], b[2];
        for (int k = 0; k < 2; ++k) {
            a[k] = (rng() % 16 == 0) ? 0.0 : random_double(rng, 490);
            b[k] = (rng() % 16 == 0) ? 0.0 : random_double(rng, 490);
            if (it % 3 == 0 && a[k] != 0 && b[k] != 0)  // products near the 2^-900 floor
                b[k] = std::ldexp(b[k], -900 - std::ilogb(a[k]) - std::ilogb(b[k]));
        }
        const Product p = exact_product(make(a[0], a[1]), make(b[0], b[1]));
        const double hi[2] = {lane0(p.hi), lane1(p.hi)}, lo[2] = {lane0(p.lo), lane1(p.lo)};
        for (int k = 0; k < 2; ++k) {
            const bool in_range = std::abs(hi[k]) >= 0x1p-916 || a[k] == 0 || b[k] == 0;
            if (!in_range || std::fpclassify(a[k]) == FP_SUBNORMAL || std::fpclassify(b[k]) == FP_SUBNORMAL) continue;
            ++checked;
            ASSERT_EQ(Q(hi[k]) + Q(lo[k]), Q(a[k]) * Q(b[k])) << "lane " << k << ": " << hex(a[k]) << " * " << hex(b[k]);
        }
    }
    EXPECT_GT(checked, 90000);
}

// One plane and ray for plane_pin, with the exact N = offset - n·o and D = n·d.
struct PinCase {
    rayproof::Ray<double> ray;
    rayproof::Plane<double> plane;
    mpq_class N, D;
};
PinCase pin_case(std::mt19937_64& rng, int kind) {
    PinCase c;
    auto value = [&](int e) { return random_double(rng, e); };
    auto small_int = [&] { return double(int(rng() % 17) - 8); };
    for (int j = 0; j < 3; ++j) {
        switch (kind) {
            case 0:  // generic
            case 1:  // cancelling numerator, nearly parallel direction (set below)
                c.plane.normal[j] = value(4);
                c.ray.origin[j] = value(8);
                c.ray.direction[j] = value(4);
                break;
            case 2:  // integers: exact products, exact zeros, rays in and parallel to the plane
                c.plane.normal[j] = small_int();
                c.ray.origin[j] = small_int();
                c.ray.direction[j] = small_int();
                break;
            default:  // wide exponents
                c.plane.normal[j] = value(200);
                c.ray.origin[j] = value(240);
                c.ray.direction[j] = value(200);
        }
    }
    const auto& n = c.plane.normal;
    c.plane.offset = kind == 2 ? small_int() : value(kind == 3 ? 440 : 8);
    if (kind == 1) {
        const double w[3] = {value(4), value(4), value(4)};
        for (int j = 0; j < 3; ++j)  // d = n × w: n·d ~ 0, up to the cross product's roundings
            c.ray.direction[j] = n[(j + 1) % 3] * w[(j + 2) % 3] - n[(j + 2) % 3] * w[(j + 1) % 3];
        if (rng() % 2) c.ray.direction[rng() % 3] *= 1 + 0x1p-40;
        c.plane.offset = n.dot(c.ray.origin) + ((rng() % 2) ? 0.0 : std::ldexp(value(4), -20));
    }
    if (kind == 2 && rng() % 3 == 0) c.plane.offset = n.dot(c.ray.origin);  // origin in the plane
    c.N = Q(c.plane.offset);
    c.D = 0;
    for (int j = 0; j < 3; ++j) {
        c.N -= Q(n[j]) * Q(c.ray.origin[j]);
        c.D += Q(n[j]) * Q(c.ray.direction[j]);
    }
    return c;
}

TEST(PlanePin, EveryClaimIsExact) {
    SEED_TRACE();
    auto rng = make_rng();
    int pinned[4] = {}, rough = 0, zero = 0, lying = 0, parallel = 0;
    const int per_kind = 20000;
    for (int it = 0; it < 4 * per_kind; ++it) {
        const int kind = it % 4;
        const PinCase c = pin_case(rng, kind);
        const PlanePin x = plane_pin(c.ray, c.plane);
        std::ostringstream what;
        what << "kind " << kind << " ray " << c.ray << " plane " << c.plane << " c = " << hex(x.c);
        if (x.pinned || x.rough || x.zero) {
            ASSERT_NE(sgn(c.D), 0) << what.str();
        }
        // a <= t (or a < t when strict), an infinite a compared as such
        const auto below = [](double a, const mpq_class& t, bool strict) {
            if (std::isinf(a)) return a < 0;
            return strict ? Q(a) < t : Q(a) <= t;
        };
        const auto above = [](double a, const mpq_class& t, bool strict) {
            if (std::isinf(a)) return a > 0;
            return strict ? t < Q(a) : t <= Q(a);
        };
        if (x.pinned) {
            ++pinned[kind];
            ASSERT_TRUE(std::isfinite(x.c)) << what.str();
            const mpq_class t = c.N / c.D;
            ASSERT_TRUE(below(step_down(x.c), t, true)) << what.str();
            ASSERT_TRUE(above(step_up(x.c), t, true)) << what.str();
        }
        if (x.rough) {
            rough += !x.pinned;
            ASSERT_FALSE(std::isnan(x.rough_lo) || std::isnan(x.rough_hi)) << what.str();
            const mpq_class t = c.N / c.D;
            ASSERT_TRUE(below(x.rough_lo, t, false)) << what.str();
            ASSERT_TRUE(above(x.rough_hi, t, false)) << what.str();
        }
        if (x.zero) {
            ++zero;
            ASSERT_EQ(sgn(c.N), 0) << what.str();
        }
        if (x.lying) {
            ++lying;
            ASSERT_EQ(sgn(c.N), 0) << what.str();
            ASSERT_EQ(sgn(c.D), 0) << what.str();
        }
        if (x.parallel) {
            ++parallel;
            ASSERT_NE(sgn(c.N), 0) << what.str();
            ASSERT_EQ(sgn(c.D), 0) << what.str();
        }
    }
    // Not dead: nearly every generic crossing is pinned, and every other claim is made.
    EXPECT_GT(pinned[0], per_kind * 99 / 100);
    EXPECT_GT(pinned[3], per_kind * 9 / 10);
    EXPECT_GT(pinned[2], per_kind / 2);
    EXPECT_GT(rough, 100);
    EXPECT_GT(zero, 100);
    EXPECT_GT(lying, 10);
    EXPECT_GT(parallel, 100);
}

}  // namespace
