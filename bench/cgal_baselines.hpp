// bench/cgal_baselines.hpp — CGAL's exact do_intersect as a baseline, through a header
// that includes no CGAL (the CGAL code is compiled in one translation unit,
// cgal_baselines.cpp, so that CGAL's -frounding-math never reaches the timed kernel).
//
//   epeck     CGAL::Exact_predicates_exact_constructions_kernel (filtered, lazy exact)
//   rational  CGAL::Simple_cartesian<CGAL::Exact_rational> (plain rationals, no filter)
//
// The ray's range picks the CGAL object: [0, inf) and [t_min, inf) a Ray_3 (its source
// o + t_min·d constructed exactly), (-inf, t_max] a Ray_3 backwards, the whole line a
// Line_3, a finite range a Segment_3, a single parameter a Point_3. Shapes: Aabb as an
// Iso_cuboid_3, Sphere as a Sphere_3 (CGAL's do_intersect has ball semantics), Plane as
// a Plane_3. CGAL has no oriented box: Obb is not answered. Only the verdict is
// computed (do_intersect constructs no t); inputs must be valid.
//
// ConvexPolyhedron: CGAL has no do_intersect for a ray and an intersection of half-spaces.
// CGAL::halfspace_intersection_3 builds one as a Polyhedron_3, but only for a bounded,
// nonempty solid with a point strictly inside it given (the workloads hold unbounded,
// empty and flat ones), and each query would then pay for a convex hull, or for an AABB
// tree of its triangles (Side_of_triangle_mesh): a different question from one query on
// a fresh shape. The exact verdict here is therefore the slab loop over the planes with
// every number in the kernel's FT (Epeck: Lazy_exact_nt, interval-filtered, exact
// rationals behind; rational: Exact_rational), as CGAL's own Ray_3/Iso_cuboid_3
// do_intersect is a slab test in FT: num = offset - n·o, den = n·d, the exact crossing
// num/den, an entry where den < 0, an exit where den > 0, parallel (den == 0) a miss when
// num < 0; a hit when the latest entry (t_min at least) is not past the earliest exit
// (t_max at most).
#pragma once

#include <rayproof/types.hpp>

#include <span>

namespace rayproof::bench::cgal {

template <class Shape> inline constexpr bool supported = !std::is_same_v<Shape, Obb<float>> && !std::is_same_v<Shape, Obb<double>>;

// One query. Explicitly instantiated for Aabb, Plane, Sphere and ConvexPolyhedron in float
// and double.
template <class T, class Shape> bool epeck(const Ray<T>& ray, const Shape& shape);
template <class T, class Shape> bool rational(const Ray<T>& ray, const Shape& shape);

}  // namespace rayproof::bench::cgal
