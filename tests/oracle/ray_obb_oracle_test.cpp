// ray_obb_oracle_test.cpp — the oracle's ray/Obb answers: non-unit, negated, rotated and
// sheared axes with hand-computed intervals and faces (side 0 is (p - c)·a_i == -h_i, ties
// to the lowest column), flat boxes (zero half extents on one, two or three axes: a
// parallelogram, a segment, a point), exact dependence of the axes (invalid) versus a
// one-ulp escape from it (valid), every invalid class; identity-axis boxes agree exactly
// with the Aabb oracle; and, over every generator, over flat copies of its cases and over
// constructed flat boxes that rays hit exactly, the oracle and the kernel's certified
// mode agree with CGAL's own answer (the box frame's Iso_cuboid_3: verdict, exact t,
// face) and, where it applies, with CGAL on the box cut into six exact tetrahedra.
#include "oracle_test_support.hpp"

namespace {

using namespace rayproof;
using namespace rayproof::oracle_test;

template <class T> class ObbOracle : public ::testing::Test {};
TYPED_TEST_SUITE(ObbOracle, Scalars, ScalarNames);

// The matrix with columns a, b, c (Eigen's comma initializer puts vectors side by side).
template <class T> Mat3<T> cols(Vec3<T> a, Vec3<T> b, Vec3<T> c) { return (Mat3<T>() << a, b, c).finished(); }

TYPED_TEST(ObbOracle, NonUnitAndNegatedAxes) {
    using T = TypeParam;
    const Ray<T> r{{-3, 0, 0}, {1, 0, 0}};
    // axes 2·I, half extents 2: the box [-1, 1]³.
    expect_answer(oracle::exact(r, Obb<T>{{0, 0, 0}, Mat3<T>::Identity() * T(2), {2, 2, 2}}), "2", "4", 0);
    // a_0 = -x: the plane (p - c)·a_0 == -h_0 is x == +1, so the ray enters on side 1.
    expect_answer(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>({-1, 0, 0}, {0, 1, 0}, {0, 0, 1}), {1, 1, 1}}), "2", "4", 1);
}

TYPED_TEST(ObbOracle, RotatedSquareTiesToTheLowestColumn) {
    using T = TypeParam;
    // |x + y| <= 2, |y - x| <= 2, |z| <= 1: a square with corners (±2, 0), (0, ±2).
    const Ray<T> r{{-5, 0, 0}, {1, 0, 0}};
    expect_answer(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>({1, 1, 0}, {-1, 1, 0}, {0, 0, 1}), {2, 2, 1}}), "3", "7", 0);
    // The same box with the tying columns moved to 1 and 2: face 2·1 + 0.
    expect_answer(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>({0, 0, 1}, {1, 1, 0}, {-1, 1, 0}), {1, 2, 2}}), "3", "7", 2);
}

TYPED_TEST(ObbOracle, ShearedAxes) {
    using T = TypeParam;
    // |x| <= 1, |x + y| <= 1, |z| <= 1, the ray along +y at x = 0: parallel to slab 0.
    const Obb<T> b{{0, 0, 0}, cols<T>({1, 0, 0}, {1, 1, 0}, {0, 0, 1}), {1, 1, 1}};
    expect_answer(oracle::exact(Ray<T>{{0, -5, 0}, {0, 1, 0}}, b), "4", "6", 2);
    // Off-centre by a translation.
    const Obb<T> moved{{10, 20, 30}, b.axes, b.half_extent};
    expect_answer(oracle::exact(Ray<T>{{10, 15, 30}, {0, 3, 0}}, moved), "4/3", "2", 2);
}

