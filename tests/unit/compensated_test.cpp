// Unit tests of rayproof/detail/compensated.hpp (the double-word stage between the
// interval filter and exact arithmetic) against GMP rationals:
//   - CompensatedSum: whenever ok(), |hi + lo - exact sum| <= bound(), on random sums
//     of products over the whole exponent range and on sums built to cancel;
//   - residual_sign: whenever it decides, it is the exact sign of N - g·D, including
//     at the neighbours of N/D and where N - g·D is tiny or zero;
//   - compensated_faithful_quotient: whenever it answers, the answer is a faithful
//     rounding of N/D, exactly N/D when that is a double; and on generic input it does
//     answer (the stage is not dead), while exact midpoints and exactly representable
//     quotients never produce a wrong double;
//   - SphereQuadratic::compensated_sign_at: whenever it decides, it is the exact sign of
//     q(g) (sign_at), at the floats around both roots, where q changes sign;
//   - lanes::exact_product: hi + lo is the exact product in both lanes, over the range
//     its callers guard (zeros, short and full mantissas, products near 2^-900);
//   - plane_pin (the certified plane's straight-line path): every claim it makes is
//     exact (t strictly between c's neighbours, the rough enclosure, t == 0, a ray in
//     or parallel to the plane), on generic, cancelling, nearly parallel, integer and
//     wide-exponent input; and it pins nearly every generic crossing (not dead).
// Every random test is seeded: RAYPROOF_SEED=<decimal> in the environment replays a run;
// the seed is printed with every failure.
#include <rayproof/detail/compensated.hpp>
#include <rayproof/io.hpp>
#include <rayproof/rayproof.hpp>

#include "seeded.hpp"

#include <gmpxx.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace rayproof::detail;

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

// A sum of products with its exact value: `terms` products x·y (and one plain term).
struct Sum {
    CompensatedSum cs;
    mpq_class exact = 0;
    std::string text;
};
Sum random_sum(std::mt19937_64& rng, int terms, int e) {
    Sum s;
    const double c = random_double(rng, e);
    s.cs.add(c);
    s.exact += Q(c);
    s.text = hex(c);
    for (int i = 0; i < terms; ++i) {
        const double x = random_double(rng, e / 2), y = random_double(rng, e / 2);
        s.cs.add_product(x, y);
        s.exact += Q(x) * Q(y);
        s.text += " + " + hex(x) + "*" + hex(y);
    }
    return s;
}
// A sum that cancels: c - Σ x_i y_i with c the rounded value of the products' sum.
Sum cancelling_sum(std::mt19937_64& rng, int terms, int e) {
    std::vector<double> x(terms), y(terms);
    double approx = 0;
    for (int i = 0; i < terms; ++i) {
        x[i] = random_double(rng, e / 2);
        y[i] = random_double(rng, e / 2);
        approx += x[i] * y[i];
    }
    Sum s;
    s.cs.add(approx);
    s.exact += Q(approx);
    s.text = hex(approx);
    for (int i = 0; i < terms; ++i) {
        s.cs.add_product(-x[i], y[i]);
        s.exact -= Q(x[i]) * Q(y[i]);
        s.text += " - " + hex(x[i]) + "*" + hex(y[i]);
    }
    return s;
}

// A sum whose terms spread over ~300 binades around 2^`center`: the two_sum errors are
// then of many magnitudes and their floating-point sum c is rarely exact.
Sum spread_sum(std::mt19937_64& rng, int terms, int center) {
    Sum s;
    for (int i = 0; i < terms; ++i) {
        const double x = std::ldexp(random_double(rng, 150), center);
        s.cs.add(x);
        s.exact += Q(x);
        s.text += (i ? " + " : "") + hex(x);
    }
    return s;
}

TEST(CompensatedSum, BoundHoldsOnSpreadTerms) {
    SEED_TRACE();
    auto rng = make_rng();
    int inexact = 0;
    for (int it = 0; it < 20000; ++it) {
        const Sum s = spread_sum(rng, 3 + int(rng() % 20), int(rng() % 1200) - 600);
        if (!s.cs.ok()) continue;
        const mpq_class err = abs_q(Q(s.cs.hi()) + Q(s.cs.lo()) - s.exact);
        inexact += err != 0;
        ASSERT_LE(err, Q(s.cs.bound())) << s.text;
    }
    EXPECT_GT(inexact, 1000);  // the bound is exercised, not only exact sums
}

