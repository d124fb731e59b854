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
#pragma once

#include <rayproof/types.hpp>

#include <span>

namespace rayproof::bench::cgal {

template <class Shape> inline constexpr bool supported = !std::is_same_v<Shape, Obb<float>> && !std::is_same_v<Shape, Obb<double>>;

// One query. Explicitly instantiated for Aabb, Plane and Sphere in float and double.
template <class T, class Shape> bool epeck(const Ray<T>& ray, const Shape& shape);
template <class T, class Shape> bool rational(const Ray<T>& ray, const Shape& shape);

}  // namespace rayproof::bench::cgal
