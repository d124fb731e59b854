// Unit tests of rayproof/detail/exact.hpp against GMP rationals (mpq_class, used here
// as the reference only; the header never touches GMP).
//
// Every random test is seeded: the seed is printed with every failure and can be set
// with the environment variable RAYPROOF_SEED (decimal) to replay a run.
#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/validate.hpp>

#include "faithful.hpp"
#include "seeded.hpp"

#include <gmpxx.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <limits>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#if defined(RAYPROOF_PORTABLE_LIMBS)
static_assert(RAYPROOF_INT128_LIMBS == 0, "RAYPROOF_PORTABLE_LIMBS must select the portable two-limb product");
#endif

namespace {

using namespace rayproof::detail;
using rayproof::testing::is_faithful;
using rayproof::testing::minus_rational;
using BigExpansion = Expansion<256>;

// ---------------------------------------------------------------- seeds and printing

std::uint64_t base_seed() {
    static const std::uint64_t s = rayproof::testing::env_seed_or(20240611);
    return s;
}
// One generator per test, derived from the base seed and the test's name (seeded.hpp).
std::mt19937_64 make_rng() { return rayproof::testing::rng_for_current_test(base_seed()); }
#define SEED_TRACE() RAYPROOF_SEED_TRACE(base_seed())

template <class T> std::string hex(T x) {
    std::ostringstream os;
    os << std::hexfloat << static_cast<double>(x);
    return os.str();
}

// ---------------------------------------------------------------- exact references

mpq_class Q(double x) { return mpq_class(x); }  // exact for finite x
mpq_class Q(float x) { return mpq_class(static_cast<double>(x)); }

mpq_class times_pow2(mpq_class v, long e) {
    if (e >= 0)
        mpq_mul_2exp(v.get_mpq_t(), v.get_mpq_t(), static_cast<mp_bitcnt_t>(e));
    else
        mpq_div_2exp(v.get_mpq_t(), v.get_mpq_t(), static_cast<mp_bitcnt_t>(-e));
    return v;
}

template <int Cap> mpq_class Q(const Expansion<Cap>& e) {
    mpq_class s = 0;
    for (double c : e.components()) s += Q(c);
    return s;
}

mpq_class Q(const BigDyadic& b) {
    mpz_class m = 0;
    for (int i = b.limb_count() - 1; i >= 0; --i) {
        m <<= 64;
        m += mpz_class(static_cast<unsigned long>(b.limb(i)));
    }
    mpq_class v(m);
    v = times_pow2(v, 64 * b.limb_exponent());
    return b.sign() < 0 ? mpq_class(-v) : v;
}

int sgn(const mpq_class& q) { return sgn(q.get_num()); }  // GMP's sgn on mpz

// Checks the representation invariants of an expansion: nonzero, increasing
// magnitude, nonoverlapping (each component's magnitude below the last bit of the next).
template <int Cap> ::testing::AssertionResult well_formed(const Expansion<Cap>& e) {
    auto c = e.components();
    for (std::size_t i = 0; i < c.size(); ++i) {
        if (c[i] == 0 || !std::isfinite(c[i])) return ::testing::AssertionFailure() << "bad component " << hex(c[i]);
        if (i + 1 < c.size()) {
            // lowest set bit of c[i+1]
            int ex = 0;
            double m = std::frexp(c[i + 1], &ex);
            std::uint64_t im = static_cast<std::uint64_t>(std::ldexp(std::abs(m), 53));
            const int low = ex - 53 + std::countr_zero(im);
            if (!(std::abs(c[i]) < std::ldexp(1.0, low)))
                return ::testing::AssertionFailure() << "overlap " << hex(c[i]) << " / " << hex(c[i + 1]);
        }
    }
    return ::testing::AssertionSuccess();
}
::testing::AssertionResult well_formed(const BigDyadic& b) {
    if (b.limb_count() == 0) return b.sign() == 0 ? ::testing::AssertionSuccess() : ::testing::AssertionFailure() << "signed zero";
    if (b.limb(0) == 0 || b.limb(b.limb_count() - 1) == 0) return ::testing::AssertionFailure() << "not normalized";
    return ::testing::AssertionSuccess();
}

// approx(): |mant| in [0.5, 1) (or 0 for zero), relative error <= 2^-50.
template <class E> ::testing::AssertionResult approx_ok(const E& x, const mpq_class& v) {
    const Approx a = x.approx();
    if (v == 0) {
        if (a.mant == 0) return ::testing::AssertionSuccess();
        return ::testing::AssertionFailure() << "approx of zero is " << hex(a.mant);
    }
    if (!(std::abs(a.mant) >= 0.5 && std::abs(a.mant) < 1)) return ::testing::AssertionFailure() << "mant " << hex(a.mant);
    const mpq_class A = times_pow2(Q(a.mant), a.exp);
    mpq_class err = abs(A - v);
    const mpq_class bound = times_pow2(mpq_class(abs(v)), -50);
    if (err <= bound) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "approx " << hex(a.mant) << "*2^" << a.exp << " of " << v.get_d();
}

// ---------------------------------------------------------------- generators

double from_bits(std::uint64_t b) { return std::bit_cast<double>(b); }

// Any finite double, exponents uniform over the whole range, with extra subnormals.
double any_double(std::mt19937_64& rng) {
    for (;;) {
        std::uint64_t b = rng();
        if (rng() % 8 == 0) b &= 0x800fffffffffffffull;  // subnormal (or ±0)
        const double x = from_bits(b);
        if (std::isfinite(x)) return x;
    }
}

// A nonzero double with |x| in [2^-100, 2^100] (expansion_safe).
double safe_double(std::mt19937_64& rng) {
    const int e = static_cast<int>(rng() % 201) - 100;  // [-100, 100]
    const std::uint64_t m = (rng() >> 11) | (std::uint64_t(1) << 52);
    const int keep = static_cast<int>(rng() % 53);  // sometimes few significant bits
    const std::uint64_t mm = rng() % 4 == 0 ? (m >> keep) << keep : m;
    double x = std::ldexp(static_cast<double>(mm), e - 52);  // in [2^e, 2^(e+1))
    if (e == 100) x = 0x1p100;
    return rng() % 2 ? -x : x;
}

const double kSpecial[] = {0.0,
                           -0.0,
                           1.0,
                           -1.0,
                           0.5,
                           3.0,
                           0x1p-1074,
                           -0x1p-1074,
                           0x1.8p-1073,
                           0x1p-1022,
                           0x0.fffffffffffffp-1022,
                           0x1.fffffffffffffp1023,
                           -0x1.fffffffffffffp1023,
                           0x1p1000,
                           0x1p-1000,
                           0x1.0000000000001p0,
                           0x1.fffffffffffffp-1,
                           0x1p-100,
                           0x1p100,
                           0x1.fffffffffffffp99,
                           0x1p-52,
                           0x1p53,
                           1e300,
                           1e-300};

// A mix aimed at the hard cases: full range, specials, small integers, near-equal pairs.
double interesting(std::mt19937_64& rng, double prev) {
    switch (rng() % 6) {
        case 0: return any_double(rng);
        case 1: return kSpecial[rng() % std::size(kSpecial)];
        case 2: return static_cast<double>(static_cast<int>(rng() % 33) - 16);
        case 3: {  // within a few ulps of the previous value: cancellation
            double x = prev;
            for (int k = static_cast<int>(rng() % 4); k > 0; --k) x = std::nextafter(x, rng() % 2 ? 1e308 : -1e308);
            return std::isfinite(x) ? x : prev;
        }
        case 4: {  // (one rng() call per statement: the sequence is the same for every compiler)
            const double m = static_cast<double>(rng() % 1000);
            return std::ldexp(m, static_cast<int>(rng() % 2088) - 1084);
        }
        default: return safe_double(rng);
    }
}

double safe_interesting(std::mt19937_64& rng, double prev) {
    switch (rng() % 4) {
        case 0: return safe_double(rng);
        case 1: return static_cast<double>(static_cast<int>(rng() % 33) - 16);
        case 2: {
            double x = prev;
            for (int k = static_cast<int>(rng() % 4); k > 0; --k) x = std::nextafter(x, rng() % 2 ? 1e308 : -1e308);
            return expansion_safe(x) ? x : prev;
        }
        default: {
            const double s[] = {0x1p-100, 0x1p100, -0x1p-100, 0x1.fffffffffffffp99, 0x1.0000000000001p-100, 1.0, 0.0};
            return s[rng() % std::size(s)];
        }
    }
}

// ================================================================= 1. EFTs

TEST(ExactEft, TwoSumFastTwoSumTwoProdAreErrorFree) {
    SEED_TRACE();
    auto rng = make_rng();
    double prev = 1;
    int checked_prod = 0;
    for (int it = 0; it < 20000; ++it) {
        const double a = interesting(rng, prev), b = interesting(rng, a);
        prev = b;
        SCOPED_TRACE(hex(a) + " " + hex(b));
        const Pair s = two_sum(a, b);
        // Exact whenever nothing overflows, always for |a|, |b| <= 2^1022; near ±max the
        // intermediate s − a may overflow and lo is then NaN, never a wrong finite value.
        if (std::abs(a) <= 0x1p1022 && std::abs(b) <= 0x1p1022) {
            EXPECT_TRUE(std::isfinite(s.lo));
        }
        if (std::isfinite(s.hi) && std::isfinite(s.lo)) {
            EXPECT_EQ(s.hi, a + b);
            EXPECT_EQ(Q(s.hi) + Q(s.lo), Q(a) + Q(b));
            const double big = std::abs(a) >= std::abs(b) ? a : b, small = std::abs(a) >= std::abs(b) ? b : a;
            const Pair f = fast_two_sum(big, small);
            EXPECT_EQ(f.hi, s.hi);
            EXPECT_EQ(f.lo, s.lo);
        }
        const Pair p = two_prod(a, b);
        if (std::isfinite(p.hi) && std::abs(p.hi) >= 0x1p-916) {  // the documented condition
            ++checked_prod;
            EXPECT_EQ(Q(p.hi) + Q(p.lo), Q(a) * Q(b));
        }
    }
    EXPECT_GT(checked_prod, 1000);
    // Subnormal error terms: inexact, as documented.
    const Pair p = two_prod(0x1.0000000000001p-540, 0x1.0000000000001p-540);
    EXPECT_NE(Q(p.hi) + Q(p.lo), Q(0x1.0000000000001p-540) * Q(0x1.0000000000001p-540));
}

// ================================================================= 2./3. Arithmetic

template <class E> struct Node {
    E e;
    mpq_class q;
    int deg;
};

template <class E> bool is_big() { return std::is_same_v<E, BigDyadic>; }

// Random straight-line programs over a pool of exact values, every result compared
// with mpq: value, sign, approx, representation invariants, stickiness of the flag.
template <class E, class Gen>
void random_programs(std::mt19937_64& rng, Gen gen, int max_deg, int programs, int steps, int* flagged_out) {
    int flagged = 0;
    for (int prog = 0; prog < programs; ++prog) {
        std::vector<Node<E>> pool;
        double prev = 1;
        for (int i = 0; i < 6; ++i) {
            prev = gen(rng, prev);
            pool.push_back({E(prev), Q(prev), 1});
        }
        for (int st = 0; st < steps; ++st) {
            const auto& x = pool[rng() % pool.size()];
            const auto& y = pool[rng() % pool.size()];
            Node<E> r{E(), 0, 1};
            std::ostringstream desc;
            switch (rng() % 6) {
                case 0: r = {x.e + y.e, x.q + y.q, std::max(x.deg, y.deg)}; desc << "+"; break;
                case 1: r = {x.e - y.e, x.q - y.q, std::max(x.deg, y.deg)}; desc << "-"; break;
                case 2:
                case 3:
                    if (x.deg + y.deg > max_deg) continue;
                    r = {x.e * y.e, x.q * y.q, x.deg + y.deg};
                    desc << "*";
                    break;
                case 4: r = {-x.e, -x.q, x.deg}; desc << "neg"; break;
                default: prev = gen(rng, prev); r = {E(prev), Q(prev), 1}; desc << "input " << hex(prev); break;
            }
            SCOPED_TRACE("program " + std::to_string(prog) + " step " + std::to_string(st) + " " + desc.str());
            const bool operand_bad = x.e.overflowed() || y.e.overflowed();
            if (r.e.overflowed()) {
                ++flagged;
                if (is_big<E>()) ADD_FAILURE() << "BigDyadic overflowed within its documented capacity";
            } else {
                if (desc.str() != "neg" && desc.str().rfind("input", 0) != 0) {
                    EXPECT_FALSE(operand_bad) << "overflowed() is not sticky";
                } else if (desc.str() == "neg") {
                    EXPECT_EQ(r.e.overflowed(), x.e.overflowed());
                }
                ASSERT_EQ(Q(r.e), r.q) << "inexact result";
                EXPECT_EQ(r.e.sign(), sgn(r.q));
                EXPECT_TRUE(approx_ok(r.e, r.q));
                EXPECT_TRUE(well_formed(r.e));
            }
            pool[rng() % pool.size()] = r;
        }
    }
    if (flagged_out) *flagged_out = flagged;
}

template <class E> class ExactArith : public ::testing::Test {};
using ExactTypes = ::testing::Types<Expansion<32>, Expansion<6>, BigDyadic>;
TYPED_TEST_SUITE(ExactArith, ExactTypes);

TYPED_TEST(ExactArith, RandomProgramsSafeInputs) {
    SEED_TRACE();
    auto rng = make_rng();
    int flagged = 0;
    random_programs<TypeParam>(rng, safe_interesting, 6, 300, 40, &flagged);
    if constexpr (std::is_same_v<TypeParam, Expansion<32>>) {
        EXPECT_LT(flagged, 300 * 40 / 20) << "Expansion<32> should rarely need more room";
    }
}

TYPED_TEST(ExactArith, RandomProgramsFullRange) {
    SEED_TRACE();
    auto rng = make_rng();
    int flagged = 0;
    // Expansion: exact whenever not flagged, even with subnormals and 2^±1000 inputs.
    random_programs<TypeParam>(rng, interesting, 6, 300, 40, &flagged);
    ::testing::Test::RecordProperty("flagged", flagged);
}

TYPED_TEST(ExactArith, ExactCancellations) {
    SEED_TRACE();
    using E = TypeParam;
    auto rng = make_rng();
    for (int it = 0; it < 3000; ++it) {
        const bool safe = !is_big<E>();
        auto g = [&](double p) { return safe ? safe_interesting(rng, p) : interesting(rng, p); };
        const double a0 = g(1), b0 = g(a0), c0 = g(b0);
        SCOPED_TRACE(hex(a0) + " " + hex(b0) + " " + hex(c0));
        const E a(a0), b(b0), c(c0);
        const E z1 = (a + b) - a - b;
        const E z2 = a * b - b * a;
        const E z3 = (a + b) * (a - b) - (a * a - b * b);
        const E z4 = (a + b + c) * (a - c) - a * a + c * c - b * a + b * c;
        const E z5 = (a * b + c) * (a * b - c) - (a * b) * (a * b) + c * c;
        for (const E* z : {&z1, &z2, &z3, &z4, &z5}) {
            if (z->overflowed()) {
                EXPECT_FALSE(is_big<E>());
                continue;
            }
            EXPECT_EQ(z->sign(), 0);
            EXPECT_EQ(Q(*z), 0);
            EXPECT_EQ(z->approx().mant, 0.0);
        }
        // One-ulp differences survive: (a + u) - a is exactly u.
        const double a1 = std::nextafter(a0, 2 * std::abs(a0) + 1);
        if (std::isfinite(a1)) {
            const E d = (E(a1) + b) - (a + b);
            if (!d.overflowed()) {
                EXPECT_EQ(Q(d), Q(a1) - Q(a0));
                EXPECT_EQ(d.sign(), 1);
            }
        }
    }
}

TEST(ExactArith, ManyComponents) {
    // ±2^(1000 - 54k), k = 0..37: 38 bits 54 apart, one component each.
    Expansion<32> small;
    Expansion<64> large;
    BigDyadic big;
    mpq_class q = 0;
    for (int k = 0; k <= 37; ++k) {
        const double x = std::ldexp(k % 3 ? -1.0 : 1.0, 1000 - 54 * k);
        small += x;
        large += x;
        big += x;
        q += Q(x);
    }
    EXPECT_TRUE(small.overflowed());
    ASSERT_FALSE(large.overflowed());
    EXPECT_EQ(large.size(), 38);
    EXPECT_EQ(Q(large), q);
    EXPECT_TRUE(approx_ok(large, q));
    ASSERT_FALSE(big.overflowed());
    EXPECT_EQ(Q(big), q);
    // Sticky.
    EXPECT_TRUE((small - small).overflowed());
    EXPECT_TRUE((small * Expansion<32>(0.0)).overflowed());
    EXPECT_TRUE((-small).overflowed());
    // Products that need many components: (1 + 2^-60)^k stays exact while it fits.
    Expansion<64> p(1.0);
    mpq_class pq = 1;
    const Expansion<64> f = Expansion<64>(1.0) + 0x1p-60;
    for (int k = 0; k < 12; ++k) {
        p *= f;
        pq *= Q(1.0) + Q(0x1p-60);
        if (p.overflowed()) break;
        EXPECT_EQ(Q(p), pq) << k;
    }
}

TEST(ExactArith, NonFiniteAndRangeFlags) {
    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(Expansion<8>(inf).overflowed());
    EXPECT_TRUE(Expansion<8>(nan).overflowed());
    EXPECT_TRUE(Expansion<8>(std::numeric_limits<float>::infinity()).overflowed());
    EXPECT_TRUE(BigDyadic(-inf).overflowed());
    EXPECT_TRUE(BigDyadic(nan).overflowed());
    const double mx = std::numeric_limits<double>::max();
    EXPECT_TRUE((Expansion<8>(mx) + mx).overflowed());
    EXPECT_TRUE((Expansion<8>(1e200) * Expansion<8>(1e200)).overflowed());
    EXPECT_TRUE((Expansion<8>(1e200) * (Expansion<8>(1e200) + 1e-100)).overflowed());
    // Products whose error term could be subnormal raise the flag instead of lying.
    EXPECT_TRUE((Expansion<8>(0x1.0000000000001p-540) * Expansion<8>(0x1.0000000000001p-540)).overflowed());
    EXPECT_TRUE((Expansion<8>(0x1p-600) * Expansion<8>(0x1p-600)).overflowed());  // underflows to 0
    EXPECT_FALSE((Expansion<8>(0x1p-400) * Expansion<8>(0x1p-400)).overflowed());
    EXPECT_TRUE(((Expansion<8>(1.0) + 0x1p-600) * (Expansion<8>(0x1p-400) + 0x1p-300)).overflowed());
    EXPECT_FALSE(((Expansion<8>(1.0) + 0x1p-300) * (Expansion<8>(0x1p-400) + 0x1p-300)).overflowed());
    // BigDyadic: the full double range, no overflow.
    const BigDyadic a = BigDyadic(mx) * BigDyadic(mx) * BigDyadic(mx) * BigDyadic(mx) * BigDyadic(mx);
    const BigDyadic b = BigDyadic(0x1p-1074) * BigDyadic(0x1p-1074) * BigDyadic(0x1p-1074) * BigDyadic(0x1p-1074) *
                        BigDyadic(0x1p-1074);
    const BigDyadic s = a + b;
    ASSERT_FALSE(s.overflowed());
    EXPECT_EQ(Q(s), Q(mx) * Q(mx) * Q(mx) * Q(mx) * Q(mx) + Q(0x1p-1074) * Q(0x1p-1074) * Q(0x1p-1074) * Q(0x1p-1074) * Q(0x1p-1074));
    EXPECT_TRUE(approx_ok(s, Q(s)));
    EXPECT_EQ((s - a - b).sign(), 0);
}

TEST(ExactArith, BigDyadicDocumentedCapacity) {
    // Degree 7 at both ends of the range, plus 2^16 terms' worth of carries: fits.
    const double hi = std::numeric_limits<double>::max(), lo = 0x1p-1074;
    BigDyadic ph(1.0), pl(1.0);
    mpq_class qh = 1, ql = 1;
    for (int k = 0; k < 7; ++k) {
        ph *= hi;
        pl *= lo;
        qh *= Q(hi);
        ql *= Q(lo);
    }
    BigDyadic s = ph * BigDyadic(65535.0) + pl;
    ASSERT_FALSE(s.overflowed());
    EXPECT_EQ(Q(s), qh * 65535 + ql);
    EXPECT_LE(s.limb_count(), BigDyadic::kCapacity);
    BigDyadic d = s - ph * BigDyadic(65535.0);
    ASSERT_FALSE(d.overflowed());
    EXPECT_EQ(Q(d), ql);
    EXPECT_EQ(d.limb_count(), 1);  // small again: only the limbs in use
    // Past the capacity: the flag, no crash.
    const BigDyadic wide = ph * ph + pl * pl;  // degree 14
    EXPECT_TRUE(wide.overflowed());
    BigDyadic p(1.0);
    const BigDyadic f = BigDyadic(1.0) + BigDyadic(0x1p-52);
    bool hit = false;
    for (int k = 0; k < 400 && !hit; ++k) {
        p *= f;
        hit = p.overflowed();
    }
    EXPECT_TRUE(hit);
    EXPECT_TRUE((p + 1.0).overflowed());
    EXPECT_TRUE((-p).overflowed());
}

TEST(ExactArith, FloatConstruction) {
    SEED_TRACE();
    auto rng = make_rng();
    for (int it = 0; it < 5000; ++it) {
        float x;
        do x = std::bit_cast<float>(static_cast<std::uint32_t>(rng())); while (!std::isfinite(x));
        EXPECT_EQ(Q(Expansion<4>(x)), Q(x));
        EXPECT_EQ(Q(BigDyadic(x)), Q(x));
        EXPECT_EQ(BigDyadic(x).sign(), sgn(Q(x)));
    }
}

// ================================================================= 4. expansion_safe

TEST(ExactSafe, Range) {
    EXPECT_TRUE(expansion_safe(0.0));
    EXPECT_TRUE(expansion_safe(-0.0));
    EXPECT_TRUE(expansion_safe(0x1p-100));
    EXPECT_TRUE(expansion_safe(-0x1p100));
    EXPECT_FALSE(expansion_safe(std::nextafter(0x1p-100, 0.0)));
    EXPECT_FALSE(expansion_safe(std::nextafter(0x1p100, 1e300)));
    EXPECT_FALSE(expansion_safe(std::numeric_limits<double>::quiet_NaN()));
    EXPECT_FALSE(expansion_safe(std::numeric_limits<double>::infinity()));
    EXPECT_TRUE(expansion_safe(std::numeric_limits<float>::denorm_min()));
    EXPECT_TRUE(expansion_safe(std::numeric_limits<float>::max()));
    EXPECT_FALSE(expansion_safe(std::numeric_limits<float>::infinity()));
    EXPECT_FALSE(expansion_safe(std::numeric_limits<float>::quiet_NaN()));
    EXPECT_TRUE(expansion_safe({1.0, 0x1p-100, 0.0}));
    EXPECT_FALSE(expansion_safe({1.0, 0x1p-101}));
}

// The derivation: products of up to 6 differences of safe inputs never raise the
// expansion's flag for range reasons (room is ample in Expansion<256>) and are exact.
double safe_extreme(std::mt19937_64& rng) {
    const double s[] = {0x1p-100, 0x1.0000000000001p-100, 0x1.fffffffffffffp-100, 0x1p100, 0x1.fffffffffffffp99, 1.0};
    if (rng() % 3 == 0) return safe_double(rng);
    const double x = s[rng() % std::size(s)];
    return rng() % 2 ? x : -x;
}
float any_float(std::mt19937_64& rng) {
    for (;;) {
        std::uint32_t b = static_cast<std::uint32_t>(rng());
        if (rng() % 4 == 0) b &= 0x807fffffu;  // subnormal
        const float x = std::bit_cast<float>(b);
        if (std::isfinite(x)) return x;
    }
}

// 3000 products of six differences a - b, each pair drawn by draw(rng), are neither
// flagged as overflowed nor inexact, and stay well formed.
template <class Draw> void expect_degree6_products_exact(std::mt19937_64& rng, Draw&& draw) {
    for (int it = 0; it < 3000; ++it) {
        BigExpansion p(1.0);
        mpq_class q = 1;
        std::string trace;
        for (int k = 0; k < 6; ++k) {
            const auto [a, b] = draw(rng);
            trace += hex(a) + "-" + hex(b) + " ";
            p *= BigExpansion(a) - BigExpansion(b);
            q *= Q(a) - Q(b);
        }
        SCOPED_TRACE(trace);
        ASSERT_FALSE(p.overflowed());
        EXPECT_EQ(Q(p), q);
        EXPECT_TRUE(well_formed(p));
    }
}

TEST(ExactSafe, Degree6ProductsNeverFlagDouble) {
    SEED_TRACE();
    auto rng = make_rng();
    expect_degree6_products_exact(rng, [](std::mt19937_64& g) {
        const double a = safe_extreme(g), b = safe_extreme(g);
        return std::pair{a, b};
    });
}

TEST(ExactSafe, Degree6ProductsNeverFlagFloat) {
    SEED_TRACE();
    auto rng = make_rng();
    const float ext[] = {std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::max(),
                         std::nextafter(std::numeric_limits<float>::denorm_min(), 1.0f), 0x1p-126f, 1.0f};
    expect_degree6_products_exact(rng, [&](std::mt19937_64& g) {
        float a = g() % 2 ? ext[g() % std::size(ext)] : any_float(g);
        float b = g() % 2 ? ext[g() % std::size(ext)] : any_float(g);
        if (g() % 2) b = -b;
        return std::pair{a, b};
    });
}

// ================================================================= 5. quotients

// r is num/den faithfully rounded (the shared helper, faithful.hpp), and beyond what
// faithfulness allows: never infinite (±max beyond the range), never NaN, zero is +0.
template <class T> ::testing::AssertionResult faithful(T r, const mpq_class& q) {
    if (!std::isfinite(r)) return ::testing::AssertionFailure() << "non-finite " << hex(r);
    if (r == 0 && std::signbit(r)) return ::testing::AssertionFailure() << "-0";
    return is_faithful(r, minus_rational(q)) << " (" << q.get_d() << ")";
}

// A random exact value of degree 1..3 from the generator (products and sums).
template <class E, class Gen> Node<E> random_value(std::mt19937_64& rng, Gen gen) {
    double prev = gen(rng, 1.0);
    Node<E> v{E(prev), Q(prev), 1};
    const int terms = static_cast<int>(rng() % 3);
    for (int t = 0; t < terms; ++t) {
        const double a = gen(rng, prev), b = gen(rng, a);
        prev = b;
        if (rng() % 2) {
            v = {v.e + E(a) * E(b), v.q + Q(a) * Q(b), 2};
        } else {
            v = {v.e * E(a) - E(b), v.q * Q(a) - Q(b), v.deg + 1};
        }
    }
    return v;
}

template <class T, class E, class Gen> void quotient_suite(std::mt19937_64& rng, Gen gen, int n) {
    for (int it = 0; it < n; ++it) {
        const Node<E> num = random_value<E>(rng, gen);
        Node<E> den = random_value<E>(rng, gen);
        if (den.q == 0 || den.e.overflowed() || num.e.overflowed()) continue;
        const mpq_class q = num.q / den.q;
        std::ostringstream tr;
        tr << "num " << num.q.get_d() << " den " << den.q.get_d();
        SCOPED_TRACE(tr.str());
        const T r = faithful_quotient<T>(num.e, den.e);
        ASSERT_TRUE(faithful(r, q));
        EXPECT_EQ(compare_quotient(num.e, den.e, r), sgn(q - Q(r)));
        // A representable quotient comes back exactly: num' = x·den.
        T x = static_cast<T>(interesting(rng, 1.0));
        if (!std::isfinite(x)) x = T(3);
        const E num2 = E(x) * den.e;
        if (!num2.overflowed()) {
            const T r2 = faithful_quotient<T>(num2, den.e);
            EXPECT_EQ(Q(r2), Q(x)) << hex(x);
            EXPECT_FALSE(std::signbit(r2) && r2 == 0);
            // and the neighbours of x: quotients half an ulp away
            const T gap = std::nextafter(x, T(1e30)) - x;
            const E num3 = E(x) * den.e * E(2.0) + den.e * E(gap);
            const E den3 = den.e * E(2.0);
            if (!any_overflowed(num3, den3) && std::isfinite(gap)) {
                const mpq_class q3 = Q(num3) / Q(den3);
                EXPECT_EQ(q3, Q(x) + Q(gap) / 2);
                EXPECT_TRUE(faithful(faithful_quotient<T>(num3, den3), q3));
            }
        }
        // compare_quotients against another random quotient, and against itself.
        const Node<E> n2 = random_value<E>(rng, gen), d2 = random_value<E>(rng, gen);
        if (d2.q != 0 && !n2.e.overflowed() && !d2.e.overflowed()) {
            EXPECT_EQ(compare_quotients(num.e, den.e, n2.e, d2.e), sgn(q - n2.q / d2.q));
        }
        EXPECT_EQ(compare_quotients(num.e, den.e, num.e * E(-3.0), den.e * E(-3.0)), 0);
    }
}

double full_gen(std::mt19937_64& rng, double prev) { return interesting(rng, prev); }
double safe_gen(std::mt19937_64& rng, double prev) { return safe_interesting(rng, prev); }

TEST(ExactQuotient, DoubleBigDyadicFullRange) {
    SEED_TRACE();
    auto rng = make_rng();
    quotient_suite<double, BigDyadic>(rng, full_gen, 2500);
}
TEST(ExactQuotient, FloatBigDyadicFullRange) {
    SEED_TRACE();
    auto rng = make_rng();
    quotient_suite<float, BigDyadic>(rng, full_gen, 2500);
}
TEST(ExactQuotient, DoubleExpansionSafe) {
    SEED_TRACE();
    auto rng = make_rng();
    quotient_suite<double, Expansion<32>>(rng, safe_gen, 2500);
}
TEST(ExactQuotient, FloatExpansionSafe) {
    SEED_TRACE();
    auto rng = make_rng();
    quotient_suite<float, Expansion<32>>(rng, safe_gen, 2500);
}
TEST(ExactQuotient, DoubleExpansionFullRangeFallsBack) {
    SEED_TRACE();
    auto rng = make_rng();
    quotient_suite<double, Expansion<32>>(rng, full_gen, 2500);
}

// Quotients of simple values sweeping the whole exponent range, both types, both T.
template <class T, class E> void sweep() {
    const T mx = std::numeric_limits<T>::max(), dmin = std::numeric_limits<T>::denorm_min();
    const double nums[] = {1.0, 3.0, -7.0, 0x1.fffffffffffffp1023, 0x1p-1074, 0x1.8p-1073, 0x1.5555555555555p-2, 1e300, -1e-300};
    for (double n : nums) {
        for (int e = -1074; e <= 1023; e += 7) {
            for (double m : {1.0, 3.0, -5.0, 0x1.fffffffffffffp0}) {
                const double d = std::ldexp(m, e);
                if (d == 0 || !std::isfinite(d)) continue;
                const E num(n), den(d);
                const mpq_class q = Q(n) / Q(d);
                const T r = faithful_quotient<T>(num, den);
                ASSERT_TRUE(faithful(r, q)) << hex(n) << " / " << hex(d);
                if (q > Q(mx)) {
                    EXPECT_EQ(r, mx);
                }
                if (q < -Q(mx)) {
                    EXPECT_EQ(r, -mx);
                }
                if (q != 0 && abs(q) < Q(dmin)) {
                    EXPECT_TRUE(r == 0 || std::abs(r) == dmin);
                }
            }
        }
    }
    EXPECT_EQ(faithful_quotient<T>(E(0.0), E(-3.0)), T(0));
    EXPECT_FALSE(std::signbit(faithful_quotient<T>(E(-0.0), E(-3.0))));
    EXPECT_FALSE(std::signbit(faithful_quotient<T>(E(-0x1p-1074), E(0x1p1000))));  // rounds to ±0 or -denorm
}

TEST(ExactQuotient, SweepDoubleBigDyadic) { sweep<double, BigDyadic>(); }
TEST(ExactQuotient, SweepFloatBigDyadic) { sweep<float, BigDyadic>(); }
TEST(ExactQuotient, SweepDoubleExpansion) { sweep<double, Expansion<16>>(); }
TEST(ExactQuotient, SweepFloatExpansion) { sweep<float, Expansion<16>>(); }

TEST(ExactQuotient, SmallExpansionFallsBackToBigDyadic) {
    // Cross products need more than 4 components: the answer comes from BigDyadic.
    using E = Expansion<4>;
    const E n1 = E(1.0) + 0x1p-60 + 0x1p-120, d1 = E(3.0) + 0x1p-70 + 0x1p-140;
    const E n2 = n1 + 0x1p-190, d2 = d1;
    ASSERT_FALSE(any_overflowed(n1, d1, n2, d2));
    ASSERT_TRUE((n1 * d2).overflowed());
    EXPECT_EQ(compare_quotients(n1, d1, n2, d2), -1);
    EXPECT_EQ(compare_quotients(n2, d2, n1, d1), 1);
    EXPECT_EQ(compare_quotients(n1, -d1, -n1, d1), 0);
    const mpq_class q = Q(n1) / Q(d1);
    EXPECT_TRUE(faithful(faithful_quotient<double>(n1, d1), q));
    EXPECT_TRUE(faithful(faithful_quotient<float>(n1, d1), q));
    const double r = faithful_quotient<double>(n1, d1);
    EXPECT_EQ(compare_quotient(n1, d1, r), sgn(q - Q(r)));
}

TEST(ExactQuotient, Boundaries) {
    using E = BigDyadic;
    const double mx = std::numeric_limits<double>::max();
    // Just above max: the enclosing finite neighbour is max, never infinity.
    EXPECT_EQ(faithful_quotient<double>(E(mx) + E(0x1p960), E(1.0)), mx);
    EXPECT_EQ(faithful_quotient<double>(-(E(mx) * E(3.0)), E(1.0)), -mx);
    EXPECT_EQ(faithful_quotient<double>(E(mx), E(0x1p-1074)), mx);
    // Exactly representable extremes.
    EXPECT_EQ(faithful_quotient<double>(E(mx) * E(0x1p-1074), E(0x1p-1074)), mx);
    EXPECT_EQ(faithful_quotient<double>(E(0x1p-1074) * E(3.0), E(3.0)), 0x1p-1074);
    // Half the smallest subnormal: 0 or denorm_min, and a zero is +0.
    const double h = faithful_quotient<double>(E(0x1p-1074), E(2.0));
    EXPECT_TRUE(h == 0x1p-1074 || (h == 0 && !std::signbit(h)));
    const double hn = faithful_quotient<double>(E(0x1p-1074), E(-2.0));
    EXPECT_TRUE(hn == -0x1p-1074 || (hn == 0 && !std::signbit(hn)));
    // Float: beyond FLT_MAX and below the float subnormals.
    EXPECT_EQ(faithful_quotient<float>(E(1e39), E(1.0)), std::numeric_limits<float>::max());
    const float fz = faithful_quotient<float>(E(1e-50), E(-1.0));
    EXPECT_TRUE(fz == -std::numeric_limits<float>::denorm_min() || (fz == 0 && !std::signbit(fz)));
    EXPECT_EQ(faithful_quotient<float>(E(1.0), E(3.0)) , 1.0f / 3.0f);
}

// ================================================================= 5. det3_sign

template <class T> mpq_class det_q(const Eigen::Matrix<T, 3, 3>& m) {
    auto q = [&](int i, int j) { return Q(m(i, j)); };
    return q(0, 0) * (q(1, 1) * q(2, 2) - q(1, 2) * q(2, 1)) - q(0, 1) * (q(1, 0) * q(2, 2) - q(1, 2) * q(2, 0)) +
           q(0, 2) * (q(1, 0) * q(2, 1) - q(1, 1) * q(2, 0));
}

// det3_sign's answer against mpq, and the Obb validity's own route to det != 0
// (obb_axes_independent, detail/validate.hpp: the inline filter, then the filter on the
// axes scaled by a power of two, then det3_sign), for finite entries.
template <class T> void check_det(const Eigen::Matrix<T, 3, 3>& m) {
    const int s = sgn(det_q(m));
    ASSERT_EQ(det3_sign(m), s);
    ASSERT_EQ(obb_axes_independent(m), s != 0);
}

template <class T> std::string mat_str(const Eigen::Matrix<T, 3, 3>& m) {
    std::string s;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) s += hex(m(i, j)) + (j == 2 ? "; " : " ");
    return s;
}

