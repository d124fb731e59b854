// bench/workloads.hpp — the workloads of the speed/accuracy trade, drawn from the shared
// case generators (rayproof::gen), so that the timings, the accuracy judgements and the
// exact-stage counts are made on the very same (ray, shape) pairs: a workload is a pure
// function of (shape, scalar type, workload name, seed, count).
//
//   uniform    the `general` generator: general position, about half the rays hit
//   grazing    grazing-heavy: `grazing` and `near_grazing` cases alternately (exact
//              touches of corners, edges, tangents, in-plane rays, and the same a hair off)
//   parallel   parallel-heavy: the `parallel` generator (±0 direction components, origins
//              on and off the slab planes)
//   extreme    the `extreme` generator (tiny far shapes, huge shapes, denormal sizes, ...)
//   far_small  far small shapes: the `extreme` cases of the "tiny and far" kind, kept by
//              rejection (origin in [-1, 1]³, the shape at least 2^20 away and at most
//              2^-9 of that distance across, nonzero size); Aabb, Obb and Sphere
//
// A convex polyhedron's case owns its planes (gen::OwnedPolyhedron); kernel_shape() is the
// kernel's ConvexPolyhedron over them (a span, built per query at no cost), the other
// shapes' cases are the kernel's shapes already. Its workloads are the same generators'
// (general: 4 to 12 random planes around a centre; grazing: rays exactly through a
// vertex, along an edge or in a face plane of an integer polytope, and those an ulp
// off; parallel; extreme). It has no far_small (it has no one size) and no batch sweep
// (the batch form aims uniform rays at one shape by its centre, which a polyhedron's
// planes do not state).
//
// The batch form answers many rays against one shape: batch_workload() takes the uniform
// cases and translates each ray by the difference of the shapes' centres, so that every
// ray is aimed at the first case's shape as it was at its own (uniform rays only: the
// translation is rounded, which does not matter for general-position input).
#pragma once

#include <rayproof/generators.hpp>
#include <rayproof/rayproof.hpp>

#include <cmath>
#include <cstdint>
#include <span>
#include <string_view>
#include <type_traits>
#include <vector>