TYPED_TEST(ObbOracle, DependenceIsDecidedExactly) {
    using T = TypeParam;
    const Ray<T> r{{-5, 0, 0}, {1, 0, 0}};
    const Vec3<T> a0(1, 2, 3), a1(-2, 1, 4);
    EXPECT_EQ(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>(a0, a1, a0 + a1), {1, 1, 1}}).verdict, Verdict::invalid);
    EXPECT_EQ(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>(a0, a1, Vec3<T>::Zero()), {1, 1, 1}}).verdict, Verdict::invalid);
    EXPECT_EQ(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>(a0, T(-3) * a0, a1), {1, 1, 1}}).verdict, Verdict::invalid);
    // Scaled into the denormal range, still exactly dependent.
    const T s = std::ldexp(T(1), std::numeric_limits<T>::min_exponent - 8);
    EXPECT_EQ(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>(s * a0, s * a1, s * (a0 + a1)), {1, 1, 1}}).verdict,
              Verdict::invalid);
    // One ulp away from dependence: valid.
    Vec3<T> a2 = a0 + a1;
    a2[1] = std::nextafter(a2[1], T(10));
    EXPECT_NE(oracle::exact(r, Obb<T>{{0, 0, 0}, cols<T>(a0, a1, a2), {1, 1, 1}}).verdict, Verdict::invalid);
    EXPECT_TRUE(oracle::valid(Obb<T>{{0, 0, 0}, cols<T>(a0, a1, a2), {1, 1, 1}}));
}

TYPED_TEST(ObbOracle, EveryInvalidClass) {
    using T = TypeParam;
    const Obb<T> b{{0, 0, 0}, Mat3<T>::Identity(), {1, 1, 1}};
    const Ray<T> r{{-3, 0, 0}, {1, 0, 0}};
    expect_invalid_ray_classes(r, b);
    Obb<T> bad = b;
    bad.half_extent[2] = -std::numeric_limits<T>::denorm_min();
    EXPECT_EQ(oracle::exact(r, bad).verdict, Verdict::invalid);
    bad = b;
    bad.axes(1, 2) = nan<T>();
    EXPECT_EQ(oracle::exact(r, bad).verdict, Verdict::invalid);
    bad = b;
    bad.center[0] = inf<T>();
    EXPECT_EQ(oracle::exact(r, bad).verdict, Verdict::invalid);
    bad = b;
    bad.half_extent[0] = inf<T>();
    EXPECT_EQ(oracle::exact(r, bad).verdict, Verdict::invalid);
    bad = b;
    bad.half_extent[1] = -T(0);  // -0 is not negative: a flat, valid box
    expect_answer(oracle::exact(r, bad), "2", "4", 0);
}

// Identity axes, centre (lo+hi)/2 and half extents (hi-lo)/2 describe the same box as the
// Aabb when those are exact: the answers must be identical (values, faces).
template <class T> bool exact_center(const Aabb<T>& a, Obb<T>& o) {
    o.axes = Mat3<T>::Identity();
    for (int i = 0; i < 3; ++i) {
        const T s = a.lo[i] + a.hi[i], d = a.hi[i] - a.lo[i];
        // Exact iff the rounding error (TwoSum) is zero and halving loses no bit.
        const T bs = s - a.lo[i], es = (a.lo[i] - (s - bs)) + (a.hi[i] - bs);
        const T bd = d - a.hi[i], ed = (a.hi[i] - (d - bd)) + (-a.lo[i] - bd);
        if (!std::isfinite(s) || !std::isfinite(d) || es != 0 || ed != 0) return false;
        o.center[i] = s / 2;
        o.half_extent[i] = d / 2;
        if (o.center[i] * 2 != s || o.half_extent[i] * 2 != d) return false;
    }
    return true;
}

TYPED_TEST(ObbOracle, IdentityAxesAgreeWithTheAabbOracle) {
    using T = TypeParam;
    int compared = 0;
    for (const auto& g : gen::generators<T, Aabb<T>>()) {
        gen::Rng rng(0x0bb ^ gen::name_hash(g.name));
        for (int i = 0; i < 300; ++i) {
            const auto c = g.make(rng);
            Obb<T> o;
            if (!oracle::valid(c.shape) || !exact_center(c.shape, o)) continue;
            const auto ea = oracle::exact(c.ray, c.shape), eo = oracle::exact(c.ray, o);
            ++compared;
            ASSERT_EQ(ea.verdict, eo.verdict) << c;
            if (ea.verdict != Verdict::hit) continue;
            EXPECT_EQ(ea.face, eo.face) << c;
            EXPECT_TRUE(ea.t_enter == eo.t_enter) << c << '\n' << ea << '\n' << eo;
            EXPECT_TRUE(ea.t_exit == eo.t_exit) << c << '\n' << ea << '\n' << eo;
        }
    }
    EXPECT_GT(compared, 1000);
}

