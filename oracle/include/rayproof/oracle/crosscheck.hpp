// rayproof/oracle/crosscheck.hpp — a second, independent opinion for testing the oracle:
// CGAL's exact geometric predicates and constructions (Simple_cartesian<Gmpq>) and its
// algebraic numbers (Sqrt_extension) applied to the same inputs, without the oracle's
// slab or quadratic algebra.
//
// verdict(): the verdict by CGAL's predicates alone.
//   Aabb    do_intersect of a Segment_3, Ray_3 or Line_3 (the ray's range) with an
//           Iso_cuboid_3.
//   Obb     the box as six tetrahedra (a triangulation of the parallelepiped whose exact
//           rational corners are c + A^-T·(±h)); do_intersect with each.
//   Plane   do_intersect with a Plane_3.
//   Sphere  do_intersect with a Sphere_3 (ball semantics).
//
// answer(): the whole exact answer (verdict, t_enter, t_exit, face) by CGAL
// constructions.
//   Aabb    intersection() of the range with the Iso_cuboid_3; t of the end points.
//   Obb     the range mapped into the box frame by a CGAL Aff_transformation_3 (rows the
//           stored axes, exact rationals), intersection() with the Iso_cuboid_3
//           [-h, h] there (a degenerate cuboid for a flat box); t of the end points.
//   Plane   intersection() of the range with the Plane_3.
//   Sphere  the verdict from the Sphere_3 predicates; the roots of |o + t·d - c|² = r²
//           as CGAL Root_of_2 numbers (make_root_of_2); t_enter is t_min when the point
//           at t_min lies in the ball (bounded_side), else the smaller root, and t_exit
//           likewise.
//   ConvexPolyhedron  two linear programs solved exactly by CGAL's QP_solver over Gmpq,
//           in the point p and its parameter t (p - t·d = o, n_k·p <= offset_k, t_min <=
//           t <= t_max where finite): infeasible is a miss, t_enter the minimum of t,
//           t_exit the maximum (±inf when unbounded). Face: -1 when t_enter is t_min or
//           -inf; otherwise the first Plane_3, in index order, that holds the entry point
//           and whose normal the direction points against (negative scalar product); the
//           plane count when none qualifies (never, for a consistent answer).
//   Face (boxes): -1 when the point at t_min lies in the box (bounded_side); otherwise
//           the first of the six world-space Plane_3s, in face order, that holds the
//           entry point and whose inward normal the direction points along (positive
//           scalar product): for an Obb a_i·p = a_i·c ∓ h_i with inward normal ±a_i.
//           6 when no plane qualifies (never, for a consistent answer).
//
// compare(): where a float lies relative to an ExactValue, decided with CGAL's numbers
// (Gmpq, Sqrt_extension::compare) rather than ExactValue::compare; and the order of two
// ExactValues (the exact entries of two shapes, for the closest-hit order).
//
// verdict() and interval() answer std::nullopt when the input is invalid (the contract's
// validity rules are the oracle's business) or the construction does not apply (an Obb
// with a zero half extent has no non-degenerate tetrahedra); answer() answers
// Verdict::invalid for an invalid input.
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

// The whole exact answer by CGAL constructions (see above).
template <class T> Exact<T> answer(const Ray<T>& ray, const Aabb<T>& box);
template <class T> Exact<T> answer(const Ray<T>& ray, const Obb<T>& box);
template <class T> Exact<T> answer(const Ray<T>& ray, const Plane<T>& plane);
template <class T> Exact<T> answer(const Ray<T>& ray, const Sphere<T>& sphere);
template <class T> Exact<T> answer(const Ray<T>& ray, const ConvexPolyhedron<T>& poly);

// Where f lies relative to v (exact; -0 and +0 are both 0; unordered for NaN or no value).
Order compare(float f, const ExactValue& v);
Order compare(double f, const ExactValue& v);
// Where a lies relative to b (exact; ±inf ordered as usual; unordered when either has
// no value), by CGAL's Root_of_2 comparison across square-root extensions.
Order compare(const ExactValue& a, const ExactValue& b);

}  // namespace rayproof::oracle::crosscheck
