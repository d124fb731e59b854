// closest_hit / any_hit over many primitives by brute force (rayproof/closest.hpp), the
// exact entry order under it (detail/entry_order.hpp) and the primitives' enclosing boxes
// (detail/primitive_bounds.hpp), over float and double. Covers:
//   - ties go to the lowest index in every mode: duplicates, and equal exact entries
//     reached through different faces of different boxes;
//   - certified closest_hit orders entries that are equal or adjacent floats exactly
//     (a box face at fl(1/3) against one at exactly 1/3; a box at fl(3 − r) against the
//     sphere whose exact entry is 3 − r), whichever index holds the closer one;
//   - spheres touching boxes, planes crossed and planes containing the ray (t_enter =
//     t_min), t_min = −inf with a half-space and a plane that hold the whole ray;
//   - invalid primitives are skipped, the ray alone decides `invalid`, empty scenes miss;
//   - seeded random scenes of every shape: in every mode the answer agrees with the
//     per-shape queries (verdict, the winner's Hit bit for bit, the smallest t_enter with
//     the lowest index for fast / conservative, compare_entry's order for certified, the
//     lowest hit for any_hit); the Ray and PreparedRay forms agree;
//   - the certified and conservative answers are the same under every rounding mode;
//   - in general position on moderate input no query of any shape, in any mode, computes
//     a subnormal number (the underflow flag stays clear): those cost microcode assists;
//   - enclosing_box contains the solid, judged by the kernel itself: for seeded rays from
//     outside, a hit on the solid is a hit on the box no later (certified hits, exact
//     order); rays leaving each face of the box outward miss the solid (certified); and
//     nullopt exactly where promised (planes, invalid, overflow, unbounded, empty).
// Every random case is seeded (RAYPROOF_SEED=<decimal> replays, seeded.hpp) and prints
// the ray and the primitives in hexadecimal when it fails.
#include "seeded.hpp"

#include <rayproof/detail/primitive_bounds.hpp>
#include <rayproof/rayproof.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cfenv>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace rayproof;
using namespace rayproof::testing;

namespace {

std::uint64_t base_seed() {
    static const std::uint64_t s = env_seed_or(20261203);
    return s;
}
std::mt19937_64 make_rng() { return rng_for_current_test(base_seed()); }

template <class T> bool same_bits(T a, T b) { return std::memcmp(&a, &b, sizeof(T)) == 0; }
template <class T> bool same_hit(const Hit<T>& a, const Hit<T>& b) {
    return a.verdict == b.verdict && same_bits(a.t_enter, b.t_enter) && same_bits(a.t_exit, b.t_exit) && a.face == b.face;
}

template <class T> std::string describe(const Ray<T>& r, std::span<const Primitive<T>> prims) {
    std::ostringstream os;
    os << "ray " << r << "\n";
    for (std::size_t i = 0; i < prims.size(); ++i) {
        os << "  [" << i << "] ";
        std::visit([&](const auto& s) { os << s; }, prims[i]);
        os << "\n";
    }
    return os.str();
}

template <class T> Vec3<T> v3(double x, double y, double z) { return Vec3<T>(T(x), T(y), T(z)); }

// A scene owns the planes of its polyhedra (a ConvexPolyhedron does not).
template <class T> struct Scene {
    std::vector<std::unique_ptr<std::vector<Plane<T>>>> planes;
    std::vector<Primitive<T>> prims;
    ConvexPolyhedron<T> poly(std::vector<Plane<T>> p) {
        planes.push_back(std::make_unique<std::vector<Plane<T>>>(std::move(p)));
        return ConvexPolyhedron<T>{std::span<const Plane<T>>(*planes.back())};
    }
};

// The six planes of the box [lo, hi] (an Aabb as a polyhedron).
template <class T> std::vector<Plane<T>> box_planes(const Vec3<T>& lo, const Vec3<T>& hi) {
    std::vector<Plane<T>> p;
    for (int i = 0; i < 3; ++i) {
        Vec3<T> n = Vec3<T>::Zero();
        n[i] = -1;
        p.push_back({n, -lo[i]});
        n[i] = 1;
        p.push_back({n, hi[i]});
    }
    return p;
}

// Sign of x − y for y = num/den of small integers, exactly.
template <class T> int sign_minus_ratio(T x, double num, double den) {
    using B = detail::BigDyadic;
    return (B(x) * B(den) - B(num)).sign() * (den > 0 ? 1 : -1);
}

template <class T> class Closest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Closest, Scalars);

// Each mode's answer on one scene, with the Ray and PreparedRay forms compared.
template <class T, class Mode> ClosestHit<T> closest_in(const Ray<T>& r, std::span<const Primitive<T>> p, Mode m) {
    const ClosestHit<T> a = closest_hit(r, p, m), b = closest_hit(PreparedRay<T>(r), p, m);
    EXPECT_EQ(a.verdict, b.verdict);
    EXPECT_EQ(a.index, b.index);
    EXPECT_TRUE(same_hit(a.hit, b.hit) || (std::is_same_v<Mode, fast_t>));
    return a;
}

