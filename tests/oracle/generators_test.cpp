// generators_test.cpp — the shared generators deliver what their names promise, judged by
// the exact oracle: the invalid families make only invalid inputs and the others only valid
// ones; exact grazing cases stay exact in T after translation and power-of-two scaling (every
// box grazing ray touches its corner or edge: an exact hit; every sphere grazing ray is an
// exact tangent: t_enter == t_exit; every plane grazing ray lies in the plane: the whole
// range); parallel box cases carry a ±0 direction component; the special-value table holds
// the values it names; exact_scale is exact; seeds reproduce cases.
#include "oracle_test_support.hpp"

namespace {

using namespace rayproof;
using namespace rayproof::oracle_test;

template <class T> class Generators : public ::testing::Test {};
TYPED_TEST_SUITE(Generators, Scalars, ScalarNames);

constexpr int kCases = 3000;

template <class T, class Shape, class F> void for_cases(std::string_view name, F&& f) {
    const auto* g = gen::find_generator<T, Shape>(name);
    ASSERT_NE(g, nullptr) << name;
    gen::Rng rng(0x9e4e ^ gen::name_hash(name));
    for (int i = 0; i < kCases; ++i) {
        const auto c = g->make(rng);
        ASSERT_EQ(c.generator, name);
        f(c, oracle::exact(c.ray, c.shape));
    }
}

template <class T, class Shape> void validity_matches_names() {
    for (const auto& g : gen::generators<T, Shape>()) {
        int invalid = 0;
        for_cases<T, Shape>(g.name, [&](const auto&, const auto& e) { invalid += e.verdict == Verdict::invalid; });
        if (g.name == "invalid") {
            EXPECT_EQ(invalid, kCases) << gen::shape_name<Shape>();
        } else if (g.name == "log_uniform") {
            EXPECT_LT(invalid, kCases / 100) << gen::shape_name<Shape>();
        } else {
            EXPECT_EQ(invalid, 0) << gen::shape_name<Shape>() << ' ' << g.name;
        }
    }
}

TYPED_TEST(Generators, ValidityMatchesTheirNames) {
    using T = TypeParam;
    validity_matches_names<T, Aabb<T>>();
    validity_matches_names<T, Obb<T>>();
    validity_matches_names<T, Plane<T>>();
    validity_matches_names<T, Sphere<T>>();
}

TYPED_TEST(Generators, BoxGrazingRaysTouchExactly) {
    using T = TypeParam;
    for_cases<T, Aabb<T>>("grazing", [](const auto& c, const auto& e) { EXPECT_EQ(e.verdict, Verdict::hit) << c; });
    for_cases<T, Obb<T>>("grazing", [](const auto& c, const auto& e) { EXPECT_EQ(e.verdict, Verdict::hit) << c; });
}

TYPED_TEST(Generators, SphereGrazingRaysAreExactTangents) {
    using T = TypeParam;
    for_cases<T, Sphere<T>>("grazing", [](const auto& c, const auto& e) {
        ASSERT_EQ(e.verdict, Verdict::hit) << c;
        EXPECT_TRUE(e.t_enter == e.t_exit) << c << '\n' << e;
    });
}

TYPED_TEST(Generators, PlaneGrazingRaysLieInThePlane) {
    using T = TypeParam;
    for_cases<T, Plane<T>>("grazing", [](const auto& c, const auto& e) {
        ASSERT_EQ(e.verdict, Verdict::hit) << c;
        EXPECT_EQ(e.enter_vs(c.ray.t_min), oracle::Order::equal) << c << '\n' << e;
        EXPECT_EQ(e.exit_vs(c.ray.t_max), oracle::Order::equal) << c << '\n' << e;
    });
}

TYPED_TEST(Generators, NearGrazingMovesOffTheGrazingCase) {
    using T = TypeParam;
    // The sphere tangents nudged by one ulp: now either a miss or a proper chord (or still a
    // touch when the nudge lands outside the range); at least some of each must occur.
    int miss = 0, chord = 0;
    for_cases<T, Sphere<T>>("near_grazing", [&](const auto&, const auto& e) {
        miss += e.verdict == Verdict::miss;
        chord += e.verdict == Verdict::hit && !(e.t_enter == e.t_exit);
    });
    EXPECT_GT(miss, kCases / 10);
    EXPECT_GT(chord, kCases / 10);
}

TYPED_TEST(Generators, ParallelBoxRaysHaveSignedZeroComponents) {
    using T = TypeParam;
    int negative_zero = 0;
    for_cases<T, Aabb<T>>("parallel", [&](const auto& c, const auto&) {
        const auto& d = c.ray.direction;
        EXPECT_TRUE(d[0] == 0 || d[1] == 0 || d[2] == 0) << c;
        for (int i = 0; i < 3; ++i) negative_zero += d[i] == 0 && std::signbit(d[i]);
    });
    EXPECT_GT(negative_zero, kCases / 10);
}

TYPED_TEST(Generators, SpecialValuesAreWhatTheySay) {
    using T = TypeParam;
    using L = std::numeric_limits<T>;
    const auto& v = gen::special_values<T>();
    const auto has = [&](T x) {
        for (const T y : v)
            if (std::memcmp(&x, &y, sizeof(T)) == 0) return true;
        return false;
    };
    EXPECT_TRUE(has(T(0)));
    EXPECT_TRUE(has(-T(0)));
    EXPECT_TRUE(has(L::denorm_min()));
    EXPECT_TRUE(has(-L::denorm_min()));
    EXPECT_TRUE(has(std::nextafter(L::min(), T(0))));
    EXPECT_TRUE(has(L::min()));
    EXPECT_TRUE(has(L::max()));
    EXPECT_TRUE(has(-L::max()));
    for (const T x : v) EXPECT_TRUE(std::isfinite(x));
    const auto n = gen::one_ulp_neighbours(T(1));
    EXPECT_EQ(n[0], T(1) - L::epsilon() / 2);
    EXPECT_EQ(n[1], T(1) + L::epsilon());
    // log_uniform covers denormals and both ends of the exponent range.
    gen::Rng rng(5);
    int denormal = 0, huge = 0;
    for (int i = 0; i < 20000; ++i) {
        const T x = gen::log_uniform<T>(rng);
        ASSERT_TRUE(std::isfinite(x));
        denormal += x != 0 && std::abs(x) < L::min();
        huge += std::abs(x) > L::max() / 4;
    }
    EXPECT_GT(denormal, 0);
    EXPECT_GT(huge, 0);
}

TYPED_TEST(Generators, ExactScaleIsExactOrRefused) {
    using T = TypeParam;
    const auto* g = gen::find_generator<T, Aabb<T>>("general");
    gen::Rng rng(11);
    int refused = 0;
    for (int i = 0; i < kCases; ++i) {
        const auto c = g->make(rng);
        const int e = std::numeric_limits<T>::max_exponent + 40;
        const int k = int(gen::uniform_int(rng, -e, e));
        auto s = c;
        if (!gen::exact_scale(s, k, k)) {
            ++refused;
            EXPECT_TRUE(s.ray.origin == c.ray.origin && s.shape.lo == c.shape.lo) << "refused but modified";
            continue;
        }
        const auto a = oracle::exact(c.ray, c.shape), b = oracle::exact(s.ray, s.shape);
        ASSERT_EQ(a.verdict, b.verdict) << c << '\n' << s;
        if (a.verdict == Verdict::hit) {
            EXPECT_TRUE(a.t_enter == b.t_enter) << c << '\n' << s;
            EXPECT_TRUE(a.t_exit == b.t_exit) << c << '\n' << s;
            EXPECT_EQ(a.face, b.face);
        }
    }
    EXPECT_GT(refused, 0);
    EXPECT_LT(refused, kCases);
}

TYPED_TEST(Generators, SeedsReproduceCases) {
    using T = TypeParam;
    for (const auto& g : gen::generators<T, Sphere<T>>()) {
        const auto a = gen::make_case<T, Sphere<T>>(g.name, 1234), b = gen::make_case<T, Sphere<T>>(g.name, 1234);
        std::ostringstream sa, sb;
        sa << a;
        sb << b;
        EXPECT_EQ(sa.str(), sb.str());
    }
}

}  // namespace
