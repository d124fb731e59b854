// The batch form against the scalar form, element by element, for every shape, scalar
// type and mode the kernel has, on seeded random rays mixed with parallel, grazing and
// invalid ones, as the contract words it: certified answers identical (verdict, both t
// values bit for bit, face); fast and conservative answers may round differently (a
// vectorized or contracted path is free to), so they must agree on validity, and each
// conservative answer, batch and scalar, must hit wherever the certified one does with
// an interval reaching the certified ends' outer neighbours (the exact ends lie within
// them). The verdict batch likewise: certified verdicts identical, the others the same
// validity, conservative's a hit wherever certified's is. An invalid shape makes every
// element invalid; a size mismatch is refused with std::invalid_argument.
#include "same_hit.hpp"
#include <rayproof/detail/ray_aabb_batch.hpp>
#include "unit_support.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

using namespace rayproof;
using namespace rayproof::testing;

template <class T> class Batch : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Batch, Scalars);

namespace {

using rayproof::testing::same_bits;

template <class T> std::vector<Ray<T>> rays(std::uint64_t seed, std::size_t n) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-4, 4);
    std::uniform_int_distribution<int> pick(0, 9);
    std::vector<Ray<T>> out;
    for (std::size_t i = 0; i < n; ++i) {
        Ray<T> r{Vec3<T>(T(u(rng)), T(u(rng)), T(u(rng))), Vec3<T>(T(u(rng)), T(u(rng)), T(u(rng)))};
        switch (pick(rng)) {
            case 0: r.direction[1] = -T(0); r.origin[1] = T(1); break;  // parallel, on a slab plane
            case 1: r.direction[0] = T(0); break;
            case 2: r.origin = Vec3<T>(-3, -3, -3); r.direction = Vec3<T>(1, 1, 1); break;  // corner
            case 3: r.t_min = T(u(rng)); r.t_max = r.t_min + T(2); break;
            case 4: r.direction.setZero(); break;  // invalid
            default: break;
        }
        out.push_back(r);
    }
    return out;
}

// A conservative answer against the certified one: a hit where it hits, with t_enter at
// most the upper and t_exit at least the lower neighbour of the certified (faithful) ends.
template <class T> void expect_conservative(const Hit<T>& c, const Hit<T>& exact) {
    if (exact.verdict != Verdict::hit) return;
    ASSERT_EQ(c.verdict, Verdict::hit) << c << " vs certified " << exact;
    EXPECT_LE(c.t_enter, detail::step_up(exact.t_enter)) << c << " vs certified " << exact;
    EXPECT_GE(c.t_exit, detail::step_down(exact.t_exit)) << c << " vs certified " << exact;
}