TEST(ExactDet3, RandomMatricesAgainstMpq) {
    SEED_TRACE();
    auto rng = make_rng();
    for (int it = 0; it < 20000; ++it) {
        Eigen::Matrix3d m;
        double prev = 1;
        const int kind = static_cast<int>(rng() % 4);
        for (int k = 0; k < 9; ++k) {
            switch (kind) {
                case 0: prev = interesting(rng, prev); break;
                case 1: prev = safe_interesting(rng, prev); break;
                case 2: prev = static_cast<double>(static_cast<int>(rng() % 7) - 3); break;
                default:  // entries a few ulps from ±1: every minor cancels, the filter is stressed
                    prev = 1 + static_cast<double>(rng() % 8) * 0x1p-52;
                    if (rng() % 2) prev = -prev;
            }
            m.data()[k] = prev;
        }
        SCOPED_TRACE(mat_str(m));
        ASSERT_NO_FATAL_FAILURE(check_det(m));
    }
}

TEST(ExactDet3, RandomFloatMatricesAgainstMpq) {
    SEED_TRACE();
    auto rng = make_rng();
    for (int it = 0; it < 20000; ++it) {
        Eigen::Matrix3f m;
        for (int k = 0; k < 9; ++k) m.data()[k] = rng() % 3 ? any_float(rng) : static_cast<float>(static_cast<int>(rng() % 7) - 3);
        SCOPED_TRACE(mat_str(m));
        ASSERT_NO_FATAL_FAILURE(check_det(m));
    }
}