TEST(CompensatedSum, BoundHoldsWheneverOk) {
    SEED_TRACE();
    auto rng = make_rng();
    int ok = 0;
    for (int it = 0; it < 20000; ++it) {
        const int e = (it % 3 == 0) ? 1000 : (it % 3 == 1 ? 60 : 400);
        const int terms = 1 + int(rng() % 12);
        const Sum s = (it % 2) ? random_sum(rng, terms, e) : cancelling_sum(rng, terms, e);
        if (!s.cs.ok()) continue;
        ++ok;
        const mpq_class err = abs_q(Q(s.cs.hi()) + Q(s.cs.lo()) - s.exact);
        ASSERT_LE(err, Q(s.cs.bound())) << s.text;
    }
    EXPECT_GT(ok, 10000);  // most random sums are in range (the test checks something)
}

TEST(CompensatedSum, GuardsRejectInexactProducts) {
    CompensatedSum tiny;
    tiny.add_product(0x1p-600, 0x1.8p-600);  // product far below 2^-916: error term may be lost
    EXPECT_FALSE(tiny.ok());
    CompensatedSum zero;
    zero.add_product(0.0, 0x1p-1074);  // an exact zero is fine
    zero.add(1.0);
    EXPECT_TRUE(zero.ok());
    CompensatedSum huge;
    huge.add(0x1p1010);
    EXPECT_FALSE(huge.ok());
    CompensatedSum nan;
    nan.add_product(0x1p1000, 0x1p1000);  // overflow
    EXPECT_FALSE(nan.ok());
}

// The residual's decided signs are exact, at random g and at the neighbours of N/D.
TEST(CompensatedQuotient, ResidualSignIsExactWhenDecided) {
    SEED_TRACE();
    auto rng = make_rng();
    int decided = 0, tried = 0;
    for (int it = 0; it < 20000; ++it) {
        const int e = (it % 2) ? 60 : 300;
        const Sum n = (it % 3 == 0) ? cancelling_sum(rng, 3, e) : random_sum(rng, 3, e);
        const Sum d = random_sum(rng, 3, e);
        if (!n.cs.ok() || !d.cs.ok() || d.exact == 0 || d.cs.hi() == 0) continue;
        const double t = n.cs.hi() / d.cs.hi();
        const double gs[] = {t, step_up(t), step_down(t), random_double(rng, e)};
        for (double g : gs) {
            if (!std::isfinite(g)) continue;
            ++tried;
            const int s = residual_sign(n.cs, d.cs, n.cs.bound(), d.cs.bound(), g);
            if (s == 2) continue;
            ++decided;
            ASSERT_EQ(s, sgn(n.exact - Q(g) * d.exact)) << "N = " << n.text << "\nD = " << d.text << "\ng = " << hex(g);
        }
    }
    EXPECT_GT(decided, tried / 2);
}

// N = g·D + δ with δ tiny (down to far below the double-word precision) or zero:
// sign(N - g·D) = sign(δ), the hardest residuals; a decided sign must be that one.
TEST(CompensatedQuotient, ResidualSignNearZero) {
    SEED_TRACE();
    auto rng = make_rng();
    int decided = 0, wrong_if_unbounded = 0;
    for (int it = 0; it < 20000; ++it) {
        const int e = 40;
        const double g = random_double(rng, e);
        CompensatedSum d, n;
        mpq_class D = 0, N = 0;
        std::string text;
        for (int j = 0; j < 3; ++j) {
            const double x = random_double(rng, e), y = random_double(rng, e);
            d.add_product(x, y);
            D += Q(x) * Q(y);
            // g·x·y as exact pieces: (g·x) split exactly, times y split exactly
            const Pair gx = two_prod(g, x);
            n.add_product(gx.hi, y);
            n.add_product(gx.lo, y);
            N += Q(g) * Q(x) * Q(y);
            text += hex(x) + "*" + hex(y) + " ";
        }
        const int k = int(rng() % 140);
        const double delta = (rng() % 5 == 0) ? 0.0 : std::ldexp(random_double(rng, 0), -k) * std::abs(n.hi() + 1);
        n.add(delta);
        N += Q(delta);
        if (!n.ok() || !d.ok() || D == 0) continue;
        const int s = residual_sign(n, d, n.bound(), d.bound(), g);
        // Would the computed residual alone (no bound) have the right sign?
        const double r = n.hi() + n.lo() - g * d.hi();
        wrong_if_unbounded += (r > 0) - (r < 0) != sgn(N - Q(g) * D);
        if (s == 2) continue;
        ++decided;
        ASSERT_EQ(s, sgn(N - Q(g) * D)) << "D = " << text << "\ng = " << hex(g) << " delta = " << hex(delta);
    }
    EXPECT_GT(decided, 5000);
    EXPECT_GT(wrong_if_unbounded, 0);  // the cases are hard enough that bounds matter
}