namespace rayproof::bench {

using gen::Case;

inline constexpr std::uint64_t kDefaultSeed = 20240611;

// The workloads in report order.
inline constexpr std::string_view kWorkloads[] = {"uniform", "grazing", "parallel", "extreme", "far_small"};

template <class Shape> inline constexpr bool is_plane_v =
    std::is_same_v<Shape, Plane<float>> || std::is_same_v<Shape, Plane<double>>;

template <class Shape> inline constexpr bool is_polyhedron_v =
    std::is_same_v<Shape, gen::OwnedPolyhedron<float>> || std::is_same_v<Shape, gen::OwnedPolyhedron<double>>;

// Whether the workload exists for the shape (a plane or a polyhedron has no one size: no
// far_small).
template <class Shape> constexpr bool has_workload(std::string_view w) {
    return !(w == "far_small" && (is_plane_v<Shape> || is_polyhedron_v<Shape>));
}

// The kernel's shape of a case's shape: itself, or the ConvexPolyhedron over the owned planes.
template <class S> constexpr const S& kernel_shape(const S& s) { return s; }
template <class T> ConvexPolyhedron<T> kernel_shape(const gen::OwnedPolyhedron<T>& p) { return p.view(); }

namespace detail {

template <class T> constexpr T kFar = T(0x1p20);

template <class T> bool small_origin(const Ray<T>& r) { return r.origin.cwiseAbs().maxCoeff() <= T(1); }

template <class T> bool far_small(const Case<T, Aabb<T>>& c) {
    const Vec3<T> centre = (c.shape.lo / 2 + c.shape.hi / 2);
    const T dist = centre.cwiseAbs().maxCoeff();
    const T size = (c.shape.hi - c.shape.lo).maxCoeff();
    return small_origin(c.ray) && dist >= kFar<T> && size > 0 && size <= std::ldexp(dist, -9);
}
template <class T> bool far_small(const Case<T, Obb<T>>& c) {
    const T dist = c.shape.center.cwiseAbs().maxCoeff();
    T size = 0;  // half the diagonal bound: sum of |axis_i| * half_extent_i
    for (int i = 0; i < 3; ++i) size += c.shape.axes.col(i).cwiseAbs().maxCoeff() * c.shape.half_extent[i];
    return small_origin(c.ray) && std::isfinite(size) && dist >= kFar<T> && size > 0 &&
           size <= std::ldexp(dist, -9);
}
template <class T> bool far_small(const Case<T, Sphere<T>>& c) {
    const T dist = c.shape.center.cwiseAbs().maxCoeff();
    return small_origin(c.ray) && dist >= kFar<T> && c.shape.radius > 0 && c.shape.radius <= std::ldexp(dist, -9);
}
template <class T> bool far_small(const Case<T, Plane<T>>&) { return false; }
template <class T> bool far_small(const Case<T, gen::OwnedPolyhedron<T>>&) { return false; }

// The generator that a single-generator workload draws from ("" for the mixed ones).
constexpr std::string_view single_generator(std::string_view workload) {
    if (workload == "uniform") return "general";
    if (workload == "parallel" || workload == "extreme") return workload;
    return "";
}

}  // namespace detail

// The seeded RNG of a generator or a workload, for one shape and scalar type.
template <class T, class Shape> gen::Rng seeded_rng(std::string_view name, std::uint64_t seed) {
    return gen::Rng(seed ^ gen::name_hash(name) ^ (gen::name_hash(gen::shape_name<Shape>()) << 1) ^
                    (gen::name_hash(gen::scalar_name<T>()) << 2));
}

// The first n cases of one registered generator for a seed.
template <class T, class Shape>
std::vector<Case<T, Shape>> generator_cases(std::string_view generator, std::size_t n,
                                            std::uint64_t seed = kDefaultSeed) {
    const auto* g = gen::find_generator<T, Shape>(generator);
    gen::Rng rng = seeded_rng<T, Shape>(generator, seed);
    std::vector<Case<T, Shape>> cases;
    cases.reserve(n);
    for (std::size_t i = 0; i < n; ++i) cases.push_back(g->make(rng));
    return cases;
}

// The first n cases of a workload for a seed (a prefix of the same sequence for any n).
// A single-generator workload is exactly that generator's sequence (uniform: the first
// n cases of `general`, the ones the exact-stage counts are made on).
template <class T, class Shape>
std::vector<Case<T, Shape>> workload(std::string_view name, std::size_t n, std::uint64_t seed = kDefaultSeed) {
    if (const auto g = detail::single_generator(name); !g.empty()) return generator_cases<T, Shape>(g, n, seed);
    gen::Rng rng = seeded_rng<T, Shape>(name, seed);
    std::vector<Case<T, Shape>> cases;
    cases.reserve(n);
    if (name == "grazing") {
        const auto* exact = gen::find_generator<T, Shape>("grazing");
        const auto* near = gen::find_generator<T, Shape>("near_grazing");
        for (std::size_t i = 0; i < n; ++i) cases.push_back((i % 2 ? near : exact)->make(rng));
    } else {  // far_small: the tiny-and-far extreme cases, by rejection
        const auto* g = gen::find_generator<T, Shape>("extreme");
        while (cases.size() < n) {
            Case<T, Shape> c = g->make(rng);
            if (detail::far_small(c)) cases.push_back(c);
        }
    }
    return cases;
}

// A stand-in for the centre of a shape (for the batch translation only).
template <class T> Vec3<T> centre_of(const Aabb<T>& b) { return b.lo / 2 + b.hi / 2; }
template <class T> Vec3<T> centre_of(const Obb<T>& b) { return b.center; }
template <class T> Vec3<T> centre_of(const Sphere<T>& s) { return s.center; }
template <class T> Vec3<T> centre_of(const Plane<T>& p) {
    return p.normal * (p.offset / p.normal.squaredNorm());
}

// One shape (the first uniform case's) and n uniform rays aimed at it.
template <class T, class Shape> struct Batch {
    Shape shape;
    std::vector<Ray<T>> rays;
};
template <class T, class Shape> Batch<T, Shape> batch_workload(std::size_t n, std::uint64_t seed = kDefaultSeed) {
    const auto cases = workload<T, Shape>("uniform", n, seed);
    Batch<T, Shape> b{cases.front().shape, {}};
    b.rays.reserve(n);
    const Vec3<T> c0 = centre_of(b.shape);
    for (const auto& c : cases) {
        Ray<T> r = c.ray;
        r.origin += c0 - centre_of(c.shape);
        b.rays.push_back(r);
    }
    return b;
}

}  // namespace rayproof::bench