template <class T, class Mode> void check_against_shapes(const Ray<T>& r, std::span<const Primitive<T>> p, Mode m);

// The hand cases use small integers, so fast mode computes every t exactly and must pick
// the exact winner too; a conservative t_enter is only a lower bound (an exact tie need not
// stay one), so conservative is held to its own t_enter order (check_against_shapes).
template <class T> void expect_index_all_modes(const Ray<T>& r, std::span<const Primitive<T>> p, std::int64_t want) {
    SCOPED_TRACE(describe(r, p));
    EXPECT_EQ(closest_in(r, p, certified).index, want) << "certified";
    EXPECT_EQ(closest_in(r, p, fast).index, want) << "fast";
    check_against_shapes(r, p, conservative);
    EXPECT_TRUE(closest_in(r, p, conservative)) << "conservative";
}

TYPED_TEST(Closest, TiesGoToTheLowestIndex) {
    using T = TypeParam;
    const Ray<T> r{v3<T>(0, 0, 0), v3<T>(3, 6, 1)};
    const Aabb<T> box{v3<T>(1, -10, -10), v3<T>(5, 10, 10)};  // enters at x = 1: t = 1/3
    std::vector<Primitive<T>> dup{box, box, box};
    expect_index_all_modes<T>(r, dup, 0);
    // The same exact entry 1/3 through the y face of another box.
    const Aabb<T> other{v3<T>(-10, 2, -10), v3<T>(10, 5, 10)};
    std::vector<Primitive<T>> ab{box, other}, ba{other, box};
    const ClosestHit<T> c = closest_hit(r, std::span<const Primitive<T>>(ab), certified);
    ASSERT_TRUE(c);
    EXPECT_EQ(c.hit.face, 0);
    expect_index_all_modes<T>(r, ab, 0);
    expect_index_all_modes<T>(r, ba, 0);
    const PreparedRay<T> pr(r);
    const Hit<T> hb = intersect(pr, box, certified), ho = intersect(pr, other, certified);
    EXPECT_EQ(detail::compare_entry<T>(pr, box, hb, other, ho), 0);
    EXPECT_EQ(detail::compare_entry<T>(pr, other, ho, box, hb), 0);
    // any_hit: the lowest primitive hit.
    std::vector<Primitive<T>> miss_first{Aabb<T>{v3<T>(50, 50, 50), v3<T>(60, 60, 60)}, other, box};
    for (const auto& h : {any_hit(r, std::span<const Primitive<T>>(miss_first), certified),
                          any_hit(r, std::span<const Primitive<T>>(miss_first), conservative),
                          any_hit(r, std::span<const Primitive<T>>(miss_first), fast)}) {
        EXPECT_EQ(h.verdict, Verdict::hit);
        EXPECT_EQ(h.index, 1);
    }
}

TYPED_TEST(Closest, AdjacentFloatsAreOrderedExactly) {
    using T = TypeParam;
    // Ray along +z from 0: a face at z = fl(1/3) against one at z = 1/3 exactly (reached
    // as (1 - 0)/3 through a ray with d_x = 3).
    const Ray<T> r{v3<T>(0, 0, 0), v3<T>(3, 0, 1)};
    const T third = T(1) / T(3);
    const Aabb<T> rounded{v3<T>(-10, -10, third), v3<T>(10, 10, 10)};  // t = fl(1/3)
    const Aabb<T> exact{v3<T>(1, -10, -10), v3<T>(10, 10, 10)};       // t = 1/3
    const int s = sign_minus_ratio(third, 1, 3);                          // fl(1/3) − 1/3
    ASSERT_NE(s, 0);
    const PreparedRay<T> pr(r);
    const Hit<T> hr = intersect(pr, rounded, certified), he = intersect(pr, exact, certified);
    ASSERT_TRUE(hr && he);
    EXPECT_EQ(detail::compare_entry_filter(hr.t_enter, he.t_enter), 0) << "the floats alone must not decide";
    EXPECT_EQ(detail::compare_entry<T>(pr, rounded, hr, exact, he), s);
    EXPECT_EQ(detail::compare_entry<T>(pr, exact, he, rounded, hr), -s);
    std::vector<Primitive<T>> re{rounded, exact}, er{exact, rounded};
    EXPECT_EQ(closest_hit(r, std::span<const Primitive<T>>(re), certified).index, s < 0 ? 0 : 1);
    EXPECT_EQ(closest_hit(r, std::span<const Primitive<T>>(er), certified).index, s < 0 ? 1 : 0);
    // The same against a sphere: center (0,0,3) on the ray d = (0,0,1), radius rad; exact
    // entry 3 − rad, and a box face at fl(3 − rad).
    const T rad = T(0.7);
    const Ray<T> rz{v3<T>(0, 0, 0), v3<T>(0, 0, 1)};
    const Sphere<T> sph{v3<T>(0, 0, 3), rad};
    const Aabb<T> face{v3<T>(-1, -1, T(3) - rad), v3<T>(1, 1, 9)};
    using B = detail::BigDyadic;
    const int s2 = (B(face.lo[2]) - (B(3.0) - B(rad))).sign();  // box entry − sphere entry
    const PreparedRay<T> pz(rz);
    const Hit<T> hs = intersect(pz, sph, certified), hf = intersect(pz, face, certified);
    ASSERT_TRUE(hs && hf);
    EXPECT_EQ(detail::compare_entry<T>(pz, face, hf, sph, hs), s2);
    EXPECT_EQ(detail::compare_entry<T>(pz, sph, hs, face, hf), -s2);
    std::vector<Primitive<T>> fs{face, sph}, sf{sph, face};
    EXPECT_EQ(closest_hit(rz, std::span<const Primitive<T>>(fs), certified).index, s2 <= 0 ? 0 : 1);
    EXPECT_EQ(closest_hit(rz, std::span<const Primitive<T>>(sf), certified).index, s2 < 0 ? 1 : 0);
}

