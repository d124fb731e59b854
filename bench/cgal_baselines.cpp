// bench/cgal_baselines.cpp — the CGAL do_intersect baselines (see cgal_baselines.hpp).
//
// Known to differ from the exact answer, and left as measured: CGAL 5.5's
// do_intersect(Line_3, Iso_cuboid_3) (bbox_line_do_intersect_aux) answers hit for a line
// parallel to two axes that lies in the plane of a face of the first one and outside the
// slab of the other (a 0/0 bound stands in for the third slab's test).
#include "cgal_baselines.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/intersections.h>

#include <cmath>
#include <type_traits>

namespace rayproof::bench::cgal {
namespace {

using Epeck = CGAL::Exact_predicates_exact_constructions_kernel;
using Rational = CGAL::Simple_cartesian<CGAL::Exact_rational>;

template <class K, class T> typename K::Point_3 point(const Vec3<T>& v) {
    return typename K::Point_3{double(v[0]), double(v[1]), double(v[2])};
}
template <class K, class T> typename K::Vector_3 vector(const Vec3<T>& v) {
    return typename K::Vector_3{double(v[0]), double(v[1]), double(v[2])};
}

template <class K, class T> typename K::Iso_cuboid_3 object(const Aabb<T>& b) {
    return typename K::Iso_cuboid_3{point<K>(b.lo), point<K>(b.hi)};
}
template <class K, class T> typename K::Sphere_3 object(const Sphere<T>& s) {
    const typename K::FT r{double(s.radius)};
    const typename K::FT r2 = r * r;
    return typename K::Sphere_3{point<K>(s.center), r2};
}
template <class K, class T> typename K::Plane_3 object(const Plane<T>& p) {
    return typename K::Plane_3{double(p.normal[0]), double(p.normal[1]), double(p.normal[2]), -double(p.offset)};
}

// Whether a point lies in the (closed) shape.
template <class K> bool contains(const typename K::Iso_cuboid_3& b, const typename K::Point_3& p) {
    return !b.has_on_unbounded_side(p);
}
template <class K> bool contains(const typename K::Sphere_3& s, const typename K::Point_3& p) {
    return !s.has_on_unbounded_side(p);
}
template <class K> bool contains(const typename K::Plane_3& pl, const typename K::Point_3& p) { return pl.has_on(p); }

template <class K, class T> typename K::Point_3 at(const typename K::Point_3& o, const typename K::Vector_3& d, T t) {
    if (t == 0) return o;
    const typename K::FT s{double(t)};
    return o + d * s;
}

template <class K, class T, class Shape> bool do_intersect_range(const Ray<T>& r, const Shape& shape) {
    const auto obj = object<K>(shape);
    const typename K::Point_3 o = point<K>(r.origin);
    const typename K::Vector_3 d = vector<K>(r.direction);
    const bool lo_inf = std::isinf(r.t_min), hi_inf = std::isinf(r.t_max);
    if (lo_inf && hi_inf) return CGAL::do_intersect(typename K::Line_3{o, d}, obj);
    if (hi_inf) return CGAL::do_intersect(typename K::Ray_3{at<K>(o, d, r.t_min), d}, obj);
    if (lo_inf) return CGAL::do_intersect(typename K::Ray_3{at<K>(o, d, r.t_max), -d}, obj);
    const typename K::Point_3 a = at<K>(o, d, r.t_min);
    if (r.t_min == r.t_max) return contains<K>(obj, a);
    const typename K::Segment_3 seg{a, at<K>(o, d, r.t_max)};
    // CGAL 5.5's Segment_3/Sphere_3 do_intersect answers for the sphere surface (false
    // when both ends are strictly inside), unlike its Ray_3 and Line_3 versions (ball):
    // a segment inside the ball is added here for the ball semantics.
    if constexpr (std::is_same_v<Shape, Sphere<T>>)
        if (contains<K>(obj, a)) return true;
    return CGAL::do_intersect(seg, obj);
}

// The exact slab loop over a polyhedron's planes (see cgal_baselines.hpp for why).
template <class K, class T> bool do_intersect_range(const Ray<T>& r, const ConvexPolyhedron<T>& p) {
    using FT = typename K::FT;
    bool lo_inf = std::isinf(r.t_min), hi_inf = std::isinf(r.t_max);  // -inf, +inf (valid rays)
    FT lo = lo_inf ? FT(0) : FT(double(r.t_min));
    FT hi = hi_inf ? FT(0) : FT(double(r.t_max));
    const typename K::Vector_3 o = vector<K>(r.origin);
    const typename K::Vector_3 d = vector<K>(r.direction);
    for (const Plane<T>& q : p.planes) {
        const typename K::Vector_3 n = vector<K>(q.normal);
        const FT den = n * d;
        const FT num = FT(double(q.offset)) - n * o;
        if (CGAL::is_zero(den)) {
            if (CGAL::is_negative(num)) return false;  // parallel, outside
            continue;
        }
        const FT t = num / den;
        if (CGAL::is_negative(den)) {
            if (lo_inf || t > lo) lo = t, lo_inf = false;
        } else if (hi_inf || t < hi) {
            hi = t, hi_inf = false;
        }
        if (!lo_inf && !hi_inf && lo > hi) return false;
    }
    return true;
}

}  // namespace

template <class T, class Shape> bool epeck(const Ray<T>& ray, const Shape& shape) {
    return do_intersect_range<Epeck>(ray, shape);
}
template <class T, class Shape> bool rational(const Ray<T>& ray, const Shape& shape) {
    return do_intersect_range<Rational>(ray, shape);
}

#define RAYPROOF_BENCH_CGAL_INSTANTIATE(T, S)                        \
    template bool epeck<T, S<T>>(const Ray<T>&, const S<T>&);        \
    template bool rational<T, S<T>>(const Ray<T>&, const S<T>&);
RAYPROOF_BENCH_CGAL_INSTANTIATE(float, Aabb)
RAYPROOF_BENCH_CGAL_INSTANTIATE(double, Aabb)
RAYPROOF_BENCH_CGAL_INSTANTIATE(float, Sphere)
RAYPROOF_BENCH_CGAL_INSTANTIATE(double, Sphere)
RAYPROOF_BENCH_CGAL_INSTANTIATE(float, Plane)
RAYPROOF_BENCH_CGAL_INSTANTIATE(double, Plane)
RAYPROOF_BENCH_CGAL_INSTANTIATE(float, ConvexPolyhedron)
RAYPROOF_BENCH_CGAL_INSTANTIATE(double, ConvexPolyhedron)
#undef RAYPROOF_BENCH_CGAL_INSTANTIATE

}  // namespace rayproof::bench::cgal