// Singular by construction: integer rows r0, r1 and r2 = α r0 + β r1, rows permuted,
// then rows or columns scaled by powers of two from 2^-1070 to 2^1000; plus one-ulp
// perturbations of them (near-singular), all checked against mpq.
template <class T> void singular_suite(std::mt19937_64& rng, const std::vector<int>& scales) {
    int zeros = 0, nonzeros = 0;
    for (int it = 0; it < 6000; ++it) {
        long r[3][3];
        const long lim = rng() % 2 ? 8 : (1 << 20);
        for (int j = 0; j < 3; ++j) {
            r[0][j] = static_cast<long>(rng() % (2 * lim + 1)) - lim;
            r[1][j] = static_cast<long>(rng() % (2 * lim + 1)) - lim;
        }
        const long al = static_cast<long>(rng() % 7) - 3, be = static_cast<long>(rng() % 7) - 3;
        for (int j = 0; j < 3; ++j) r[2][j] = al * r[0][j] + be * r[1][j];
        int perm[3] = {0, 1, 2};
        std::shuffle(perm, perm + 3, rng);
        const bool by_rows = rng() % 2;
        int sc[3];
        for (int& s : sc) s = scales[rng() % scales.size()];
        Eigen::Matrix<T, 3, 3> m;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                const int e = by_rows ? sc[i] : sc[j];
                m(i, j) = static_cast<T>(std::ldexp(static_cast<T>(r[perm[i]][j]), e));
            }
        SCOPED_TRACE(mat_str(m));
        // Scaling may round a large integer in the subnormal range: then not singular.
        const mpq_class dq = det_q(m);
        ASSERT_NO_FATAL_FAILURE(check_det(m));
        (dq == 0 ? zeros : nonzeros)++;
        // Near-singular: one entry moved by one ulp.
        const int k = static_cast<int>(rng() % 9);
        m.data()[k] = std::nextafter(m.data()[k], rng() % 2 ? T(1) : T(-1));
        if (std::isfinite(m.data()[k])) {
            SCOPED_TRACE("perturbed " + std::to_string(k));
            ASSERT_NO_FATAL_FAILURE(check_det(m));
        }
        // Swapping two rows flips the sign.
        Eigen::Matrix<T, 3, 3> sw = m;
        sw.row(0).swap(sw.row(1));
        ASSERT_EQ(det3_sign(sw), -det3_sign(m));
    }
    EXPECT_GT(zeros, 4000);
    ::testing::Test::RecordProperty("nonzeros", nonzeros);
}

