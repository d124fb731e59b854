// rayproof/generators.hpp — the shared case generators and their registry.
//
//   rayproof::gen::Rng rng(seed);
//   for (const auto& g : rayproof::gen::generators<double, rayproof::Aabb<double>>())
//       auto c = g.make(rng);   // c.ray, c.shape, c.generator == g.name
//
// Every generator is a plain function of a seeded std::mt19937_64 (no RapidCheck), so the
// property suites, the fuzz targets, the benchmarks and the audit tool draw identical
// cases from identical seeds. They aim at the hard inputs, not only uniform ones:
//   general       general position, moderate magnitudes, about half the rays hit
//   log_uniform   every number log-uniform over the whole exponent range, denormals,
//                 ±0 and the other special values included
//   grazing       exact grazing: through a box corner or edge point, exactly tangent to a
//                 sphere, lying exactly in a plane (integer geometry moved by exact
//                 translations and power-of-two scalings)
//   near_grazing  the grazing rays with the direction (or a coordinate) moved by one ulp
//   parallel      direction components ±0 / exactly perpendicular to a box axis, origins
//                 inside, outside and exactly on the slab planes
//   on_boundary   origins exactly on faces, edges, corners, the sphere, the plane; t_min
//                 or t_max exactly at the entry
//   extreme       tiny shapes far away, huge shapes, denormal-sized shapes, nearly
//                 parallel planes, a plane crossing near the top of the range next to
//                 a limit, nearly dependent Obb axes
//   rotated_integer (Obb) integer, non-normalized, rotated or sheared axes
//   duplicates, unbounded, infeasible, many_planes   (ConvexPolyhedron, whose cases hold
//                 their planes in an OwnedPolyhedron: see ray_polyhedron.hpp)
//   invalid       one invalid input class of the contract per case, every class drawn
#pragma once

#include <rayproof/generators/ray_aabb.hpp>
#include <rayproof/generators/core.hpp>
#include <rayproof/generators/ray_obb.hpp>
#include <rayproof/generators/ray_plane.hpp>
#include <rayproof/generators/ray_polyhedron.hpp>
#include <rayproof/generators/ray_sphere.hpp>

#include <span>
#include <string_view>

namespace rayproof::gen {

template <class T, class Shape> struct Generator {
    std::string_view name;
    Case<T, Shape> (*make)(Rng&);
};

namespace detail {
// The families every shape has, in registry order: shape_general<T>, ..., shape_extreme<T>
// (the invalid one comes last, after any family of the shape's own).
#define RAYPROOF_GEN_FAMILIES(shape)                                                                       \
    {"general", shape##_general<T>}, {"log_uniform", shape##_log_uniform<T>}, {"grazing", shape##_grazing<T>},  \
        {"near_grazing", shape##_near_grazing<T>}, {"parallel", shape##_parallel<T>},                          \
        {"on_boundary", shape##_on_boundary<T>}, {"extreme", shape##_extreme<T>}

template <class T, class Shape> struct Registry;
template <class T> struct Registry<T, Aabb<T>> {
    static constexpr Generator<T, Aabb<T>> list[] = {RAYPROOF_GEN_FAMILIES(aabb), {"invalid", aabb_invalid<T>}};
};
template <class T> struct Registry<T, Obb<T>> {
    static constexpr Generator<T, Obb<T>> list[] = {
        RAYPROOF_GEN_FAMILIES(obb), {"rotated_integer", obb_rotated_integer<T>}, {"invalid", obb_invalid<T>}};
};
template <class T> struct Registry<T, Plane<T>> {
    static constexpr Generator<T, Plane<T>> list[] = {RAYPROOF_GEN_FAMILIES(plane), {"invalid", plane_invalid<T>}};
};
template <class T> struct Registry<T, Sphere<T>> {
    static constexpr Generator<T, Sphere<T>> list[] = {RAYPROOF_GEN_FAMILIES(sphere), {"invalid", sphere_invalid<T>}};
};
// Polyhedron cases own their planes (OwnedPolyhedron, ray_polyhedron.hpp).
template <class T> struct Registry<T, OwnedPolyhedron<T>> {
    static constexpr Generator<T, OwnedPolyhedron<T>> list[] = {
        RAYPROOF_GEN_FAMILIES(polyhedron),        {"duplicates", polyhedron_duplicates<T>},
        {"unbounded", polyhedron_unbounded<T>},   {"infeasible", polyhedron_infeasible<T>},
        {"many_planes", polyhedron_many_planes<T>}, {"invalid", polyhedron_invalid<T>}};
};
#undef RAYPROOF_GEN_FAMILIES
}  // namespace detail

// All generators for one shape, in a fixed order.
template <class T, class Shape> constexpr std::span<const Generator<T, Shape>> generators() {
    return detail::Registry<T, Shape>::list;
}

// The polyhedron generators (their cases own the planes: c.shape.view() is the shape).
template <class T> constexpr std::span<const Generator<T, OwnedPolyhedron<T>>> polyhedron_generators() {
    return generators<T, OwnedPolyhedron<T>>();
}

// The generator with this name, or nullptr.
template <class T, class Shape> const Generator<T, Shape>* find_generator(std::string_view name) {
    for (const auto& g : generators<T, Shape>())
        if (g.name == name) return &g;
    return nullptr;
}

// The case that generator `name` makes from `seed` (a fresh Rng), so that a printed
// (name, seed) pair reproduces it. Precondition: the name is registered for the shape.
template <class T, class Shape> Case<T, Shape> make_case(std::string_view name, std::uint64_t seed) {
    Rng rng(seed);
    return find_generator<T, Shape>(name)->make(rng);
}

// The shape names, in the spelling used by the tools and the tests.
template <class Shape> constexpr std::string_view shape_name();
template <> constexpr std::string_view shape_name<Aabb<float>>() { return "aabb"; }
template <> constexpr std::string_view shape_name<Aabb<double>>() { return "aabb"; }
template <> constexpr std::string_view shape_name<Obb<float>>() { return "obb"; }
template <> constexpr std::string_view shape_name<Obb<double>>() { return "obb"; }
template <> constexpr std::string_view shape_name<Plane<float>>() { return "plane"; }
template <> constexpr std::string_view shape_name<Plane<double>>() { return "plane"; }
template <> constexpr std::string_view shape_name<Sphere<float>>() { return "sphere"; }
template <> constexpr std::string_view shape_name<Sphere<double>>() { return "sphere"; }
template <> constexpr std::string_view shape_name<OwnedPolyhedron<float>>() { return "polyhedron"; }
template <> constexpr std::string_view shape_name<OwnedPolyhedron<double>>() { return "polyhedron"; }

template <class T> constexpr std::string_view scalar_name() { return std::is_same_v<T, float> ? "float" : "double"; }

}  // namespace rayproof::gen
