// The run-time mode (RuntimeMode) against the mode tags: for every shape, scalar type and
// mode, intersect(ray, shape, RuntimeMode) and verdict(ray, shape, RuntimeMode), scalar
// and batch, give the tag's answer bit for bit, on every shared case generator's cases
// (general, log-uniform, grazing, near grazing, parallel, on the boundary, extreme,
// invalid); a value outside the enumerators is invalid input; to_string and parse_mode
// are inverse; the scalar forms are noexcept.
#include "same_hit.hpp"
#include "seeded.hpp"

#include <rayproof/generators.hpp>
#include <rayproof/rayproof.hpp>

#include <gtest/gtest.h>

#include <cstring>
#include <sstream>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

using namespace rayproof;

namespace {

std::uint64_t base_seed() {
    static const std::uint64_t s = rayproof::testing::env_seed_or(23);
    return s;
}

using rayproof::testing::same_bits;
using rayproof::testing::same_hit;

constexpr RuntimeMode every_mode[] = {RuntimeMode::fast, RuntimeMode::conservative, RuntimeMode::certified};

// The tag of a run-time mode, handed to f.
template <class F> void with_tag(RuntimeMode m, F&& f) {
    switch (m) {
        case RuntimeMode::fast: f(fast); return;
        case RuntimeMode::conservative: f(conservative); return;
        case RuntimeMode::certified: f(certified); return;
    }
    FAIL() << "not a mode";
}

constexpr int kCasesPerGenerator = 300;

template <class T, class Shape> void check_dispatch() {
    std::mt19937_64 rng = rayproof::testing::rng_for_current_test(base_seed());
    RAYPROOF_SEED_TRACE(base_seed());
    for (const auto& g : gen::generators<T, Shape>()) {
        std::vector<Ray<T>> rays;
        std::vector<Shape> shapes;
        for (int i = 0; i < kCasesPerGenerator; ++i) {
            const gen::Case<T, Shape> c = g.make(rng);
            rays.push_back(c.ray);
            shapes.push_back(c.shape);
        }
        for (const RuntimeMode m : every_mode) {
            with_tag(m, [&](auto tag) {
                for (std::size_t i = 0; i < rays.size(); ++i) {
                    SCOPED_TRACE(::testing::Message() << g.name << ' ' << to_string(m) << ": " << rays[i] << ' '
                                                      << shapes[i]);
                    ASSERT_TRUE(same_hit(intersect(rays[i], shapes[i], m), intersect(rays[i], shapes[i], tag)));
                    ASSERT_EQ(verdict(rays[i], shapes[i], m), verdict(rays[i], shapes[i], tag));
                }
                // The batch forms against the tag's batch forms, on one shape and every ray.
                const Shape& s = shapes.front();
                std::vector<Hit<T>> by_mode(rays.size()), by_tag(rays.size());
                std::vector<Verdict> v_mode(rays.size()), v_tag(rays.size());
                intersect(std::span<const Ray<T>>(rays), s, m, std::span<Hit<T>>(by_mode));
                intersect(std::span<const Ray<T>>(rays), s, tag, std::span<Hit<T>>(by_tag));
                verdict(std::span<const Ray<T>>(rays), s, m, std::span<Verdict>(v_mode));
                verdict(std::span<const Ray<T>>(rays), s, tag, std::span<Verdict>(v_tag));
                for (std::size_t i = 0; i < rays.size(); ++i) {
                    ASSERT_TRUE(same_hit(by_mode[i], by_tag[i])) << g.name << ' ' << to_string(m) << " element " << i;
                    ASSERT_EQ(v_mode[i], v_tag[i]) << g.name << ' ' << to_string(m) << " element " << i;
                }
            });
        }
    }
}

template <class T> void check_every_shape() {
    check_dispatch<T, Aabb<T>>();
    check_dispatch<T, Obb<T>>();
    check_dispatch<T, Plane<T>>();
    check_dispatch<T, Sphere<T>>();
}

}  // namespace

TEST(RuntimeMode, DispatchEqualsTheTagFloat) { check_every_shape<float>(); }
TEST(RuntimeMode, DispatchEqualsTheTagDouble) { check_every_shape<double>(); }

TEST(RuntimeMode, OutOfRangeValueIsInvalid) {
    const auto bad = static_cast<RuntimeMode>(7);
    const Ray<double> r{Vec3<double>(-4, 0, 0), Vec3<double>(1, 0, 0)};
    const Sphere<double> s{Vec3<double>(0, 0, 0), 1};
    ASSERT_EQ(intersect(r, s, RuntimeMode::certified).verdict, Verdict::hit);
    EXPECT_EQ(intersect(r, s, bad).verdict, Verdict::invalid);
    EXPECT_EQ(verdict(r, s, bad), Verdict::invalid);
    const std::vector<Ray<double>> rays(3, r);
    std::vector<Hit<double>> out(3);
    std::vector<Verdict> vs(3, Verdict::hit);
    intersect(std::span<const Ray<double>>(rays), s, bad, std::span<Hit<double>>(out));
    verdict(std::span<const Ray<double>>(rays), s, bad, std::span<Verdict>(vs));
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(out[std::size_t(i)].verdict, Verdict::invalid);
        EXPECT_EQ(vs[std::size_t(i)], Verdict::invalid);
    }
    std::vector<Hit<double>> short_out(2);
    EXPECT_THROW(intersect(std::span<const Ray<double>>(rays), s, bad, std::span<Hit<double>>(short_out)),
                 std::invalid_argument);
    EXPECT_THROW(intersect(std::span<const Ray<double>>(rays), s, RuntimeMode::fast, std::span<Hit<double>>(short_out)),
                 std::invalid_argument);
    EXPECT_STREQ(to_string(bad), "?");
}

TEST(RuntimeMode, NamesRoundTrip) {
    EXPECT_STREQ(to_string(RuntimeMode::fast), mode_name(fast));
    EXPECT_STREQ(to_string(RuntimeMode::conservative), mode_name(conservative));
    EXPECT_STREQ(to_string(RuntimeMode::certified), mode_name(certified));
    for (const RuntimeMode m : every_mode) {
        ASSERT_TRUE(parse_mode(to_string(m)).has_value());
        EXPECT_EQ(*parse_mode(to_string(m)), m);
        std::ostringstream os;
        os << m;
        EXPECT_EQ(os.str(), to_string(m));
    }
    for (const char* wrong : {"", "Fast", "fast ", "exact", "certifie", "?", "conservative\n"})
        EXPECT_FALSE(parse_mode(wrong).has_value()) << wrong;
    static_assert(parse_mode("certified") == RuntimeMode::certified);
    static_assert(!parse_mode("none"));
}

TEST(RuntimeMode, ScalarFormsAreNoexcept) {
    const Ray<float> r{};
    const Aabb<float> b{};
    static_assert(noexcept(intersect(r, b, RuntimeMode::fast)));
    static_assert(noexcept(verdict(r, b, RuntimeMode::fast)));
    static_assert(noexcept(intersect(r, b, certified)));
    static_assert(noexcept(verdict(r, b, certified)));
    static_assert(noexcept(normal(b, Hit<float>{}, r)));
    static_assert(noexcept(reversed(r)));
    static_assert(!noexcept(intersect(std::span<const Ray<float>>(), b, fast, std::span<Hit<float>>())));
    SUCCEED();
}