// Integer matrices (singular or not) scaled as a whole by one power of two across the
// double range: outside the Expansion type's range but spanning few binades, det3_sign
// rescales them first; the sign is mpq's, and the rescaled route is taken on most.
TEST(ExactDet3, UniformlyScaledAgainstMpq) {
    SEED_TRACE();
    auto rng = make_rng();
    int rescaled = 0;
    for (int it = 0; it < 6000; ++it) {
        Eigen::Matrix3d m;
        for (int k = 0; k < 9; ++k) m.data()[k] = static_cast<double>(static_cast<int>(rng() % 17) - 8);
        if (rng() % 2)  // singular: row 2 = α row 0 + β row 1
            m.row(2) = static_cast<double>(static_cast<int>(rng() % 7) - 3) * m.row(0) +
                       static_cast<double>(static_cast<int>(rng() % 7) - 3) * m.row(1);
        const int e = static_cast<int>(rng() % 2000) - 1000;
        for (int k = 0; k < 9; ++k) m.data()[k] = std::ldexp(m.data()[k], e);
        SCOPED_TRACE(mat_str(m));
        ASSERT_NO_FATAL_FAILURE(check_det(m));
        rescaled += !expansion_safe(m);
    }
    EXPECT_GT(rescaled, 4000);
}

TEST(ExactDet3, SingularAndNearSingularDouble) {
    SEED_TRACE();
    auto rng = make_rng();
    singular_suite<double>(rng, {-1070, -1050, -600, -300, -100, -53, 0, 1, 52, 100, 300, 600, 950, 1000});
}
TEST(ExactDet3, SingularAndNearSingularFloat) {
    SEED_TRACE();
    auto rng = make_rng();
    singular_suite<float>(rng, {-140, -126, -100, -24, 0, 1, 23, 60, 100});
}

