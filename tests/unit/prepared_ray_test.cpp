// PreparedRay<T> (prepared_ray.hpp) against the Ray it was made from, for every shape,
// every mode, float and double, on every shared case generator's cases (general,
// log-uniform, grazing, near grazing, parallel with ±0 components and origins on slab
// planes, on the boundary, extreme exponents and denormals, invalid):
//   - certified: intersect(prepared) equals intersect(ray) bit for bit (verdict, t_enter,
//     t_exit, face; -0 and +0 told apart), and verdict(prepared) equals both verdicts;
//   - conservative: the prepared answer meets the mode's contract against the exact
//     oracle, and verdict(prepared) equals intersect(prepared).verdict;
//   - fast: Verdict::invalid exactly where the ray answers it, and verdict(prepared)
//     and the batch forms agree with intersect(prepared) in validity (fast promises
//     nothing, and a contracted build rounds its inlined paths differently);
//   - every mode answers Verdict::invalid exactly for the inputs the oracle calls invalid;
//   - the RuntimeMode forms, and in certified and conservative mode the batch forms over
//     prepared rays, equal the tag's scalar prepared answers bit for bit.
// By hand: what the prepared ray decides (validity, fl(1/d_i) with the sign of a zero,
// the signs, reciprocals_normal, reciprocals_usable_in, parallel_axes); -0 and +0
// directions with the origin on a slab plane; denormal and huge directions; invalid
// rays; the prepared ray keeps its own copy of the ray (it outlives it); and a prepared
// ray made under a directed rounding mode or flush-to-zero / denormals-are-zero decides
// what it decides in the default environment.
#include "same_hit.hpp"
#include "seeded.hpp"

#include <rayproof/generators.hpp>
#include <rayproof/oracle/contract.hpp>
#include <rayproof/oracle/oracle.hpp>
#include <rayproof/rayproof.hpp>

#include <gtest/gtest.h>

#include <cfenv>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#if defined(__SSE2__) || defined(_M_X64)
#include <xmmintrin.h>
#define PREPARED_TEST_MXCSR 1
#endif

using namespace rayproof;

namespace {

std::uint64_t base_seed() {
    static const std::uint64_t s = rayproof::testing::env_seed_or(31);
    return s;
}

using rayproof::testing::same_bits;
using rayproof::testing::same_hit;

constexpr int kCasesPerGenerator = 250;

// The run-time enumerator of a tag.
RuntimeMode runtime(fast_t) { return RuntimeMode::fast; }
RuntimeMode runtime(conservative_t) { return RuntimeMode::conservative; }
RuntimeMode runtime(certified_t) { return RuntimeMode::certified; }

// Every check of the header comment on one case; the batch forms on the generator's
// cases against one shape.
template <class T, class Shape> void check_case(const Ray<T>& r, const Shape& s) {
    const PreparedRay<T> p(r);
    const auto e = oracle::exact(r, s);
    const auto each_mode = [&](auto mode) {
        SCOPED_TRACE(mode_name(mode));
        const Hit<T> hp = intersect(p, s, mode);
        const Hit<T> hr = intersect(r, s, mode);
        // fast promises nothing, and its verdict path and full query may round differently
        // where the compiler contracts them differently (-ffp-contract=fast): there the two
        // agree in validity only, as in the props suites.
        // The run-time dispatch is another inlined path, so the same holds for it.
        if constexpr (std::is_same_v<decltype(mode), fast_t>) {
            const auto invalid = [](Verdict v) { return v == Verdict::invalid; };
            EXPECT_EQ(invalid(verdict(p, s, mode)), invalid(hp.verdict));
            EXPECT_EQ(invalid(intersect(p, s, runtime(mode)).verdict), invalid(hp.verdict));
            EXPECT_EQ(invalid(verdict(p, s, runtime(mode))), invalid(hp.verdict));
        } else {
            EXPECT_EQ(verdict(p, s, mode), hp.verdict);
            EXPECT_TRUE(same_hit(intersect(p, s, runtime(mode)), hp));
            EXPECT_EQ(verdict(p, s, runtime(mode)), hp.verdict);
        }
        EXPECT_EQ(hp.verdict == Verdict::invalid, hr.verdict == Verdict::invalid) << hp << " vs " << hr;
        const auto c = oracle::check_contract(r, s, hp, e, mode);
        EXPECT_FALSE(c.invalid_mismatch()) << hp << "\n  " << e;
        if constexpr (!std::is_same_v<decltype(mode), fast_t>) {
            EXPECT_FALSE(c.promise_broken()) << hp << "\n  " << e << "\n  " << c.mode_judgement();
        }
        if constexpr (std::is_same_v<decltype(mode), certified_t>) {
            EXPECT_TRUE(same_hit(hp, hr));
            EXPECT_EQ(verdict(p, s, mode), verdict(r, s, mode));
        }
    };
    each_mode(fast);
    each_mode(conservative);
    each_mode(certified);
}

template <class T, class Shape, class Mode> void check_batch(const std::vector<Ray<T>>& rays, const Shape& s, Mode mode) {
    std::vector<PreparedRay<T>> prepared;
    for (const Ray<T>& r : rays) prepared.emplace_back(r);
    std::vector<Hit<T>> hits(rays.size());
    std::vector<Verdict> verdicts(rays.size());
    const std::span<const PreparedRay<T>> in(prepared);
    intersect(in, s, mode, std::span<Hit<T>>(hits));
    verdict(in, s, mode, std::span<Verdict>(verdicts));
    for (std::size_t i = 0; i < rays.size(); ++i) {
        // fast promises nothing, and a batch may round differently from the scalar form
        // (CONTRACT, batch forms; a contracted build does): there, validity only.
        if constexpr (std::is_same_v<Mode, fast_t>) {
            const Verdict v = intersect(prepared[i], s, mode).verdict;
            ASSERT_EQ(hits[i].verdict == Verdict::invalid, v == Verdict::invalid) << "fast element " << i;
            ASSERT_EQ(verdicts[i] == Verdict::invalid, v == Verdict::invalid) << "fast element " << i;
        } else {
            ASSERT_TRUE(same_hit(hits[i], intersect(prepared[i], s, mode))) << mode_name(mode) << " element " << i;
            ASSERT_EQ(verdicts[i], verdict(prepared[i], s, mode)) << mode_name(mode) << " element " << i;
        }
    }
    std::vector<Hit<T>> by_runtime(rays.size());
    intersect(in, s, runtime(mode), std::span<Hit<T>>(by_runtime));
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if constexpr (std::is_same_v<Mode, fast_t>)  // another inlined path: validity only, as above
            ASSERT_EQ(by_runtime[i].verdict == Verdict::invalid, hits[i].verdict == Verdict::invalid) << " element " << i;
        else
            ASSERT_TRUE(same_hit(by_runtime[i], hits[i])) << " element " << i;
    }
}

