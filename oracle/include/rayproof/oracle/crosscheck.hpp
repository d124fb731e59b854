// rayproof/oracle/crosscheck.hpp — a second, independent opinion for testing the oracle:
// CGAL's exact geometric predicates and constructions (Simple_cartesian<Gmpq>) applied
// to the same inputs, without the oracle's slab or quadratic algebra.
//
//   Aabb    do_intersect / intersection of a Segment_3, Ray_3 or Line_3 (the ray's range)
//           with an Iso_cuboid_3; t of the intersection's end points.
//   Obb     the box as six tetrahedra (a triangulation of the parallelepiped whose exact
//           rational corners are c + A^-T·(±h)); do_intersect with each.
//   Plane   do_intersect / intersection with a Plane_3; t of the point, or the whole range.
//   Sphere  do_intersect with a Sphere_3 (ball semantics).
//
// Each answers std::nullopt when the input is invalid (the contract's validity rules are
// the oracle's business) or the construction does not apply (an Obb with a zero half
// extent has no non-degenerate tetrahedra).
#pragma once

#include <rayproof/oracle/oracle.hpp>

#include <optional>

namespace rayproof::oracle::crosscheck {

template <class T> std::optional<Verdict> verdict(const Ray<T>& ray, const Aabb<T>& box);
template <class T> std::optional<Verdict> verdict(const Ray<T>& ray, const Obb<T>& box);
template <class T> std::optional<Verdict> verdict(const Ray<T>& ray, const Plane<T>& plane);
template <class T> std::optional<Verdict> verdict(const Ray<T>& ray, const Sphere<T>& sphere);

// The exact [t_enter, t_exit] from CGAL's intersection constructions (nullopt: invalid
// input or a miss).
struct Interval {
    ExactValue t_enter, t_exit;
};
template <class T> std::optional<Interval> interval(const Ray<T>& ray, const Aabb<T>& box);
template <class T> std::optional<Interval> interval(const Ray<T>& ray, const Plane<T>& plane);

}  // namespace rayproof::oracle::crosscheck