TYPED_TEST(Closest, SpheresTouchingBoxes) {
    using T = TypeParam;
    const Ray<T> r{v3<T>(0, 0, 0), v3<T>(0, 0, 1)};
    const Sphere<T> s{v3<T>(0, 0, 3), T(1)};                   // entry t = 2
    const Aabb<T> b{v3<T>(-1, -1, 2), v3<T>(1, 1, 5)};         // entry t = 2, face 4
    const Sphere<T> far{v3<T>(0, 0, 10), T(1)};                // entry t = 9
    std::vector<Primitive<T>> sb{far, s, b}, bs{far, b, s};
    expect_index_all_modes<T>(r, sb, 1);
    expect_index_all_modes<T>(r, bs, 1);
    // Two spheres tangent to the plane z = 2 from the same side, one much larger.
    const Sphere<T> big{v3<T>(0, 0, 1002), T(1000)};
    std::vector<Primitive<T>> two{big, s}, owt{s, big};
    expect_index_all_modes<T>(r, two, 0);
    expect_index_all_modes<T>(r, owt, 0);
    const PreparedRay<T> pr(r);
    EXPECT_EQ(detail::compare_entry<T>(pr, big, intersect(pr, big, certified), s, intersect(pr, s, certified)), 0);
    // A ray starting inside a sphere: entry t_min, against a box that also holds the start.
    const Ray<T> in{v3<T>(0, 0, T(2.5)), v3<T>(1, 0, 0)};
    std::vector<Primitive<T>> held{Aabb<T>{v3<T>(5, -1, 0), v3<T>(6, 1, 5)}, b, s};
    const ClosestHit<T> c = closest_hit(in, std::span<const Primitive<T>>(held), certified);
    EXPECT_EQ(c.index, 1);
    EXPECT_EQ(c.hit.t_enter, T(0));
    EXPECT_EQ(c.hit.face, -1);
}

TYPED_TEST(Closest, Planes) {
    using T = TypeParam;
    const Ray<T> r{v3<T>(0, 0, 0), v3<T>(1, 0, 0), T(-1), T(100)};
    const Plane<T> lying{v3<T>(0, 0, 1), T(0)};   // holds the whole ray: t_enter = t_min = -1
    const Plane<T> crossed{v3<T>(1, 0, 0), T(2)};  // x = 2: t = 2
    const Aabb<T> box{v3<T>(2, -1, -1), v3<T>(3, 1, 1)};  // t = 2
    const Aabb<T> holding{v3<T>(-5, -1, -1), v3<T>(3, 1, 1)};  // holds the start: t = -1
    std::vector<Primitive<T>> a{box, crossed, lying};
    expect_index_all_modes<T>(r, a, 2);
    const ClosestHit<T> c = closest_hit(r, std::span<const Primitive<T>>(a), certified);
    EXPECT_EQ(c.hit.t_enter, T(-1));
    std::vector<Primitive<T>> b{crossed, box};
    expect_index_all_modes<T>(r, b, 0);
    std::vector<Primitive<T>> d{box, lying, holding};
    expect_index_all_modes<T>(r, d, 1);
    // t_min = -inf: a half-space and a plane holding the whole ray enter at -inf, a tie;
    // both are below every finite entry.
    const Ray<T> all{v3<T>(0, 0, 0), v3<T>(1, 0, 0), -std::numeric_limits<T>::infinity(), T(100)};
    Scene<T> sc;
    const ConvexPolyhedron<T> half = sc.poly({Plane<T>{v3<T>(0, 0, 1), T(1)}});
    std::vector<Primitive<T>> e{box, half, lying}, f{box, lying, half};
    expect_index_all_modes<T>(all, e, 1);
    expect_index_all_modes<T>(all, f, 1);
    const ClosestHit<T> g = closest_hit(all, std::span<const Primitive<T>>(e), certified);
    EXPECT_EQ(g.hit.t_enter, -std::numeric_limits<T>::infinity());
}

