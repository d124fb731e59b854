// The batch form against the scalar form, element by element, for every shape, scalar
// type and mode the kernel has, on seeded random rays mixed with parallel, grazing and
// invalid ones, as the contract words it: certified answers identical (verdict, both t
// values bit for bit, face); fast and conservative answers may round differently (a
// vectorized or contracted path is free to), so they must agree on validity, and each
// conservative answer, batch and scalar, must hit wherever the certified one does with
// an interval reaching the certified ends' outer neighbours (the exact ends lie within
// them). An invalid shape makes every element invalid; a size mismatch is refused with
// std::invalid_argument.
#include "same_hit.hpp"
#include "unit_support.hpp"

#include <cstring>
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
    std::vector<Hit<T>> short_out(in.size() - 1);
    EXPECT_THROW(intersect(std::span<const Ray<T>>(in), s, m, std::span<Hit<T>>(short_out)), std::invalid_argument);
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