TYPED_TEST(ObbOracle, FlatBoxes) {
    using T = TypeParam;
    // |x| <= 0, |y| <= 1, |z| <= 1: the unit square in the plane x = 0.
    const Obb<T> square{{0, 0, 0}, Mat3<T>::Identity(), {0, 1, 1}};
    expect_answer(oracle::exact(Ray<T>{{-3, 0, 0}, {1, 0, 0}}, square), "3", "3", 0);
    expect_answer(oracle::exact(Ray<T>{{3, 0, 0}, {-1, 0, 0}}, square), "3", "3", 1);
    expect_answer(oracle::exact(Ray<T>{{-3, 1, 1}, {1, 0, 0}}, square), "3", "3", 0);  // its corner
    EXPECT_EQ(oracle::exact(Ray<T>{{-3, 2, 0}, {1, 0, 0}}, square).verdict, Verdict::miss);
    // Lying in the square's plane: slab 0 is parallel, slab 1 is entered at y = -1.
    expect_answer(oracle::exact(Ray<T>{{0, -3, 0}, {0, 1, 0}}, square), "2", "4", 2);
    EXPECT_EQ(oracle::exact(Ray<T>{{std::numeric_limits<T>::denorm_min(), -3, 0}, {0, 1, 0}}, square).verdict,
              Verdict::miss);
    // A segment along z (rotated axes: |x + y| <= 0, |y - x| <= 0, |z| <= 2).
    const Obb<T> segment{{0, 0, 0}, cols<T>({1, 1, 0}, {-1, 1, 0}, {0, 0, 1}), {0, 0, 2}};
    expect_answer(oracle::exact(Ray<T>{{-3, 0, 1}, {1, 0, 0}}, segment), "3", "3", 0);  // slabs 0 and 1 tie
    expect_answer(oracle::exact(Ray<T>{{0, -3, 1}, {0, 1, 0}}, segment), "3", "3", 0);   // 0 entered, 1 exited
    expect_answer(oracle::exact(Ray<T>{{0, 0, -5}, {0, 0, 2}}, segment), "3/2", "7/2", 4);
    EXPECT_EQ(oracle::exact(Ray<T>{{-3, 0, 3}, {1, 0, 0}}, segment).verdict, Verdict::miss);
    // A point: every slab is entered at the same t, the lowest axis wins; face -1 from it.
    const Obb<T> point{{1, 2, 3}, cols<T>({2, 0, 0}, {0, 0, 3}, {0, -1, 0}), {0, 0, 0}};
    expect_answer(oracle::exact(Ray<T>{{0, 0, 0}, {1, 2, 3}}, point), "1", "1", 0);
    expect_answer(oracle::exact(Ray<T>{{1, 0, 3}, {0, 1, 0}}, point), "2", "2", 5);  // d·a_2 < 0: side 1
    expect_answer(oracle::exact(Ray<T>{{1, 4, 3}, {0, -1, 0}}, point), "2", "2", 4);
    expect_answer(oracle::exact(Ray<T>{{1, 2, 3}, {0, -1, 0}}, point), "0", "0", -1);
    EXPECT_EQ(oracle::exact(Ray<T>{{0, 0, 0}, {1, 2, std::nextafter(T(3), T(4))}}, point).verdict, Verdict::miss);
    // CGAL and the certified mode on the same cases.
    Coverage cov;
    for (const auto& [r, b] : {std::pair{Ray<T>{{-3, 0, 0}, {1, 0, 0}}, square}, {Ray<T>{{0, -3, 0}, {0, 1, 0}}, square},
                               {Ray<T>{{-3, 0, 1}, {1, 0, 0}}, segment}, {Ray<T>{{0, -3, 1}, {0, 1, 0}}, segment},
                               {Ray<T>{{0, 0, -5}, {0, 0, 2}}, segment}, {Ray<T>{{0, 0, 0}, {1, 2, 3}}, point},
                               {Ray<T>{{1, 0, 3}, {0, 1, 0}}, point}, {Ray<T>{{1, 4, 3}, {0, -1, 0}}, point},
                               {Ray<T>{{1, 2, 3}, {0, -1, 0}}, point}})
        EXPECT_EQ(disagreement(r, b, cov), "") << r << ' ' << b;
    EXPECT_EQ(cov.hits, 9);
}

TYPED_TEST(ObbOracle, AgreesWithCgalOnEveryGenerator) {
    using T = TypeParam;
    crosscheck_all_generators<T, Obb<T>>(kCrosscheckCases / 2);
}