TYPED_TEST(Closest, InvalidPrimitivesAreSkippedAndTheRayDecidesInvalid) {
    using T = TypeParam;
    const T nan = std::numeric_limits<T>::quiet_NaN();
    Scene<T> sc;
    const Primitive<T> bad[] = {
        Aabb<T>{v3<T>(1, 1, 1), v3<T>(0, 0, 0)},                      // lo > hi
        Sphere<T>{v3<T>(0, 0, nan), T(1)},                            // NaN
        Sphere<T>{v3<T>(0, 0, 3), T(-1)},                             // negative radius
        Plane<T>{v3<T>(0, 0, 0), T(1)},                               // zero normal
        Obb<T>{v3<T>(0, 0, 3), Mat3<T>::Zero(), v3<T>(1, 1, 1)},     // dependent axes
        sc.poly({Plane<T>{v3<T>(0, 0, nan), T(1)}}),                  // NaN plane
    };
    const Ray<T> r{v3<T>(0, 0, 0), v3<T>(0, 0, 1)};
    std::vector<Primitive<T>> only_bad(std::begin(bad), std::end(bad));
    for (const auto& c : {closest_in(r, std::span<const Primitive<T>>(only_bad), certified),
                          closest_in(r, std::span<const Primitive<T>>(only_bad), conservative),
                          closest_in(r, std::span<const Primitive<T>>(only_bad), fast),
                          any_hit(r, std::span<const Primitive<T>>(only_bad), certified),
                          any_hit(r, std::span<const Primitive<T>>(only_bad), conservative),
                          any_hit(r, std::span<const Primitive<T>>(only_bad), fast)}) {
        EXPECT_EQ(c.verdict, Verdict::miss);
        EXPECT_EQ(c.index, -1);
    }
    std::vector<Primitive<T>> mixed(std::begin(bad), std::end(bad));
    mixed.push_back(Sphere<T>{v3<T>(0, 0, 10), T(1)});
    mixed.insert(mixed.begin() + 2, Aabb<T>{v3<T>(-1, -1, 4), v3<T>(1, 1, 5)});
    expect_index_all_modes<T>(r, mixed, 2);
    for (const auto& c : {any_hit(r, std::span<const Primitive<T>>(mixed), certified),
                          any_hit(r, std::span<const Primitive<T>>(mixed), conservative),
                          any_hit(r, std::span<const Primitive<T>>(mixed), fast)})
        EXPECT_EQ(c.index, 2);
    // Invalid rays: invalid whatever the primitives, index -1.
    const Ray<T> invalid_rays[] = {
        {v3<T>(0, 0, 0), v3<T>(0, 0, 0)},
        {v3<T>(0, nan, 0), v3<T>(0, 0, 1)},
        {v3<T>(0, 0, 0), v3<T>(0, 0, 1), T(2), T(1)},
        {v3<T>(0, 0, 0), v3<T>(0, 0, 1), std::numeric_limits<T>::infinity()},
    };
    std::vector<Primitive<T>> none;
    for (const Ray<T>& ir : invalid_rays)
        for (const auto* scene : {&mixed, &none}) {
            const std::span<const Primitive<T>> p(*scene);
            for (const auto& c : {closest_in(ir, p, certified), closest_in(ir, p, conservative), closest_in(ir, p, fast),
                                  any_hit(ir, p, certified), any_hit(ir, p, conservative), any_hit(ir, p, fast)}) {
                EXPECT_EQ(c.verdict, Verdict::invalid) << ir;
                EXPECT_EQ(c.index, -1);
                EXPECT_FALSE(bool(c));
            }
        }
    // An empty scene misses.
    EXPECT_EQ(closest_hit(r, std::span<const Primitive<T>>(none), certified).verdict, Verdict::miss);
    EXPECT_EQ(any_hit(r, std::span<const Primitive<T>>(none), fast).verdict, Verdict::miss);
}

// ---- Seeded random scenes -------------------------------------------------------------

