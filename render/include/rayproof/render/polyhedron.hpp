// rayproof/render/polyhedron.hpp — the scene's convex polyhedra: the owning storage of
// their planes (the kernel's ConvexPolyhedron is a non-owning span over it), the exact
// convex hull of given points, the presets, and the bounding sphere of the pre-filter.
//
// Solid: { p : planes[k].normal·p <= planes[k].offset for every k } (normals point out),
// as the kernel defines it (rayproof/ray_polyhedron.hpp).
//
// Hull (convex_hull): the facets are decided with exact orientation predicates: for
// points a, b, c, d, orient = ((b - a) × (c - a))·(d - a), the determinant of the exact
// differences, evaluated in Shewchuk expansions (BigDyadic outside their safe range,
// rayproof/detail/exact.hpp), never rounded. A triple (a, b, c) spans a facet when no
// point lies strictly on each side of its plane; the facet is kept once per plane (the
// set of points on it identifies it). Its plane is stored exactly when it can be:
// n = (b - a) × (c - a) and offset = n·a, computed exactly, then divided exactly by
// |n_0|, |n_1|, |n_2| (the nonzero ones) or 1 (a positive factor: the same
// half-space), the first division whose four quotients are all doubles. Integer and dyadic points of
// moderate size give exact planes (n and n·a fit in a double), and so do planes like
// h·x + y <= 1 + h whose normal is a multiple of a double vector (the dodecahedron
// preset). Then the stored solid is exactly the hull of the points (HullResult::exact).
// Otherwise the stored normal is m = n/max|n_j| faithfully rounded (each component one
// of the two doubles enclosing it; never zero) and the stored offset is the smallest
// double >= max over all the points of m·p, decided exactly: every given point then
// satisfies every stored inequality exactly, so the stored solid contains the hull
// (never loses a point of it), and each facet's points lie within HullResult::slack of
// its stored plane (computed in double: the largest (offset - m·p)/|m| over the facet's
// points, an a-posteriori measure of the difference, reported, not a rigorous bound).
// Refused (HullResult::error): fewer than 4 points, more than max_hull_points, a point
// given twice, all points on one line or on one plane (no solid).
// Cost: O(n^3) triples, each rejected at the first point on its far side; n <= 64.
//
// Bounding sphere (enclosing_sphere): c = the midpoint of the points' bounding box (any c
// works), R >= max |p - c| rigorously, rounded up: with d_i = fl(p_i - c_i), s = fl(Σ d_i²)
// and l = fl(sqrt(s)), the exact distance D satisfies D <= l/(1 - u)^3.5 + 2^-535 (one
// rounding per difference, product and sum, 2^-1075 per product in the subnormal range,
// one in the root); R = next_up(fl(fl(l·(1 + 16u)) + 2^-500)) exceeds it, since
// (1 + 16u)(1 - u) > (1 - u)^-3.5 and 2^-500 covers the absolute terms (next_up covers
// the last addition's rounding). The ball (exact center and radius, as the kernel takes
// them) then holds every point, hence their hull. Only a hull whose planes are exact
// gets one: the stored solid is then the hull; otherwise the stored solid is a little
// larger than the hull and no ball is claimed (no pre-filter), nor for plane-given
// polyhedra, which may be unbounded.
#pragma once

#include <rayproof/types.hpp>

#include <Eigen/Core>

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rayproof::render {

// Scene limits: the planes of one polyhedron and the points of one hull.
inline constexpr std::size_t max_polyhedron_planes = 256;
inline constexpr std::size_t max_hull_points = 64;

struct Polyhedron {
    std::vector<Plane<double>> planes;        // the owning storage
    bool exact = true;                        // planes given, or a hull stored exactly (see above)
    double slack = 0;                         // a hull stored inexactly: HullResult::slack
    std::optional<Sphere<double>> bound;      // encloses the stored solid: the pre-filter
    ConvexPolyhedron<double> kernel() const { return ConvexPolyhedron<double>{std::span<const Plane<double>>(planes)}; }
};

struct HullResult {
    std::vector<Plane<double>> planes;  // one per facet, outward normals
    bool exact = true;                  // the stored solid is exactly the hull
    double slack = 0;                   // largest distance of a facet's point from its stored plane
    std::string error;                  // non-empty: refused, and why
};

// The exact convex hull of the points (see the header comment). Finite coordinates.
HullResult convex_hull(std::span<const Eigen::Vector3d> points);

// A ball that holds every point exactly (see the header comment); nullopt for no points.
std::optional<Sphere<double>> enclosing_sphere(std::span<const Eigen::Vector3d> points);

// The exact orientation sign of d against the plane through a, b, c:
// sign(((b - a) × (c - a))·(d - a)).
int orient(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& d);

// The presets' points before center and size: the polyhedron is the hull of
// center + size·v over these v (each coordinate rounded to a double). Empty for an unknown
// name. Names: preset_names.
//   tetrahedron   (1,1,1), (1,-1,-1), (-1,1,-1), (-1,-1,1)           planes ±x±y±z <= 1 (odd -)
//   octahedron    ±e_x, ±e_y, ±e_z                                    planes ±x ±y ±z <= 1
//   prism         the triangle (-1,-1), (1,-1), (0,1) in x, y, for z = ±1: planes -y <= 1,
//                 2x + y <= 1, -2x + y <= 1, ±z <= 1
//   cube          (±1, ±1, ±1)
//   dodecahedron  the pyritohedron (±1,±1,±1), (0, ±(1+h), ±(1-h²)) and its cyclic
//                 permutations, h = round(2^13/φ)/2^13 (φ the golden ratio): every
//                 coordinate is a double of at most 26 significant bits, its 12 planes
//                 are exactly (±h, ±1, 0)·p <= 1 + h and their cyclic permutations; at
//                 h = 1/φ it would be the regular dodecahedron, from which this one
//                 differs by less than 2^-12 of its size (|h - 1/φ| <= 2^-14)
// The few significant bits keep center + size·v exact for a center and a size of few
// bits (0.75, 1.5, 2.25, ...). Otherwise the points are rounded: the hull of the rounded
// points is what is stored (for the dodecahedron its pentagons may then split into
// facets of slightly different planes, and the planes may be inexact, see above).
std::vector<Eigen::Vector3d> preset_points(std::string_view name);
inline constexpr const char* preset_names = "tetrahedron, octahedron, prism, cube, dodecahedron";
// h of the dodecahedron preset.
double dodecahedron_h();

}  // namespace rayproof::render