template <class T, class Shape, class Mode> void compare(const Shape& s, Mode m, std::uint64_t seed) {
    const std::vector<Ray<T>> in = rays<T>(seed, 512);
    std::vector<Hit<T>> out(in.size());
    intersect(std::span<const Ray<T>>(in), s, m, std::span<Hit<T>>(out));
    for (std::size_t i = 0; i < in.size(); ++i) {
        const Hit<T> h = intersect(in[i], s, m);
        SCOPED_TRACE(::testing::Message() << mode_name(m) << " seed " << seed << " element " << i << ": " << in[i]);
        ASSERT_EQ(out[i].verdict == Verdict::invalid, h.verdict == Verdict::invalid) << out[i] << " vs " << h;
        if constexpr (std::is_same_v<Mode, certified_t>) {
            ASSERT_EQ(out[i].verdict, h.verdict);
            ASSERT_TRUE(same_bits(out[i].t_enter, h.t_enter)) << out[i] << " vs " << h;
            ASSERT_TRUE(same_bits(out[i].t_exit, h.t_exit)) << out[i] << " vs " << h;
            ASSERT_EQ(out[i].face, h.face);
        } else if constexpr (std::is_same_v<Mode, conservative_t>) {
            if constexpr (Answerable<T, Shape, certified_t>) {
                const Hit<T> exact = intersect(in[i], s, certified);
                expect_conservative(out[i], exact);
                expect_conservative(h, exact);
            }
        }
    }
    // The verdict batch: each element the scalar verdict (certified: the same verdict;
    // the other modes: the same validity, and conservative's hit wherever certified's).
    std::vector<Verdict> vout(in.size());
    verdict(std::span<const Ray<T>>(in), s, m, std::span<Verdict>(vout));
    for (std::size_t i = 0; i < in.size(); ++i) {
        const Verdict v1 = verdict(in[i], s, m);
        SCOPED_TRACE(::testing::Message() << mode_name(m) << " verdict, seed " << seed << " element " << i << ": "
                                          << in[i]);
        ASSERT_EQ(vout[i] == Verdict::invalid, v1 == Verdict::invalid) << int(vout[i]) << " vs " << int(v1);
        if constexpr (std::is_same_v<Mode, certified_t>) {
            ASSERT_EQ(vout[i], v1);
        } else if constexpr (std::is_same_v<Mode, conservative_t>) {
            if constexpr (Answerable<T, Shape, certified_t>) {
                if (verdict(in[i], s, certified) == Verdict::hit) {
                    ASSERT_EQ(vout[i], Verdict::hit);
                    ASSERT_EQ(v1, Verdict::hit);
                }
            }
        }
    }
    std::vector<Hit<T>> short_out(in.size() - 1);
    EXPECT_THROW(intersect(std::span<const Ray<T>>(in), s, m, std::span<Hit<T>>(short_out)), std::invalid_argument);
    std::vector<Verdict> short_v(in.size() - 1);
    EXPECT_THROW(verdict(std::span<const Ray<T>>(in), s, m, std::span<Verdict>(short_v)), std::invalid_argument);
}

template <class T, class Shape> void compare_all_modes(const Shape& s, std::uint64_t seed) {
    compare<T>(s, fast, seed);
    if constexpr (Answerable<T, Shape, conservative_t>) compare<T>(s, conservative, seed);
    if constexpr (Answerable<T, Shape, certified_t>) compare<T>(s, certified, seed);
}

}  // namespace

TYPED_TEST(Batch, EqualsScalarForEveryShape) {
    using T = TypeParam;
    Mat3<T> rot;
    rot << 3, -4, 0, 4, 3, 0, 0, 0, 5;
    for (std::uint64_t seed : {1u, 2u, 3u}) {
        compare_all_modes<T>(Aabb<T>{v<T>(-1, -1, -1), v<T>(1, 1, 1)}, seed);
        compare_all_modes<T>(Obb<T>{v<T>(0.5, 0, 0), rot, v<T>(5, 10, 5)}, seed);
        compare_all_modes<T>(Plane<T>{v<T>(0, 1, 0), T(0.5)}, seed);
        compare_all_modes<T>(Sphere<T>{v<T>(0, 0.5, 0), T(1.5)}, seed);
    }
}

TYPED_TEST(Batch, InvalidShapeMakesEveryElementInvalid) {
    using T = TypeParam;
    const std::vector<Ray<T>> in = rays<T>(7, 64);
    std::vector<Hit<T>> out(in.size());
    intersect(std::span<const Ray<T>>(in), Sphere<T>{v<T>(0, 0, 0), T(-1)}, fast, std::span<Hit<T>>(out));
    for (const Hit<T>& h : out) EXPECT_EQ(h.verdict, Verdict::invalid);
    intersect(std::span<const Ray<T>>(in), Aabb<T>{v<T>(1, 0, 0), v<T>(0, 1, 1)}, fast, std::span<Hit<T>>(out));
    for (const Hit<T>& h : out) EXPECT_EQ(h.verdict, Verdict::invalid);
    std::vector<Hit<T>> none;
    intersect(std::span<const Ray<T>>(), Aabb<T>{v<T>(0, 0, 0), v<T>(1, 1, 1)}, fast, std::span<Hit<T>>(none));
}