TEST(ExactDet3, FilterEdgeCases) {
    // Classic near-degenerate: det = 1 ulp-ish, filter must not decide wrongly.
    Eigen::Matrix3d m;
    m << 1, 1, 1, 1, 1 + 0x1p-52, 1, 1, 1, 1 + 0x1p-52;
    EXPECT_EQ(det3_sign(m), 1);
    EXPECT_EQ(det3_sign(m), sgn(det_q(m)));
    m << 0x1p-1074, 0, 0, 0, 0x1p-1074, 0, 0, 0, 0x1p-1074;
    EXPECT_EQ(det3_sign(m), 1);
    m << 0x1p1000, 0, 0, 0, 0x1p1000, 0, 0, 0, -0x1p1000;
    EXPECT_EQ(det3_sign(m), -1);
    m.setZero();
    EXPECT_EQ(det3_sign(m), 0);
    m << 1, 2, 3, 4, 5, 6, 7, 8, std::numeric_limits<double>::infinity();
    EXPECT_EQ(det3_sign(m), 0);  // non-finite: 0 (meaningless), no crash
}

// ================================================================= slab values without expansions

// exact_sum_sign against GMP on eight doubles of the safe range that cancel: random
// terms, each followed by its negation or a neighbour of it, in shuffled order.
TEST(ExactSlabValues, SumSignAgainstMpq) {
    SEED_TRACE();
    auto rng = make_rng();
    for (int it = 0; it < 20000; ++it) {
        double x[8];
        double prev = 1;
        for (int k = 0; k < 8; k += 2) {
            prev = safe_interesting(rng, prev);
            x[k] = prev;
            const double back = rng() % 2 ? -prev : std::nextafter(-prev, rng() % 2 ? 1e308 : -1e308);
            x[k + 1] = rng() % 3 ? back : safe_interesting(rng, prev);
        }
        std::shuffle(std::begin(x), std::end(x), rng);
        const int n = 1 + static_cast<int>(rng() % 8);
        mpq_class sum = 0;
        std::string terms;
        for (int k = 0; k < n; ++k) {
            sum += Q(x[k]);
            terms += hex(x[k]) + " ";
        }
        SCOPED_TRACE(terms);
        ASSERT_EQ(exact_sum_sign(x, n), sgn(sum));
    }
}