template <class T, class Shape> void check_generators() {
    std::mt19937_64 rng = rayproof::testing::rng_for_current_test(base_seed());
    RAYPROOF_SEED_TRACE(base_seed());
    for (const auto& g : gen::generators<T, Shape>()) {
        std::vector<Ray<T>> rays;
        std::vector<Shape> shapes;
        for (int i = 0; i < kCasesPerGenerator; ++i) {
            const gen::Case<T, Shape> c = g.make(rng);
            SCOPED_TRACE(::testing::Message() << g.name << " case " << i << ": " << c);
            check_case(c.ray, c.shape);
            if (::testing::Test::HasFailure()) return;
            rays.push_back(c.ray);
            shapes.push_back(c.shape);
        }
        SCOPED_TRACE(::testing::Message() << g.name << " batch on " << shapes.front());
        check_batch(rays, shapes.front(), fast);
        check_batch(rays, shapes.front(), conservative);
        check_batch(rays, shapes.front(), certified);
        if (::testing::Test::HasFailure()) return;
    }
}

template <class T> Aabb<T> unit_box() { return {Vec3<T>(-1, -1, -1), Vec3<T>(1, 1, 1)}; }

// The hand cases of the header comment, against every shape.
template <class T> std::vector<Ray<T>> hand_rays() {
    constexpr T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
    constexpr T den = std::numeric_limits<T>::denorm_min(), big = std::numeric_limits<T>::max();
    std::vector<Ray<T>> rays;
    for (const T z : {T(0), T(-0.0)})
        for (const T o : {T(-1), T(1), T(0.5), T(-0.0), T(2)}) {
            rays.push_back({Vec3<T>(-4, o, 0), Vec3<T>(1, z, z)});      // on, inside, off slab 1
            rays.push_back({Vec3<T>(o, -4, 1), Vec3<T>(z, 1, -z)});     // on the hi plane of slab 2
            rays.push_back({Vec3<T>(4, o, o), Vec3<T>(-1, z, T(0.5))});  // oblique, one zero
        }
    rays.push_back({Vec3<T>(-4, 0, 0), Vec3<T>(1, den, -den)});
    rays.push_back({Vec3<T>(-4, 0, 0), Vec3<T>(big, den, 0)});
    rays.push_back({Vec3<T>(-4, 0, 0), Vec3<T>(den, den, den)});
    rays.push_back({Vec3<T>(0, 0, 0), Vec3<T>(big, big, -big)});
    rays.push_back({Vec3<T>(-4, 0, 0), Vec3<T>(1, 0, 0), T(0), T(0)});
    rays.push_back({Vec3<T>(-4, 0, 0), Vec3<T>(1, 0, 0), -inf, inf});
    // Invalid.
    rays.push_back({Vec3<T>(-4, 0, 0), Vec3<T>(0, -0.0, 0)});
    rays.push_back({Vec3<T>(-4, 0, 0), Vec3<T>(nan, 1, 0)});
    rays.push_back({Vec3<T>(-4, 0, 0), Vec3<T>(inf, 1, 0)});
    rays.push_back({Vec3<T>(nan, 0, 0), Vec3<T>(1, 0, 0)});
    rays.push_back({Vec3<T>(-4, 0, 0), Vec3<T>(1, 0, 0), T(2), T(1)});
    rays.push_back({Vec3<T>(-4, 0, 0), Vec3<T>(1, 0, 0), inf, inf});
    rays.push_back({Vec3<T>(-4, 0, 0), Vec3<T>(1, 0, 0), T(0), nan});
    return rays;
}