// --- The lane paths (detail/ray_aabb_batch.hpp, detail/ray_plane_batch.hpp) -------------
// The certified Aabb and plane batches run W rays at a time in SIMD lanes (for double
// rays against a plane, the verdict filter) and must give every ray the scalar certified
// answer bit for bit, in both backends (simd::portable and simd::native), for Ray and
// PreparedRay spans, intersect and verdict, for every batch size around the block width
// (0, 1, W - 1, W, W + 1, ...) and with each special ray (invalid, ±0, huge and tiny
// direction components, non-finite, ties, ranges ending on the box; for the plane
// parallel rays on and off it, nearly parallel ones, crossings at t_min, t_max and
// t = 0) at every lane position of a block.
namespace {

namespace simd = rayproof::detail::simd;

template <class T> std::vector<Ray<T>> special_rays() {
    const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
    const T big = std::numeric_limits<T>::max() / 4, tiny = std::numeric_limits<T>::denorm_min();
    std::vector<Ray<T>> s;
    const auto add = [&](Vec3<T> o, Vec3<T> d, T t0 = 0, T t1 = std::numeric_limits<T>::infinity()) {
        s.push_back(Ray<T>{o, d, t0, t1});
    };
    add(v<T>(-3, 0.25, 0.5), v<T>(1, 0, 0));                  // parallel to two slabs
    add(v<T>(-3, 1, 0.5), v<T>(1, -T(0), T(0)));              // on a slab plane, -0
    add(v<T>(-3, -3, -3), v<T>(1, 1, 1));                     // through a corner
    add(v<T>(-3, -1, 0), v<T>(1, 0, 0));                      // along a face
    add(v<T>(-3, 0, 0), v<T>(1, 0, 0), T(2), T(2));           // t range a point, on the face
    add(v<T>(-3, 0.1f, 0.2f), v<T>(1, 0.01f, 0.02f), T(0), T(2));  // range ends at the entry
    add(v<T>(-3, 0.1f, 0.2f), v<T>(1, 0.01f, 0.02f), T(4), T(9));  // range starts at the exit
    add(v<T>(0, 0, 0), v<T>(0, 0, 0));                        // zero direction: invalid
    add(v<T>(nan, 0, 0), v<T>(1, 1, 1));                      // NaN origin
    add(v<T>(0, 0, 0), v<T>(inf, 1, 1));                      // infinite direction
    add(v<T>(0, 0, 0), v<T>(1, 1, 1), T(2), T(1));            // empty range: invalid
    add(v<T>(0, 0, 0), v<T>(1, 1, 1), -inf, inf);             // whole line
    add(v<T>(-3, 0.5, 0.5), v<T>(big, 1, 1));                 // huge direction component
    add(v<T>(-3, 0.5, 0.5), v<T>(1, tiny, tiny));             // subnormal components
    add(v<T>(-3, 0.5, 0.5), v<T>(T(1e-30), T(1e-30), T(-1e-30)));  // tiny direction
    add(v<T>(big, big, big), v<T>(-1, -1, -1));               // far origin, values overflow
    add(v<T>(0.5, 0.5, 0.5), v<T>(-1, 2, -3));                // origin inside
    add(v<T>(2, 2, 2), v<T>(1, 1, 1));                        // moving away
    add(v<T>(-1, -1, -1), v<T>(1, 2, 3), -inf, T(0));         // starts on a corner, range to it
    // Float rays whose t lies beyond the largest float (faithful_to answers that float):
    // the exit only, both ends, and both ends on either side of the origin.
    add(v<T>(-3, 0, 0), v<T>(T(1e-38f), T(1e-40f), T(1e-40f)));
    add(v<T>(-3, 0, 0), v<T>(T(5e-39f), T(1e-40f), T(1e-40f)));
    add(v<T>(0, 0, 0), v<T>(T(1e-39f), T(1e-40f), T(1e-40f)), -inf, inf);
    return s;
}

// The rays of rays() with every other one aimed at a point of the box [-0.9, 0.9]^3 (a
// hit of the unit box, decided in lanes with its winners rounded there), and the special
// ones placed in turn at every position of the first blocks.
template <class T>
std::vector<Ray<T>> lane_rays(std::uint64_t seed, std::size_t n, std::size_t special_at,
                              const std::vector<Ray<T>>& s = special_rays<T>()) {
    std::vector<Ray<T>> out = rays<T>(seed, n);
    std::mt19937_64 rng(seed + 1000);
    std::uniform_real_distribution<double> u(-0.9, 0.9);
    for (std::size_t i = 1; i < out.size(); i += 2) {
        const Vec3<T> target(T(u(rng)), T(u(rng)), T(u(rng)));
        out[i].direction = target - out[i].origin;
    }
    for (std::size_t k = 0; k < s.size(); ++k) {
        const std::size_t at = special_at + 3 * k;
        if (at < out.size()) out[at] = s[k];
    }
    return out;
}

template <class T> void expect_same(const Hit<T>& a, const Hit<T>& b, std::size_t i) {
    ASSERT_EQ(a.verdict, b.verdict) << "element " << i << ": " << a << " vs scalar " << b;
    ASSERT_TRUE(same_bits(a.t_enter, b.t_enter)) << "element " << i << ": " << a << " vs scalar " << b;
    ASSERT_TRUE(same_bits(a.t_exit, b.t_exit)) << "element " << i << ": " << a << " vs scalar " << b;
    ASSERT_EQ(a.face, b.face) << "element " << i;
}

// The lane batch of backend B against the scalar certified query, element by element.
template <class B, class R, class T, class Shape>
void check_lanes(const std::vector<Ray<T>>& in, const Shape& s) {
    std::vector<R> rs;
    for (const Ray<T>& r : in) rs.push_back(R(r));
    const auto prepared = detail::prepare(s);
    std::vector<Hit<T>> hits(rs.size());
    std::vector<Verdict> verdicts(rs.size());
    detail::batch::certified_lanes<B>(std::span<const R>(rs), prepared, std::span<Hit<T>>(hits));
    detail::batch::certified_lanes<B>(std::span<const R>(rs), prepared, std::span<Verdict>(verdicts));
    for (std::size_t i = 0; i < rs.size(); ++i) {
        SCOPED_TRACE(::testing::Message() << (std::is_same_v<B, simd::portable> ? "portable " : "native ")
                                          << (detail::is_prepared_ray_v<R> ? "prepared " : "ray ") << in[i]);
        const Hit<T> h = intersect(rs[i], s, certified);
        expect_same(hits[i], h, i);
        ASSERT_EQ(verdicts[i], verdict(rs[i], s, certified)) << "element " << i;
        ASSERT_EQ(verdicts[i], h.verdict) << "element " << i;
    }
}

template <class T, class Shape> void check_all_forms(const std::vector<Ray<T>>& in, const Shape& s) {
    check_lanes<simd::portable, Ray<T>>(in, s);
    check_lanes<simd::native, Ray<T>>(in, s);
    check_lanes<simd::portable, PreparedRay<T>>(in, s);
    check_lanes<simd::native, PreparedRay<T>>(in, s);
    // And the public batch forms (the native lanes inside batch_of where it takes them).
    std::vector<Hit<T>> out(in.size());
    std::vector<Verdict> verdicts(in.size());
    intersect(std::span<const Ray<T>>(in), s, certified, std::span<Hit<T>>(out));
    verdict(std::span<const Ray<T>>(in), s, certified, std::span<Verdict>(verdicts));
    for (std::size_t i = 0; i < in.size(); ++i) {
        expect_same(out[i], intersect(in[i], s, certified), i);
        ASSERT_EQ(verdicts[i], verdict(in[i], s, certified)) << "element " << i << ": " << in[i];
    }
}

template <class T> std::vector<Aabb<T>> lane_boxes() {
    return {Aabb<T>{v<T>(-1, -1, -1), v<T>(1, 1, 1)}, Aabb<T>{v<T>(-0.3f, 0.1f, -2), v<T>(0.7f, 0.1f, 1.5f)},  // flat
            Aabb<T>{v<T>(1e-3f, 2e-3f, -1e-3f), v<T>(3e-3f, 5e-3f, 1e-3f)}, Aabb<T>{v<T>(-1e6f, -1e6f, -1e6f), v<T>(1e6f, 1e6f, 1e6f)}};
}
}  // namespace