// GrowingSum's compress against GMP: the value is unchanged, the components stay
// nonzero, nonoverlapping and increasing in magnitude, and there are no more of them;
// and sign_cross_difference on two compressed sums of products is mpq's sign, on
// exact ties (the second pair a scaled copy of the first) and near ones.
template <int N> mpq_class Q(const GrowingSum<N>& s) {
    mpq_class v = 0;
    for (int k = 0; k < s.n; ++k) v += Q(s.e[k]);
    return v;
}
template <int N> void expect_nonoverlapping(const GrowingSum<N>& s) {
    for (int k = 0; k < s.n; ++k) {
        ASSERT_NE(s.e[k], 0.0) << "component " << k;
        if (k > 0) {  // |e[k-1]| below the last nonzero bit of e[k]
            const double lsb = std::ldexp(1.0, std::ilogb(s.e[k]) - 52 + std::countr_zero(std::bit_cast<std::uint64_t>(s.e[k]) | (1ull << 52)));
            ASSERT_LT(std::abs(s.e[k - 1]), lsb) << "components " << k - 1 << " and " << k;
        }
    }
}
TEST(ExactSlabValues, CompressAndCrossDifferenceAgainstMpq) {
    SEED_TRACE();
    auto rng = make_rng();
    int ties = 0;
    for (int it = 0; it < 20000; ++it) {
        GrowingSum<16> x[2];
        GrowingSum<8> y[2];
        std::string terms;
        double prev = 1;
        for (int k = 0; k < 6; ++k) {
            prev = safe_interesting(rng, prev);
            const double f = safe_interesting(rng, 1);
            x[0].add_product(prev, f);
            terms += hex(prev) + "*" + hex(f) + " ";
        }
        for (int k = 0; k < 3; ++k) {
            prev = safe_interesting(rng, prev);
            y[0].add(prev);
            terms += "/ " + hex(prev) + " ";
        }
        SCOPED_TRACE(terms);
        const mpq_class vx = Q(x[0]), vy = Q(y[0]);
        const int nx = x[0].n;
        x[0].compress();
        y[0].compress();
        ASSERT_EQ(Q(x[0]), vx);
        ASSERT_EQ(Q(y[0]), vy);
        ASSERT_LE(x[0].n, nx);
        expect_nonoverlapping(x[0]);
        expect_nonoverlapping(y[0]);
        if (::testing::Test::HasFatalFailure()) return;
        // the second pair: the first times 2^a and 2^b (an exact tie of x/y), or with
        // one more term (a near tie)
        const int a = static_cast<int>(rng() % 9) - 4, b = static_cast<int>(rng() % 9) - 4;
        for (int k = 0; k < x[0].n; ++k) x[1].add(std::ldexp(x[0].e[k], a));
        for (int k = 0; k < y[0].n; ++k) y[1].add(std::ldexp(y[0].e[k], b));
        if (rng() % 2) x[1].add(safe_interesting(rng, 1) * 0x1p-60);
        x[1].compress();
        const std::optional<int> s = sign_cross_difference<64>(x[0], y[1], x[1], y[0]);
        const mpq_class d = Q(x[0]) * Q(y[1]) - Q(x[1]) * Q(y[0]);
        ASSERT_TRUE(s.has_value());
        ASSERT_EQ(*s, sgn(d));
        ties += d == 0;
    }
    EXPECT_GT(ties, 1000);
}