template <class T> void check_hand_cases() {
    const Obb<T> obb{Vec3<T>(0, 0, 0), Eigen::Matrix<T, 3, 3>::Identity(), Vec3<T>(1, 1, 1)};
    const Plane<T> plane{Vec3<T>(1, 0, 0), T(-1)};
    const Sphere<T> sphere{Vec3<T>(0, 0, 0), T(1)};
    for (const Ray<T>& r : hand_rays<T>()) {
        SCOPED_TRACE(::testing::Message() << r);
        check_case(r, unit_box<T>());
        check_case(r, obb);
        check_case(r, plane);
        check_case(r, sphere);
        // What the prepared ray decided.
        const PreparedRay<T> p(r);
        EXPECT_EQ(p.valid(), detail::valid(r));
        bool normal = p.valid(), usable_double = true, usable_float = true;
        unsigned parallel_axes = 0;
        for (int i = 0; i < 3; ++i) {
            const double inv = 1.0 / double(r.direction[i]);
            EXPECT_TRUE(same_bits(p.rinv(i), inv) || (std::isnan(inv) && std::isnan(p.rinv(i)))) << i;
            EXPECT_TRUE(same_bits(p.inv(i), T(inv)) || (std::isnan(inv) && std::isnan(p.inv(i)))) << i;
            EXPECT_EQ(p.negative(i), std::signbit(r.direction[i])) << i;
            normal = normal && std::isnormal(inv);
            const bool parallel = r.direction[i] == 0;
            parallel_axes |= unsigned(parallel) << i;
            usable_double = usable_double && (parallel || std::isnormal(inv));
            usable_float = usable_float && (parallel || std::isnormal(float(inv)));
        }
        EXPECT_EQ(p.reciprocals_normal(), normal);
        EXPECT_EQ(p.template reciprocals_usable_in<double>(), usable_double);
        EXPECT_EQ(p.template reciprocals_usable_in<float>(), usable_float);
        EXPECT_EQ(p.parallel_axes(), parallel_axes);
        if (!p.valid()) {
            for (const Hit<T>& h : {intersect(p, unit_box<T>(), certified), intersect(p, obb, fast),
                                    intersect(p, plane, conservative), intersect(p, sphere, certified)}) {
                EXPECT_EQ(h.verdict, Verdict::invalid);
            }
        }
    }
}

TEST(PreparedRay, CertifiedEqualsRayAabbFloat) { check_generators<float, Aabb<float>>(); }
TEST(PreparedRay, CertifiedEqualsRayAabbDouble) { check_generators<double, Aabb<double>>(); }
TEST(PreparedRay, CertifiedEqualsRayObbFloat) { check_generators<float, Obb<float>>(); }
TEST(PreparedRay, CertifiedEqualsRayObbDouble) { check_generators<double, Obb<double>>(); }
TEST(PreparedRay, CertifiedEqualsRayPlaneFloat) { check_generators<float, Plane<float>>(); }
TEST(PreparedRay, CertifiedEqualsRayPlaneDouble) { check_generators<double, Plane<double>>(); }
TEST(PreparedRay, CertifiedEqualsRaySphereFloat) { check_generators<float, Sphere<float>>(); }
TEST(PreparedRay, CertifiedEqualsRaySphereDouble) { check_generators<double, Sphere<double>>(); }

TEST(PreparedRay, HandCasesFloat) { check_hand_cases<float>(); }
TEST(PreparedRay, HandCasesDouble) { check_hand_cases<double>(); }