TYPED_TEST(Batch, AabbLanesEqualScalarBitForBit) {
    using T = TypeParam;
    const std::size_t W = detail::batch::kBatchLanes;
    for (const Aabb<T>& b : lane_boxes<T>())
        for (std::size_t at = 0; at < W; ++at) check_all_forms(lane_rays<T>(11 + at, 96, at), b);
}

TYPED_TEST(Batch, AabbLanesEveryBatchSize) {
    using T = TypeParam;
    const std::size_t W = detail::batch::kBatchLanes;
    const Aabb<T> b{v<T>(-1, -1, -1), v<T>(1, 1, 1)};
    for (std::size_t n : {std::size_t(0), std::size_t(1), W - 1, W, W + 1, 2 * W - 1, 2 * W + 1, 5 * W + 3})
        check_all_forms(lane_rays<T>(n, n, 0), b);
    // An invalid box: every element invalid, none through the lanes.
    check_all_forms(rays<T>(5, 2 * W + 1), Aabb<T>{v<T>(1, 0, 0), v<T>(0, 1, 1)});
}

// The lanes decide the common case themselves: on uniform rays nearly every lane is
// answered in lanes (the rest goes to the scalar query), in both backends. A lane path
// that declined everything would still equal the scalar answers; this catches it.
template <class B, class T> void expect_lanes_decide() {
    const std::size_t W = detail::batch::kBatchLanes;
    const std::vector<Ray<T>> in = rays<T>(99, 400);
    const Aabb<T> box{v<T>(-1, -1, -1), v<T>(1, 1, 1)};
    std::size_t box_lanes = 0, box_hits = 0, scalar_hits = 0;
    for (std::size_t k = 0; k + W <= in.size(); k += W) {
        for (std::size_t i = 0; i < W; ++i) scalar_hits += intersect(in[k + i], box, certified).verdict == Verdict::hit;
        detail::batch::RayBlock<detail::batch::kBatchLanes> g;
        detail::batch::gather<Ray<T>, T>(in.data() + k, g);
        detail::batch::AabbDecided<detail::batch::kBatchLanes> d;
        detail::batch::aabb_block<B, true>(g, false, box, d);
        box_lanes += std::size_t(std::popcount(d.decided));
        box_hits += std::size_t(std::popcount(d.decided & d.hit));
    }
    // rays() makes 40% of its rays special (parallel, corner, invalid); of the other 60%
    // nearly all are decided, and so are most hits (the corner rays are hits left to the
    // scalar query: a tie of three axes).
    EXPECT_GE(box_lanes, in.size() / 2);
    EXPECT_GT(box_hits, 0u);
    EXPECT_GE(2 * box_hits, scalar_hits - std::size_t(std::count_if(in.begin(), in.end(), [](const Ray<T>& r) {
        return r.origin == Vec3<T>(-3, -3, -3);
    })));
}