// Two slab values (p - o)/d for the comparison tests: the first from gen (d nonzero),
// the second either the first with all three numbers scaled by 2^k, |k| <= max_shift
// (an exact tie), or that tie moved by an ulp in one of them, or drawn from gen too; none
// where a scaled number fails keep or the scaled d is 0.
struct SlabValuePair {
    double p1, o1, d1, p2, o2, d2;
};
template <class Gen, class Keep>
std::optional<SlabValuePair> slab_value_pair(std::mt19937_64& rng, Gen&& gen, int max_shift, Keep&& keep) {
    const auto nonzero = [&](double prev) {
        for (;;) {
            const double d = gen(rng, prev);
            if (d != 0) return d;
            prev = 1;
        }
    };
    SlabValuePair v;
    v.p1 = gen(rng, 1), v.o1 = gen(rng, v.p1), v.d1 = nonzero(v.o1);
    if (rng() % 2) {
        const int k = static_cast<int>(rng() % static_cast<unsigned>(2 * max_shift + 1)) - max_shift;
        v.p2 = std::ldexp(v.p1, k);
        v.o2 = std::ldexp(v.o1, k);
        v.d2 = std::ldexp(v.d1, k);
        double* moved[] = {&v.p2, &v.o2, &v.d2};
        if (rng() % 2) {
            double& m = *moved[rng() % 3];
            m = std::nextafter(m, rng() % 2 ? 1e308 : -1e308);
        }
        if (!(keep(v.p2) && keep(v.o2) && keep(v.d2)) || v.d2 == 0) return std::nullopt;
    } else {
        v.p2 = gen(rng, v.p1);
        v.o2 = gen(rng, v.p2);
        v.d2 = nonzero(v.o2);
    }
    return v;
}

// compare_slab_values and compare_slab_value against GMP on slab values of the safe
// range, near ties above all: the second value the first scaled by a power of two in
// both its difference and its denominator (an exact tie), or that tie moved by an ulp
// in one of its three numbers; the constants the nearest double to a slab value and its
// neighbours, and constants whose product with d leaves the exact range: answered
// (compare_products) where p - o is a double, declined only where it is not.
TEST(ExactSlabValues, ComparisonsAgainstMpq) {
    SEED_TRACE();
    auto rng = make_rng();
    int ties = 0, declined = 0, beyond_answered = 0;
    for (int it = 0; it < 20000; ++it) {
        const std::optional<SlabValuePair> pair =
            slab_value_pair(rng, safe_interesting, 4, [](double x) { return expansion_safe(x); });
        if (!pair) continue;
        const auto [p1, o1, d1, p2, o2, d2] = *pair;
        SCOPED_TRACE(hex(p1) + " " + hex(o1) + " " + hex(d1) + " vs " + hex(p2) + " " + hex(o2) + " " + hex(d2));
        const mpq_class v1 = (Q(p1) - Q(o1)) / Q(d1), v2 = (Q(p2) - Q(o2)) / Q(d2);
        ties += v1 == v2;
        ASSERT_EQ(compare_slab_values(p1, o1, d1, p2, o2, d2), std::optional<int>(sgn(v1 - v2)));
        const double near = v1.get_d();
        for (const double t : {near, std::nextafter(near, 1e308), std::nextafter(near, -1e308), 0.0, 0x1p-1000, -0x1p1000,
                               std::numeric_limits<double>::denorm_min()}) {
            const std::optional<int> s = compare_slab_value(p1, o1, d1, t);
            if (!s) {
                ASSERT_NE(two_sum(p1, -o1).lo, 0.0) << "declined with an exact difference, t = " << hex(t);
                ++declined;
                continue;
            }
            ASSERT_EQ(*s, sgn(v1 - Q(t))) << "t = " << hex(t);
            beyond_answered += !exact_product_taken(t, two_prod(t, d1).hi);
        }
    }
    EXPECT_GT(ties, 1000) << "exact ties should be exercised";
    EXPECT_GT(beyond_answered, 1000) << "constants out of the exact range should be answered where p - o is exact";
    EXPECT_GT(declined, 1000) << "constants out of the exact range should be declined where p - o is not a double";
}

// The same comparisons at any scale (they check their own products, so that the Aabb's
// frame can ask them before rescaling): positions and directions from the whole double
// range (extreme exponents, subnormals, near-equal pairs), the second value the first
// scaled by 2^k, |k| up to 600, in all three numbers (an exact tie) or that tie moved by
// an ulp, and constants near the value. Every answer agrees with GMP; on input safe for
// expansions none declines, nor where both differences are exact; and each route is
// taken: ties of exact differences (two rounded pairs), exact differences whose
// products leave the exact range (compare_products), differences with an error term
// (the eight-term sum), answers on input outside the safe range, and declines.
TEST(ExactSlabValues, ComparisonsAtAnyScaleAgainstMpq) {
    SEED_TRACE();
    auto rng = make_rng();
    int ties = 0, with_error_term = 0, unsafe_answered = 0, declined = 0, constants_answered = 0, beyond_answered = 0;
    for (int it = 0; it < 40000; ++it) {
        const std::optional<SlabValuePair> pair =
            slab_value_pair(rng, interesting, 600, [](double x) { return std::isfinite(x); });
        if (!pair) continue;
        const auto [p1, o1, d1, p2, o2, d2] = *pair;
        SCOPED_TRACE(hex(p1) + " " + hex(o1) + " " + hex(d1) + " vs " + hex(p2) + " " + hex(o2) + " " + hex(d2));
        const mpq_class v1 = (Q(p1) - Q(o1)) / Q(d1), v2 = (Q(p2) - Q(o2)) / Q(d2);
        const bool safe = expansion_safe(p1) && expansion_safe(o1) && expansion_safe(d1) && expansion_safe(p2) &&
                          expansion_safe(o2) && expansion_safe(d2);
        const std::optional<int> s = compare_slab_values(p1, o1, d1, p2, o2, d2);
        const Pair n1 = two_sum(p1, -o1), n2 = two_sum(p2, -o2);
        const bool exact_differences = n1.lo == 0 && n2.lo == 0;
        if (!s) {
            ASSERT_FALSE(safe) << "declined on input safe for expansions";
            ASSERT_FALSE(exact_differences) << "declined with both differences exact";
            ++declined;
        } else {
            ASSERT_EQ(*s, sgn(v1 - v2));
            ties += v1 == v2;
            with_error_term += !exact_differences;
            unsafe_answered += !safe;
            beyond_answered += exact_differences && !(exact_product_taken(n1.hi, two_prod(n1.hi, d2).hi) &&
                                                      exact_product_taken(n2.hi, two_prod(n2.hi, d1).hi));
        }
        const double near = v1.get_d();
        for (const double t : {near, std::nextafter(near, 1e308), std::nextafter(near, -1e308), 0.0}) {
            if (!std::isfinite(t)) continue;
            if (const std::optional<int> c = compare_slab_value(p1, o1, d1, t)) {
                ASSERT_EQ(*c, sgn(v1 - Q(t))) << "t = " << hex(t);
                ++constants_answered;
            } else {
                ASSERT_NE(n1.lo, 0.0) << "declined against a constant with an exact difference, t = " << hex(t);
            }
        }
    }
    EXPECT_GT(ties, 1000) << "exact ties should be exercised";
    EXPECT_GT(with_error_term, 1000) << "differences with an error term should be exercised";
    EXPECT_GT(unsafe_answered, 5000) << "input outside the safe range should be answered";
    EXPECT_GT(declined, 500) << "products outside the exact range should be declined after an inexact difference";
    EXPECT_GT(beyond_answered, 500) << "exact differences should be compared beyond the exact range";
    EXPECT_GT(constants_answered, 40000) << "comparisons with constants should be exercised";
}