template <class T> struct Gen {
    explicit Gen(std::mt19937_64& rng, bool with_integers = true) : g(rng), integers(with_integers) {}
    std::mt19937_64& g;
    bool integers;  // false: reals only (general position)
    double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(g); }
    int pick(int n) { return int(std::uniform_int_distribution<int>(0, n - 1)(g)); }
    // Small integers half the time (ties and shared faces), reals otherwise.
    T coord() { return integers && pick(2) == 0 ? T(pick(9) - 4) : T(uni(-4, 4)); }
    Vec3<T> point() { return Vec3<T>{coord(), coord(), coord()}; }
    Vec3<T> unit() {
        for (;;) {
            const Eigen::Vector3d d{uni(-1, 1), uni(-1, 1), uni(-1, 1)};
            const double n = d.norm();
            if (n > 0.1 && n <= 1) return (d / n).cast<T>();
        }
    }
    Mat3<T> rotation() {
        const Eigen::Quaterniond q{uni(-1, 1), uni(-1, 1), uni(-1, 1), uni(-1, 1)};
        return q.normalized().toRotationMatrix().cast<T>();
    }
    Primitive<T> primitive(Scene<T>& sc) {
        const Vec3<T> c = point();
        switch (pick(6)) {
            case 0: {
                const Vec3<T> e{T(pick(3)), T(pick(3)), T(pick(3))};
                return Aabb<T>{c, Vec3<T>(c + e)};
            }
            case 1: return Obb<T>{c, rotation(), Vec3<T>{T(uni(0, 2)), T(uni(0, 2)), T(uni(0, 2))}};
            case 2: return Sphere<T>{c, pick(2) == 0 ? T(pick(3)) : T(uni(0, 2))};
            case 3: {
                // A box's planes rotated: a bounded polyhedron around c.
                const Mat3<T> R = rotation();
                std::vector<Plane<T>> p;
                for (int i = 0; i < 3; ++i)
                    for (int s : {-1, 1}) {
                        const Vec3<T> n = (R.col(i) * T(s)).eval();
                        p.push_back({n, T(n.dot(c) + uni(0.1, 2))});
                    }
                return sc.poly(std::move(p));
            }
            case 4: return Plane<T>{unit(), coord()};
            default: return Aabb<T>{Vec3<T>(c - Vec3<T>::Ones()), Vec3<T>(c + Vec3<T>::Ones())};
        }
    }
    // n random primitives into sc.
    void fill(Scene<T>& sc, int n) {
        for (int i = 0; i < n; ++i) sc.prims.push_back(primitive(sc));
    }
    Ray<T> ray() {
        Ray<T> r{point(), Vec3<T>::Zero()};
        while (r.direction.isZero()) r.direction = Vec3<T>(point() - r.origin);
        if (pick(4) == 0) r.t_min = T(uni(-1, 1));
        if (pick(4) == 0) r.t_max = T(uni(1, 3));
        return r;
    }
};

template <class T, class Mode> void check_against_shapes(const Ray<T>& r, std::span<const Primitive<T>> p, Mode m) {
    SCOPED_TRACE(std::string(mode_name(m)) + "\n" + describe(r, p));
    const PreparedRay<T> pr(r);
    std::vector<Hit<T>> h;
    for (const Primitive<T>& x : p) h.push_back(detail::intersect_primitive(pr, x, m));
    const ClosestHit<T> c = closest_in(r, p, m), a = any_hit(r, p, m);
    std::int64_t lowest = -1;
    for (std::size_t i = 0; i < h.size() && lowest < 0; ++i)
        if (h[i]) lowest = std::int64_t(i);
    EXPECT_EQ(a.index, lowest);
    if (lowest < 0) {
        EXPECT_EQ(c.verdict, Verdict::miss);
        EXPECT_EQ(c.index, -1);
        EXPECT_EQ(a.verdict, Verdict::miss);
        return;
    }
    EXPECT_TRUE(same_hit(a.hit, h[std::size_t(lowest)]));
    ASSERT_EQ(c.verdict, Verdict::hit);
    ASSERT_GE(c.index, 0);
    const std::size_t w = std::size_t(c.index);
    ASSERT_TRUE(h[w]);
    EXPECT_TRUE(same_hit(c.hit, h[w]) || (std::is_same_v<Mode, fast_t>)) << c.hit << " vs " << h[w];
    for (std::size_t j = 0; j < h.size(); ++j) {
        if (!h[j] || j == w) continue;
        if constexpr (std::is_same_v<Mode, certified_t>) {
            const int s = detail::compare_entry<T>(pr, p[w], h[w], p[j], h[j]);
            EXPECT_EQ(s, -detail::compare_entry<T>(pr, p[j], h[j], p[w], h[w])) << "antisymmetric, j = " << j;
            if (j < w)
                EXPECT_LT(s, 0) << "j = " << j;
            else
                EXPECT_LE(s, 0) << "j = " << j;
        } else {
            if (j < w)
                EXPECT_LT(h[w].t_enter, h[j].t_enter) << "j = " << j;
            else
                EXPECT_LE(h[w].t_enter, h[j].t_enter) << "j = " << j;
        }
    }
}