TYPED_TEST(Batch, LanesDecideTheCommonCase) {
    expect_lanes_decide<simd::portable, TypeParam>();
    expect_lanes_decide<simd::native, TypeParam>();
}

// The plane's lane path (float rays: the enclosure; double rays: the verdict filter).
// Rays against the plane y = 0.5 (and the others of lane_planes): parallel off and in
// the plane, nearly parallel, crossing exactly at t_min, at t_max, at t = 0 (the origin
// on the plane), behind the range, through a whole line, and the invalid and extreme
// ones of special_rays.
namespace {

template <class T> std::vector<Ray<T>> plane_special_rays() {
    std::vector<Ray<T>> s = special_rays<T>();
    const auto add = [&](Vec3<T> o, Vec3<T> d, T t0 = 0, T t1 = std::numeric_limits<T>::infinity()) {
        s.push_back(Ray<T>{o, d, t0, t1});
    };
    const T inf = std::numeric_limits<T>::infinity();
    add(v<T>(0, 2, 0), v<T>(1, 0, 3));                  // parallel, off the plane
    add(v<T>(0, 0.5f, 0), v<T>(1, 0, 3));               // parallel, in the plane
    add(v<T>(0, 0.5f, 0), v<T>(1, -T(0), 3));           // in the plane, -0
    add(v<T>(0, 2, 0), v<T>(1, -1e-7f, 0));             // nearly parallel, far crossing
    add(v<T>(0, 2, 0), v<T>(1, -1e-30f, 0));            // nearly parallel, crossing overflows (float)
    add(v<T>(0, 1.5f, 0), v<T>(0, -1, 0), T(1), T(3));  // crossing at t_min
    add(v<T>(0, 1.5f, 0), v<T>(0, -1, 0), T(0), T(1));  // crossing at t_max
    add(v<T>(0, 1.5f, 0), v<T>(0, -1, 0), T(1), T(1));  // range a point, at the crossing
    add(v<T>(2, 0.5f, 1), v<T>(1, 1, 1));               // origin on the plane: t = 0
    add(v<T>(2, 0.5f, 1), v<T>(1, 1, 1), -inf, T(0));   // t = 0 at t_max
    add(v<T>(0, 3, 0), v<T>(0, 1, 0));                  // crossing behind the origin
    add(v<T>(0, 3, 0), v<T>(0.1f, 1, 0.2f), -inf, inf); // whole line
    add(v<T>(0, 1.5f, 0), v<T>(0.3f, -1, 0.7f), T(0), std::nextafter(T(1), T(0)));  // range ends a step short
    return s;
}

template <class T> std::vector<Plane<T>> lane_planes() {
    return {Plane<T>{v<T>(0, 1, 0), T(0.5)}, Plane<T>{v<T>(1, 2, 3), T(0.25)},
            Plane<T>{v<T>(1e-30f, -2e-30f, 1e-30f), T(1e-31f)}, Plane<T>{v<T>(0.6f, 0, 0.8f), T(1e30f)},
            Plane<T>{v<T>(3e-38f, 1, 0), T(-0.5)}};
}

}  // namespace