::testing::AssertionResult faithful(double r, const mpq_class& q) {
    if (!std::isfinite(r)) return ::testing::AssertionFailure() << "non-finite " << hex(r);
    if (Q(step_down(r)) < q && q < Q(step_up(r))) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << hex(r) << " is not a faithful rounding of " << q.get_d();
}

TEST(CompensatedQuotient, FaithfulWheneverAnswered) {
    SEED_TRACE();
    auto rng = make_rng();
    int answered = 0, generic = 0;
    for (int it = 0; it < 20000; ++it) {
        const int e = (it % 4 == 0) ? 600 : 60;
        const Sum n = (it % 5 == 0) ? cancelling_sum(rng, 3, e) : random_sum(rng, 3, e);
        const Sum d = random_sum(rng, 3, e);
        if (!n.cs.ok() || !d.cs.ok() || d.exact == 0) continue;
        const mpq_class q = n.exact / d.exact;
        const std::optional<double> r = compensated_faithful_quotient(n.cs, d.cs, sgn(d.exact));
        if (it % 4 != 0 && it % 5 != 0) ++generic;
        if (!r) continue;
        if (it % 4 != 0 && it % 5 != 0) ++answered;
        ASSERT_TRUE(faithful(*r, q)) << "N = " << n.text << "\nD = " << d.text;
    }
    // Generic, well-scaled input is the stage's whole purpose: it must decide nearly always.
    EXPECT_GT(answered, generic * 99 / 100) << answered << " of " << generic;
}

// Exactly representable quotients come back exactly (or not at all); exact midpoints
// between two doubles give one of the two.
TEST(CompensatedQuotient, RepresentableAndMidpointQuotients) {
    SEED_TRACE();
    auto rng = make_rng();
    int answered = 0;
    for (int it = 0; it < 5000; ++it) {
        const double x = random_double(rng, 40), y = random_double(rng, 40);
        const double z = random_double(rng, 40);  // t = x exactly for N = x·y·z, D = y·z
        // D = y·z held exactly as a two-term sum, N = x·D as exact products.
        const Pair yz = two_prod(y, z);
        CompensatedSum d, n, n2, d2;
        d.add(yz.hi);
        d.add(yz.lo);
        n.add_product(x, yz.hi);
        n.add_product(x, yz.lo);
        if (!n.ok() || !d.ok()) continue;
        const mpq_class D = Q(yz.hi) + Q(yz.lo);
        const std::optional<double> r = compensated_faithful_quotient(n, d, sgn(D));
        if (r) {
            ++answered;
            EXPECT_EQ(*r, x) << hex(x) << " " << hex(y) << " " << hex(z);
        }
        // midpoint: N = (2x + gap)·D, D' = 2·D, t = x + gap/2
        const double gap = step_up(x) - x;
        n2.add_product(2 * x, yz.hi);
        n2.add_product(2 * x, yz.lo);
        n2.add_product(gap, yz.hi);
        n2.add_product(gap, yz.lo);
        d2.add(2 * yz.hi);
        d2.add(2 * yz.lo);
        if (!n2.ok() || !d2.ok()) continue;
        const mpq_class q = (Q(2 * x) + Q(gap)) * D / (2 * D);
        if (const std::optional<double> m = compensated_faithful_quotient(n2, d2, sgn(D))) {
            EXPECT_TRUE(faithful(*m, q));
        }
    }
    // At a representable t the residuals at its neighbours are D times one gap: decided.
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
                const int c = q.compensated_sign_at(g);
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