TYPED_TEST(Closest, RandomScenesAgreeWithThePerShapeQueries) {
    using T = TypeParam;
    RAYPROOF_SEED_TRACE(base_seed());
    auto rng = make_rng();
    Gen<T> gen{rng};
    int hits = 0;
    for (int scene = 0; scene < 150; ++scene) {
        Scene<T> sc;
        gen.fill(sc, 1 + gen.pick(12));
        const std::span<const Primitive<T>> p(sc.prims);
        for (int k = 0; k < 20; ++k) {
            const Ray<T> r = gen.ray();
            check_against_shapes(r, p, certified);
            check_against_shapes(r, p, conservative);
            check_against_shapes(r, p, fast);
            const ClosestHit<T> cert = closest_hit(r, p, certified), cons = closest_hit(r, p, conservative);
            if (cert) {
                ++hits;
                EXPECT_TRUE(cons) << "conservative missed a certified hit\n" << describe(r, p);
            }
            if (::testing::Test::HasFailure()) return;
        }
    }
    EXPECT_GT(hits, 500) << "the scenes must be hit often enough to test the order";
}

// The certified and conservative answers do not depend on the caller's rounding mode:
// closest_hit and any_hit answer in the default environment (detail/fp_env.hpp), the
// exact order included.
TYPED_TEST(Closest, DirectedRoundingGivesTheSameAnswers) {
    using T = TypeParam;
    RAYPROOF_SEED_TRACE(base_seed());
    auto rng = make_rng();
    Gen<T> gen{rng};
    int compared = 0;
    for (int scene = 0; scene < 40; ++scene) {
        Scene<T> sc;
        gen.fill(sc, 2 + gen.pick(10));
        const std::span<const Primitive<T>> p(sc.prims);
        for (int k = 0; k < 10; ++k) {
            const Ray<T> r = gen.ray();
            const ClosestHit<T> cert = closest_hit(r, p, certified), cons = closest_hit(r, p, conservative);
            const ClosestHit<T> any = any_hit(r, p, certified);
            for (const int mode : {FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO}) {
                ASSERT_EQ(std::fesetround(mode), 0);
                const ClosestHit<T> c2 = closest_hit(r, p, certified), k2 = closest_hit(r, p, conservative);
                const ClosestHit<T> a2 = any_hit(r, p, certified);
                ASSERT_EQ(std::fesetround(FE_TONEAREST), 0);
                EXPECT_TRUE(c2.index == cert.index && same_hit(c2.hit, cert.hit)) << "rounding " << mode << "\n" << describe(r, p);
                EXPECT_TRUE(k2.index == cons.index && same_hit(k2.hit, cons.hit)) << "rounding " << mode << "\n" << describe(r, p);
                EXPECT_TRUE(a2.index == any.index && same_hit(a2.hit, any.hit)) << "rounding " << mode << "\n" << describe(r, p);
                ++compared;
            }
            if (::testing::Test::HasFailure()) return;
        }
    }
    EXPECT_EQ(compared, 40 * 10 * 3);
}

// In general position on moderate input (the scenes above with real coordinates only,
// within [-4, 4]) no query of any shape computes a subnormal number: the underflow flag
// stays clear through each primitive's verdict and Hit and through closest_hit, in every
// mode. A subnormal intermediate is slow, not wrong (a microcode assist of about a
// hundred cycles per operation on x86 with flush-to-zero off, as the certified modes
// require): the sphere's verdict filter once added 2^-1072·|d|² to its bound and spent
// half its time there. Special positions still may (an exit at t = 0 exactly, widened by
// 2^-1022 and rounded to float; the double sphere's residual bound where every rounding
// error is 0): rare, and answered correctly. Which primitive and mode raised the flag is
// printed.
TYPED_TEST(Closest, GeneralPositionComputesNoSubnormal) {
    using T = TypeParam;
    RAYPROOF_SEED_TRACE(base_seed());
    auto rng = make_rng();
    Gen<T> gen{rng, false};
    int queries = 0;
    const auto raised = [] { return std::fetestexcept(FE_UNDERFLOW) != 0; };
    for (int scene = 0; scene < 60; ++scene) {
        Scene<T> sc;
        gen.fill(sc, 1 + gen.pick(12));
        const std::span<const Primitive<T>> p(sc.prims);
        for (int k = 0; k < 10; ++k) {
            const Ray<T> r = gen.ray();
            const auto each_mode = [&](auto mode, const char* name) {
                for (std::size_t i = 0; i < p.size(); ++i) {
                    std::feclearexcept(FE_ALL_EXCEPT);
                    const Verdict v = std::visit([&](const auto& s) { return verdict(r, s, mode); }, p[i]);
                    const Hit<T> h = std::visit([&](const auto& s) { return intersect(r, s, mode); }, p[i]);
                    EXPECT_FALSE(raised()) << name << ", primitive " << i << " (verdict " << int(v) << ", hit "
                                           << int(h.verdict) << ")\n" << describe(r, p);
                    ++queries;
                }
                std::feclearexcept(FE_ALL_EXCEPT);
                const ClosestHit<T> c = closest_hit(r, p, mode);
                EXPECT_FALSE(raised()) << name << ", closest_hit (index " << c.index << ")\n" << describe(r, p);
            };
            each_mode(fast, "fast");
            each_mode(conservative, "conservative");
            each_mode(certified, "certified");
            if (::testing::Test::HasFailure()) return;
        }
    }
    EXPECT_GT(queries, 5000);
}