TYPED_TEST(Batch, PlaneLanesEqualScalarBitForBit) {
    using T = TypeParam;
    const std::size_t W = detail::batch::kBatchLanes;
    const std::vector<Ray<T>> specials = plane_special_rays<T>();
    for (const Plane<T>& p : lane_planes<T>())
        for (std::size_t at = 0; at < W; ++at) check_all_forms(lane_rays<T>(21 + at, 128, at, specials), p);
}

TYPED_TEST(Batch, PlaneLanesEveryBatchSize) {
    using T = TypeParam;
    const std::size_t W = detail::batch::kBatchLanes;
    const Plane<T> p{v<T>(0, 1, 0), T(0.5)};
    const std::vector<Ray<T>> specials = plane_special_rays<T>();
    for (std::size_t n : {std::size_t(0), std::size_t(1), W - 1, W, W + 1, 2 * W - 1, 2 * W + 1, 5 * W + 3})
        check_all_forms(lane_rays<T>(n, n, 0, specials), p);
    // Invalid planes (a zero normal, an infinite offset): every element invalid.
    for (const Plane<T>& bad :
         {Plane<T>{v<T>(0, 0, 0), T(1)}, Plane<T>{v<T>(0, 1, 0), std::numeric_limits<T>::infinity()}}) {
        const std::vector<Ray<T>> in = rays<T>(6, 2 * W + 1);
        check_all_forms(in, bad);
        std::vector<Hit<T>> out(in.size());
        intersect(std::span<const Ray<T>>(in), bad, certified, std::span<Hit<T>>(out));
        for (const Hit<T>& h : out) EXPECT_EQ(h.verdict, Verdict::invalid);
    }
}