// The generators' cases made flat: the half extents of 1, 2 or all 3 axes set to zero
// (the seven non-empty axis sets in turn).
TYPED_TEST(ObbOracle, FlatCopiesAgreeWithCgalOnEveryGenerator) {
    using T = TypeParam;
    for (const auto& g : gen::generators<T, Obb<T>>()) {
        const auto flat = [](gen::Case<T, Obb<T>> c, int i) {
            const unsigned mask = 1u + unsigned(i % 7);
            for (int k = 0; k < 3; ++k)
                if (mask & (1u << k)) c.shape.half_extent[k] = 0;
            return c;
        };
        const Coverage cov =
            crosscheck_cases<T, Obb<T>>(g.name, 0xf1a7 ^ gen::name_hash(g.name), kCrosscheckCases / 4, g.make, flat);
        EXPECT_EQ(cov.failures, 0) << g.name;
    }
}

// Flat Obbs that rays hit exactly: integer axes, the half extents of the axes in a
// non-empty set F zero and the others integers; the point p = c + w lies in the flat box
// (w·a_i == 0 for i in F: w = 0, a multiple of a_i × a_j, or a_i × u), on its rim when a
// drawn margin is 0; the ray passes through p at the integer parameter s, or through p
// moved by a unit step (mostly a miss), sometimes along the flat plane (d·a_i == 0).
// Every number is an integer below 2^24, exact in float and double, then scaled by a
// random power of two.
template <class T> gen::Case<T, Obb<T>> flat_obb(gen::Rng& rng, unsigned mask) {
    using namespace gen;
    for (;;) {
        const IMat3 a = integer_axes(rng);
        int f[3], nf = 0;
        for (int i = 0; i < 3; ++i)
            if (mask & (1u << i)) f[nf++] = i;
        I3 w = {0, 0, 0};
        if (nf == 2) w = mul(uniform_int(rng, -2, 2), cross(a.col[f[0]], a.col[f[1]]));
        if (nf == 1) w = cross(a.col[f[0]], random_nonzero_i3(rng, 3));
        I3 h;
        for (int i = 0; i < 3; ++i) h[i] = (mask & (1u << i)) ? 0 : std::abs(dot(w, a.col[i])) + uniform_int(rng, 0, 3);
        const I3 center = random_i3(rng, -8, 8);
        I3 p = add(center, w);
        if (chance(rng, 1, 4)) p = add(p, random_nonzero_i3(rng, 1));
        I3 d = random_nonzero_i3(rng, 6);
        if (nf < 3 && chance(rng, 1, 4)) {  // along the flat plane of a flat axis
            const int i = f[below(rng, unsigned(nf))];
            d = cross(a.col[i], random_nonzero_i3(rng, 3));
        }
        if (is_zero(d)) continue;
        const std::int64_t s = uniform_int(rng, 0, 6);
        const I3 origin = sub(p, mul(s, d));
        if (!representable<T>(h) || !representable<T>(origin) || !representable<T>(center) || !representable<T>(d)) continue;
        Case<T, Obb<T>> c{{}, {}, "flat"};
        c.shape.center = to_vec<T>(center);
        c.shape.axes = to_mat<T>(a);
        c.shape.half_extent = to_vec<T>(h);
        c.ray.origin = to_vec<T>(origin);
        c.ray.direction = to_vec_signed_zeros<T>(d, rng);
        special_t_range(c.ray, rng, narrow<T>(s));
        random_exact_scaling(c, rng);
        return c;
    }
}

TYPED_TEST(ObbOracle, ConstructedFlatBoxesAgreeWithCgal) {
    using T = TypeParam;
    for (unsigned mask = 1; mask < 8; ++mask) {
        const std::string name = "flat mask " + std::to_string(mask);
        const Coverage cov = crosscheck_cases<T, Obb<T>>(
            name, 0xf1a7b0c5 + mask, kCrosscheckCases / 4, [mask](gen::Rng& rng) { return flat_obb<T>(rng, mask); },
            [](const gen::Case<T, Obb<T>>& c, int) { return c; });
        EXPECT_EQ(cov.failures, 0) << name;
        // Most rays go through a point of the box: hits, and entries through a face.
        EXPECT_GT(cov.hits, cov.checked / 2) << name;
        EXPECT_GT(cov.faces, cov.checked / 4) << name;
    }
}

}  // namespace