// ---- enclosing_box ----------------------------------------------------------------------

// The box contains the solid, judged by the kernel's certified queries and the exact
// entry order: a ray from outside that hits the solid hits the box no later, and rays
// leaving the box through a face (origin on the face, t_min the least positive float)
// miss the solid.
template <class T> void expect_box_holds(const Primitive<T>& p, Gen<T>& gen, double scale) {
    std::ostringstream os;
    std::visit([&](const auto& s) { os << s; }, p);
    SCOPED_TRACE(os.str());
    const std::optional<Aabb<T>> ob = detail::enclosing_box(p);
    ASSERT_TRUE(ob.has_value());
    const Aabb<T> b = *ob;
    ASSERT_TRUE((b.lo.array() <= b.hi.array()).all()) << b;
    const Primitive<T> bp = b;
    const Vec3<T> mid = ((b.lo + b.hi) / T(2)).eval();
    const T radius = T((b.hi - b.lo).norm());
    for (int k = 0; k < 60; ++k) {
        // From a point outside the box towards a point near (or inside) the solid.
        const Vec3<T> from = (mid + gen.unit() * T(2) * radius).eval();
        const Vec3<T> towards = gen.unit();
        const Vec3<T> to = (mid + towards * T(gen.uni(0, 0.6)) * radius).eval();
        const Ray<T> r{from, Vec3<T>(to - from)};
        if (r.direction.isZero()) continue;
        const PreparedRay<T> pr(r);
        const Hit<T> hs = detail::intersect_primitive(pr, p, certified);
        if (!hs) continue;
        const Hit<T> hb = intersect(pr, b, certified);
        ASSERT_TRUE(hb) << "the solid is hit, its box is not: " << r << " box " << b;
        EXPECT_LE(detail::compare_entry<T>(pr, bp, hb, p, hs), 0) << r << " box " << b << " " << hb << " solid " << hs;
    }
    // Outward rays from each face, through the middle and random points of the face.
    const T tiny = std::numeric_limits<T>::denorm_min();
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side)
            for (int k = 0; k < 12; ++k) {
                Vec3<T> o = mid;
                if (k > 0)
                    for (int j = 0; j < 3; ++j) o[j] = T(b.lo[j] + (b.hi[j] - b.lo[j]) * T(gen.uni(0, 1)));
                o[axis] = side == 0 ? b.lo[axis] : b.hi[axis];
                Vec3<T> d = Vec3<T>::Zero();
                d[axis] = side == 0 ? T(-scale) : T(scale);
                const Ray<T> r{o, d, tiny};
                EXPECT_FALSE(detail::intersect_primitive(PreparedRay<T>(r), p, certified))
                    << "the solid leaves the box: " << r << " box " << b;
            }
}

TYPED_TEST(Closest, EnclosingBoxHoldsTheSolid) {
    using T = TypeParam;
    RAYPROOF_SEED_TRACE(base_seed());
    auto rng = make_rng();
    Gen<T> gen{rng};
    const int far_exp = std::is_same_v<T, float> ? 40 : 500;
    for (const int e : {0, -20, 20, -far_exp, far_exp}) {
        const double s = std::ldexp(1.0, e);
        SCOPED_TRACE("scale 2^" + std::to_string(e));
        for (int k = 0; k < 25; ++k) {
            Scene<T> sc;
            // Every draw in its own statement, so that every compiler draws the same cases.
            const Vec3<T> c = (gen.point().template cast<double>() * s).template cast<T>();
            const T radius = T(gen.uni(0, 2) * s);
            const Mat3<T> R1 = gen.rotation();
            const Vec3<T> h1{T(gen.uni(0, 2) * s), T(gen.uni(0, 2) * s), T(gen.uni(0, 2) * s)};
            const Mat3<T> R2 = gen.rotation();
            const T k0 = T(gen.uni(0.5, 3)), k1 = T(gen.uni(0.5, 3));
            const Mat3<T> skew = (R2 * Eigen::DiagonalMatrix<T, 3>(k0, k1, T(1)) + Mat3<T>::Identity() * T(0.25)).eval();
            const Vec3<T> h2{T(gen.uni(0, 2) * s), T(gen.uni(0, 2) * s), T(gen.uni(0, 2) * s)};
            std::vector<Plane<T>> planes;  // tangent to spheres around c: a bounded polyhedron
            const int count = 4 + gen.pick(8);
            for (int i = 0; i < count; ++i) {
                const Vec3<T> n = gen.unit();
                planes.push_back({n, T(n.template cast<double>().dot(c.template cast<double>()) + gen.uni(0.5, 2) * s)});
            }
            for (const Vec3<T>& n : {v3<T>(1, 1, 1), v3<T>(-1, 1, 1), v3<T>(0, -1, 1), v3<T>(0, 0, -1)})
                planes.push_back({n, T(n.template cast<double>().dot(c.template cast<double>()) + 2 * s)});
            const T side = T(gen.uni(0, 2) * s);
            const Primitive<T> prims[] = {
                Sphere<T>{c, radius},
                Obb<T>{c, R1, h1},
                Obb<T>{c, skew, h2},  // skewed, unnormalized axes
                sc.poly(std::move(planes)),
                Aabb<T>{c, Vec3<T>(c + Vec3<T>::Constant(side))},
            };
            for (const Primitive<T>& p : prims) {
                expect_box_holds(p, gen, s);
                if (::testing::Test::HasFatalFailure()) return;
            }
        }
    }
}