// The zero's sign decides which plane of a parallel slab a reciprocal "enters": the
// prepared ray keeps it (1/-0 = -inf), and the face of a box hit along another axis is
// the same for +0 and -0.
TEST(PreparedRay, SignedZeroReciprocals) {
    const PreparedRay<double> plus(Ray<double>{Vec3<double>(-4, 1, 0), Vec3<double>(1, 0.0, 0.0)});
    const PreparedRay<double> minus(Ray<double>{Vec3<double>(-4, 1, 0), Vec3<double>(1, -0.0, -0.0)});
    EXPECT_EQ(plus.rinv(1), std::numeric_limits<double>::infinity());
    EXPECT_EQ(minus.rinv(1), -std::numeric_limits<double>::infinity());
    EXPECT_FALSE(plus.negative(1));
    EXPECT_TRUE(minus.negative(1));
    EXPECT_FALSE(plus.reciprocals_normal());
    const Hit<double> a = intersect(plus, unit_box<double>(), certified), b = intersect(minus, unit_box<double>(), certified);
    ASSERT_EQ(a.verdict, Verdict::hit);  // the origin lies on the hi plane of slab 1
    EXPECT_TRUE(same_hit(a, b));
    EXPECT_EQ(a.face, 0);
    EXPECT_EQ(a.t_enter, 3);
    EXPECT_EQ(a.t_exit, 5);
}

// The prepared ray keeps its own copy: the Ray it was made from may change or die.
TEST(PreparedRay, OutlivesItsRay) {
    auto owned = std::make_unique<Ray<float>>(Ray<float>{Vec3<float>(-4, 0.25f, 0.5f), Vec3<float>(1, 0.125f, -0.0f)});
    const PreparedRay<float> p(*owned);
    const Ray<float> copy = *owned;
    const Hit<float> before = intersect(copy, unit_box<float>(), certified);
    ASSERT_EQ(before.verdict, Verdict::hit);
    owned->origin = Vec3<float>(100, 100, 100);
    owned->direction = Vec3<float>(0, 0, 0);
    owned.reset();
    EXPECT_TRUE(same_hit(intersect(p, unit_box<float>(), certified), before));
    EXPECT_EQ(p.ray().origin, copy.origin);
    EXPECT_TRUE(p.valid());
}

// A prepared ray made in a foreign floating-point environment decides what it decides in
// the default one, and its certified answers there are the Ray's in the default one.
template <class T> void check_foreign_preparation(void (*enter)(), void (*leave)()) {
    const T den = std::numeric_limits<T>::denorm_min();
    const std::vector<Ray<T>> rays = {
        {Vec3<T>(-4, T(0.1), T(0.3)), Vec3<T>(T(1) / 3, T(0.7), T(-0.11))},  // reciprocals round
        {Vec3<T>(0, 0, 0), Vec3<T>(den, T(3), T(7))},                       // a subnormal component
        {Vec3<T>(-4, 0, 0), Vec3<T>(den, 0, 0)},                            // valid only as a subnormal
    };
    for (const Ray<T>& r : rays) {
        SCOPED_TRACE(::testing::Message() << r);
        enter();
        const PreparedRay<T> p(r);
        leave();
        const PreparedRay<T> q(r);
        EXPECT_EQ(p.valid(), q.valid());
        EXPECT_TRUE(q.valid());
        EXPECT_EQ(p.reciprocals_normal(), q.reciprocals_normal());
        for (int i = 0; i < 3; ++i) {
            EXPECT_TRUE(same_bits(p.rinv(i), q.rinv(i))) << i;
            EXPECT_TRUE(same_bits(p.inv(i), q.inv(i))) << i;
        }
        EXPECT_TRUE(same_hit(intersect(p, unit_box<T>(), certified), intersect(r, unit_box<T>(), certified)));
    }
}

void upward() { ASSERT_EQ(std::fesetround(FE_UPWARD), 0); }
void downward() { ASSERT_EQ(std::fesetround(FE_DOWNWARD), 0); }
void nearest() { ASSERT_EQ(std::fesetround(FE_TONEAREST), 0); }

TEST(PreparedRay, PreparedInDirectedRoundingFloat) {
    check_foreign_preparation<float>(&upward, &nearest);
    check_foreign_preparation<float>(&downward, &nearest);
}
TEST(PreparedRay, PreparedInDirectedRoundingDouble) {
    check_foreign_preparation<double>(&upward, &nearest);
    check_foreign_preparation<double>(&downward, &nearest);
}

#if defined(PREPARED_TEST_MXCSR)
unsigned saved_csr = 0;
void ftz_daz() {
    saved_csr = _mm_getcsr();
    _mm_setcsr(saved_csr | 0x8040u);  // FTZ (15), DAZ (6)
}
void restore_csr() { _mm_setcsr(saved_csr); }
TEST(PreparedRay, PreparedUnderFlushToZeroFloat) { check_foreign_preparation<float>(&ftz_daz, &restore_csr); }
TEST(PreparedRay, PreparedUnderFlushToZeroDouble) { check_foreign_preparation<double>(&ftz_daz, &restore_csr); }
#endif

}  // namespace