// Batches over several of for_each_block's chunks (the double plane's full query lists
// each chunk's undecided rays, its hits, and answers them after the chunk's blocks), with
// the special rays across a chunk's boundary and a last, partial block: every element
// the scalar answer, for both shapes.
TYPED_TEST(Batch, LanesAcrossChunks) {
    using T = TypeParam;
    const std::size_t W = detail::batch::kBatchLanes, chunk = detail::batch::kFallbackChunk;
    const std::size_t n = 2 * chunk + 2 * W + 1;
    for (const std::size_t at : {chunk - 40, 2 * chunk - 30}) {
        check_all_forms(lane_rays<T>(31 + at, n, at, plane_special_rays<T>()), Plane<T>{v<T>(0, 1, 0), T(0.5)});
        check_all_forms(lane_rays<T>(41 + at, n, at, plane_special_rays<T>()), Plane<T>{v<T>(0.6f, 0, 0.8f), T(0.25)});
        check_all_forms(lane_rays<T>(51 + at, n, at), Aabb<T>{v<T>(-1, -1, -1), v<T>(1, 1, 1)});
    }
}

// The plane's lanes decide the common case: on the rays of rays() (less their 10% of
// invalid ones; the rest cross the plane 0.6x + 0.8y = 0.5 or miss it in general
// position) most lanes answer in lanes, in both backends and both forms. Float: the
// enclosure decides hits (with t) and misses, and a lane the full query decides the
// verdict decides alike. Double: the filter decides the verdicts, the full query
// answers its misses.
template <class B, class T> void expect_plane_lanes_decide() {
    const std::size_t W = detail::batch::kBatchLanes;
    const std::vector<Ray<T>> in = rays<T>(98, 400);
    const Plane<T> p{v<T>(0.6f, 0.8f, 0), T(0.5)};
    std::size_t decided = 0, hits = 0, misses = 0;
    for (std::size_t k = 0; k + W <= in.size(); k += W) {
        detail::batch::RayBlock<detail::batch::kBatchLanes> g;
        detail::batch::gather<Ray<T>, T>(in.data() + k, g);
        if constexpr (std::is_same_v<T, float>) {
            detail::batch::PlaneDecided<detail::batch::kBatchLanes> d, dv;
            detail::batch::plane_block<B, true>(g, p, d);
            detail::batch::plane_block<B, false>(g, p, dv);
            EXPECT_EQ(d.decided & ~dv.decided, 0u) << "block at " << k;
            EXPECT_EQ(d.decided & (d.hit ^ dv.hit), 0u) << "block at " << k;
            decided += std::size_t(std::popcount(d.decided));
            hits += std::size_t(std::popcount(d.decided & d.hit));
            misses += std::size_t(std::popcount(d.decided & ~d.hit));
        } else {
            const detail::batch::FilterDecided f = detail::batch::plane_filter_block<B>(g, p);
            decided += std::size_t(std::popcount(f.decided));
            hits += std::size_t(std::popcount(f.decided & f.hit));
            misses += std::size_t(std::popcount(f.decided & ~f.hit));
        }
    }
    EXPECT_GE(decided, in.size() * 4 / 5);
    EXPECT_GT(hits, in.size() / 5);
    EXPECT_GT(misses, in.size() / 5);
}

TYPED_TEST(Batch, PlaneLanesDecideTheCommonCase) {
    expect_plane_lanes_decide<simd::portable, TypeParam>();
    expect_plane_lanes_decide<simd::native, TypeParam>();
}