// compare_products: sign(x1·y1 - x2·y2) against GMP for finite doubles of any range,
// subnormals and zeros of both signs included, where the products underflow, overflow
// or tie: factors from `interesting`, pairs built to tie exactly (x2 = x1·2^k, y2 =
// y1·2^-k, where both scalings are exact) or to differ by an ulp of one factor, and
// products two binades apart (decided by exponents alone). Each route is taken: sign
// differences, exponents alone, and the rounded pairs, ties among them. split_exponent
// is checked on every factor (m·2^e == x exactly, |m| in [1, 2), m's sign x's).
TEST(ExactProducts, CompareProductsAgainstMpq) {
    SEED_TRACE();
    auto rng = make_rng();
    int by_sign = 0, by_exponent = 0, by_pairs = 0, ties = 0, out_of_range = 0;
    double prev = 1.0;
    for (int it = 0; it < 200000; ++it) {
        double x1 = interesting(rng, prev), y1 = interesting(rng, x1), x2 = interesting(rng, y1), y2 = interesting(rng, x2);
        prev = y2;
        switch (rng() % 4) {
            case 0: {  // an exact tie where both scalings are exact
                const int k = int(rng() % 41) - 20;
                const double a = std::ldexp(x1, k), b = std::ldexp(y1, -k);
                if (std::isfinite(a) && std::isfinite(b) && std::ldexp(a, -k) == x1 && std::ldexp(b, k) == y1)
                    x2 = a, y2 = b;
                break;
            }
            case 1: {  // one factor an ulp off a tie
                x2 = x1, y2 = std::nextafter(y1, (rng() & 1) ? 1e308 : -1e308);
                if (!std::isfinite(y2)) y2 = y1;
                break;
            }
            default: break;
        }
        SCOPED_TRACE(hex(x1) + " * " + hex(y1) + " vs " + hex(x2) + " * " + hex(y2));
        for (const double x : {x1, y1, x2, y2}) {
            if (x == 0) continue;
            const SplitDouble s = split_exponent(x);
            ASSERT_TRUE(std::abs(s.m) >= 1 && std::abs(s.m) < 2 && (s.m < 0) == (x < 0)) << hex(x);
            ASSERT_EQ(times_pow2(Q(s.m), s.e), Q(x)) << hex(x);
        }
        const mpq_class p = Q(x1) * Q(y1), q = Q(x2) * Q(y2);
        ASSERT_EQ(compare_products(x1, y1, x2, y2), sgn(p - q));
        const int s1 = sgn(p), s2 = sgn(q);
        if (s1 != s2 || s1 == 0) {
            ++by_sign;
        } else {
            const int k = (split_exponent(x1).e + split_exponent(y1).e) - (split_exponent(x2).e + split_exponent(y2).e);
            (k >= 2 || k <= -2 ? by_exponent : by_pairs)++;
            ties += p == q;
            const double r1 = std::abs(x1 * y1), r2 = std::abs(x2 * y2);
            out_of_range += r1 < 0x1p-1022 || r2 < 0x1p-1022 || std::isinf(r1) || std::isinf(r2);
        }
    }
    EXPECT_GT(by_sign, 10000) << "products of different signs or zero should be exercised";
    EXPECT_GT(by_exponent, 10000) << "products binades apart should be exercised";
    EXPECT_GT(by_pairs, 20000) << "products within a binade should be compared as pairs";
    EXPECT_GT(ties, 5000) << "exact ties should be exercised";
    EXPECT_GT(out_of_range, 5000) << "products that underflow or overflow should be compared";
}

// unscaled_faithful: a faithful double for q from f, a faithful double for 2^shift·q
// (a rescaled copy's rounding scaled back). For random normal f (below the largest
// double: ±max may be a clamp) and q' = 2^shift·q at f or strictly between f and one of
// its neighbours (a third, two thirds, or nearly all the way), with shifts that put
// the result in range, in the subnormal range, or beyond the largest double (the
// boundaries drawn often), every answer is a faithful rounding of q (±max beyond the
// range, as faithful_quotient answers it), and each route is taken: exact scalings,
// ±max beyond the range, and declines (inexact scalings, results near the top whose
// side of the largest double f does not decide).
TEST(ExactScale, UnscaledFaithfulAgainstMpq) {
    SEED_TRACE();
    auto rng = make_rng();
    std::uniform_int_distribution<int> exponent(-1022, 1022), wide(-1100, 1100), boundary(0, 10);
    const int edges[] = {1022, 1023, 1024, 1025, -1021, -1022, -1023, -1073, -1074, -1075, -1076};
    int exact = 0, beyond = 0, declined = 0;
    for (int it = 0; it < 40000; ++it) {
        const double m = 1 + std::ldexp(double(rng() >> 12), -52);  // [1, 2)
        const int e = exponent(rng), k = (rng() & 1) ? wide(rng) : edges[boundary(rng)];
        const double f = std::ldexp((rng() & 1) ? -m : m, e);
        const int shift = e - k;  // f·2^-shift about 2^k
        const double toward = (rng() & 1) ? std::nextafter(f, HUGE_VAL) : std::nextafter(f, -HUGE_VAL);
        const int third = int(rng() % 4);
        const mpq_class frac = third == 3 ? mpq_class(1023, 1024) : mpq_class(third, 3);
        const mpq_class q = times_pow2(Q(f) + frac * (Q(toward) - Q(f)), -shift);
        SCOPED_TRACE("f = " + hex(f) + ", shift " + std::to_string(shift) + ", q' at " + frac.get_str() + " towards " +
                     hex(toward));
        const std::optional<double> r = unscaled_faithful(f, shift);
        if (!r) {
            ++declined;
            continue;
        }
        ASSERT_TRUE(faithful(*r, q));
        (std::abs(*r) == std::numeric_limits<double>::max() ? beyond : exact)++;
    }
    EXPECT_GT(exact, 10000) << "exact scalings should be exercised";
    EXPECT_GT(beyond, 1000) << "results beyond the largest double should be answered";
    EXPECT_GT(declined, 1000) << "inexact scalings should be declined";
}

// ================================================================= with_exact

TEST(ExactDispatch, RerunsWithBigDyadicOnOverflow) {
    int expansion_runs = 0, big_runs = 0;
    auto alg = [&](auto tag) -> std::optional<int> {
        using E = typename decltype(tag)::type;
        (is_expansion_v<E> ? expansion_runs : big_runs)++;
        E s(0.0);
        for (int k = 0; k < 10; ++k) s += std::ldexp(1.0, -60 * k);  // 10 components
        s -= 1.0;
        if (s.overflowed()) return std::nullopt;
        return s.sign();
    };
    EXPECT_EQ(with_exact<4>(true, alg), std::optional<int>(1));
    EXPECT_EQ(expansion_runs, 1);
    EXPECT_EQ(big_runs, 1);
    EXPECT_EQ(with_exact<16>(true, alg), std::optional<int>(1));
    EXPECT_EQ(expansion_runs, 2);
    EXPECT_EQ(big_runs, 1);
    EXPECT_EQ(with_exact(false, alg), std::optional<int>(1));
    EXPECT_EQ(expansion_runs, 2);
    EXPECT_EQ(big_runs, 2);
    EXPECT_EQ(any_overflowed(Expansion<4>(1.0), BigDyadic(2.0)), false);
    EXPECT_EQ(any_overflowed(Expansion<4>(1.0), BigDyadic(std::numeric_limits<double>::infinity())), true);
}

}  // namespace