TYPED_TEST(Closest, EnclosingBoxOfWhatHasNone) {
    using T = TypeParam;
    const T max = std::numeric_limits<T>::max(), nan = std::numeric_limits<T>::quiet_NaN();
    Scene<T> sc;
    const Aabb<T> box{v3<T>(-1, 0, 2), v3<T>(1, 3, 2)};
    const std::optional<Aabb<T>> bb = detail::enclosing_box(Primitive<T>{box});
    ASSERT_TRUE(bb);
    EXPECT_TRUE(bb->lo == box.lo && bb->hi == box.hi) << "an Aabb is its own box";
    const Primitive<T> none[] = {
        Plane<T>{v3<T>(0, 0, 1), T(0)},
        Aabb<T>{v3<T>(1, 0, 0), v3<T>(0, 0, 0)},
        Sphere<T>{v3<T>(0, 0, 0), T(-1)},
        Sphere<T>{v3<T>(0, 0, nan), T(1)},
        Sphere<T>{v3<T>(max, 0, 0), T(max)},                   // overflows
        Sphere<T>{v3<T>(max, 0, 0), T(0)},                     // step_up(max) is inf
        Obb<T>{v3<T>(0, 0, 0), Mat3<T>::Zero(), v3<T>(1, 1, 1)},
        Obb<T>{v3<T>(0, 0, 0), Mat3<T>::Identity(), v3<T>(max, 1, 1)},
        sc.poly({}),                                                                    // all of space
        sc.poly({Plane<T>{v3<T>(0, 0, 1), T(1)}, Plane<T>{v3<T>(0, 0, -1), T(1)}}),    // a slab
        sc.poly({Plane<T>{v3<T>(1, 1, 1), T(1)}, Plane<T>{v3<T>(-1, 0, 0), T(0)}, Plane<T>{v3<T>(0, -1, 0), T(0)},
                 Plane<T>{v3<T>(0, 0, 1), T(0)}}),  // x, y >= 0, z <= 0, x + y + z <= 1: unbounded towards -z
        sc.poly({Plane<T>{v3<T>(1, 1, 1), T(-1)}, Plane<T>{v3<T>(-1, 0, 0), T(0)}, Plane<T>{v3<T>(0, -1, 0), T(0)},
                 Plane<T>{v3<T>(0, 0, -1), T(0)}}),  // empty
        sc.poly({Plane<T>{v3<T>(1, 0, 0), T(1)}, Plane<T>{v3<T>(-1, 0, 0), T(1)}, Plane<T>{v3<T>(0, 1, 0), T(1)},
                 Plane<T>{v3<T>(0, -1, 0), T(1)}, Plane<T>{v3<T>(0, 1, 1), T(1)}}),  // rank 3, unbounded towards -z
        sc.poly({Plane<T>{v3<T>(0, 0, nan), T(1)}}),
    };
    for (const Primitive<T>& p : none) {
        std::ostringstream os;
        std::visit([&](const auto& s) { os << s; }, p);
        EXPECT_FALSE(detail::enclosing_box(p).has_value()) << os.str();
    }
    // A bounded polyhedron past the plane-count limit is kept beside the tree too.
    std::vector<Plane<T>> many = box_planes<T>(v3<T>(-1, -1, -1), v3<T>(1, 1, 1));
    const std::optional<Aabb<T>> cube = detail::enclosing_box(Primitive<T>{sc.poly(many)});
    ASSERT_TRUE(cube);
    EXPECT_LE(cube->hi[0], T(1.0001));
    EXPECT_GE(cube->lo[0], T(-1.0001));
    while (many.size() <= detail::kMaxBoxedPlanes) many.push_back(many[many.size() % 6]);
    EXPECT_FALSE(detail::enclosing_box(Primitive<T>{sc.poly(many)}).has_value());
}

}  // namespace
