// rayproof/normal.hpp — the outward unit normal at t_enter.
//
// Boxes: exact from the face id (the axis, or the stored Obb column normalized, with the
// sign of the side); no "closest face within a tolerance" guessing. face == -1 (the ray
// starts in the box, so there is no entry face) gives the zero vector: query
// reversed(ray) for the exit face. Sphere: (p - c)/|p - c| at p = o + t_enter·d (for a
// point sphere, or p == c, the direction opposing the ray). Plane: the unit normal
// facing the ray's origin side (against d; for a ray lying in the plane, n itself).
// ConvexPolyhedron: the entry plane's normal made unit (outward: the ray enters through
// plane k only where n_k·d < 0); face == -1 gives the zero vector, as for the boxes.
// A hit that is not Verdict::hit gives the zero vector. Unit vectors are made by
// detail::unit_vector (scaled exactly by a power of two first), so a normal or a
// direction with tiny, subnormal or huge components still gives a unit vector.
// Each normal is computed in the default floating-point environment whatever the
// caller's (detail/fp_env.hpp), for a hit of any mode: the scaling and the norm count on
// round-to-nearest and gradual underflow. The Aabb's needs no arithmetic.
#pragma once

#include <rayproof/detail/fp_env.hpp>
#include <rayproof/types.hpp>

#include <cmath>
#include <cstddef>

namespace rayproof {

namespace detail {
// v/|v| for v != 0 with finite components (the zero vector stays zero): v is scaled by
// 2^-e, e the exponent of its largest |component|, which is exact (a component scaled
// into the subnormal range loses bits below 2^-1022 of the largest, far below its
// rounding), so the largest lands in [1/2, 1) and neither the squares nor the norm can
// overflow or underflow; then Eigen's normalized(): three products and two sums (gamma(3)
// on the squared norm), a square root and a division, so each component is within
// gamma(4) (relative) of the exact unit vector's, with its sign.
template <class T> [[nodiscard]] Vec3<T> unit_vector(const Vec3<T>& v) noexcept {
    const T m = v.cwiseAbs().maxCoeff();
    if (!(m > 0) || !std::isfinite(m)) return v.normalized();
    int e = 0;
    (void)std::frexp(m, &e);
    Vec3<T> s;
    for (int i = 0; i < 3; ++i) s[i] = std::ldexp(v[i], -e);
    return s.normalized();
}
}  // namespace detail

template <class T> [[nodiscard]] Vec3<T> normal(const Aabb<T>&, const Hit<T>& h, const Ray<T>&) noexcept {
    Vec3<T> n = Vec3<T>::Zero();
    if (h.verdict != Verdict::hit || h.face < 0 || h.face > 5) return n;
    n[h.face / 2] = (h.face % 2) ? T(1) : T(-1);
    return n;
}

template <class T> [[nodiscard]] Vec3<T> normal(const Obb<T>& b, const Hit<T>& h, const Ray<T>& r) noexcept {
    return detail::in_default_fp_env(
        [](const Obb<T>& box, const Hit<T>& hit, const Ray<T>&) noexcept -> Vec3<T> {
            if (hit.verdict != Verdict::hit || hit.face < 0 || hit.face > 5) return Vec3<T>::Zero();
            const Vec3<T> a = detail::unit_vector<T>(box.axes.col(hit.face / 2));
            return (hit.face % 2) ? a : Vec3<T>(-a);
        },
        b, h, r);
}

template <class T> [[nodiscard]] Vec3<T> normal(const Sphere<T>& s, const Hit<T>& h, const Ray<T>& r) noexcept {
    return detail::in_default_fp_env(
        [](const Sphere<T>& sphere, const Hit<T>& hit, const Ray<T>& ray) noexcept -> Vec3<T> {
            if (hit.verdict != Verdict::hit) return Vec3<T>::Zero();
            // p - c scaled exactly before it is normalized (unit_vector): dividing by
            // v.norm() directly loses the unit length when |v| overflows (huge spheres)
            // or falls into the subnormal range (tiny ones).
            const Vec3<T> v = ray.origin + hit.t_enter * ray.direction - sphere.center;
            if (v.allFinite() && !v.isZero(0)) return detail::unit_vector<T>(v);
            return detail::unit_vector<T>(-ray.direction);
        },
        s, h, r);
}

template <class T> [[nodiscard]] Vec3<T> normal(const Plane<T>& p, const Hit<T>& h, const Ray<T>& r) noexcept {
    return detail::in_default_fp_env(
        [](const Plane<T>& plane, const Hit<T>& hit, const Ray<T>& ray) noexcept -> Vec3<T> {
            if (hit.verdict != Verdict::hit) return Vec3<T>::Zero();
            const Vec3<T> n = detail::unit_vector(plane.normal);
            return n.dot(ray.direction) > 0 ? Vec3<T>(-n) : n;
        },
        p, h, r);
}

template <class T>
[[nodiscard]] Vec3<T> normal(const ConvexPolyhedron<T>& poly, const Hit<T>& h, const Ray<T>& r) noexcept {
    return detail::in_default_fp_env(
        [](const ConvexPolyhedron<T>& p, const Hit<T>& hit, const Ray<T>&) noexcept -> Vec3<T> {
            if (hit.verdict != Verdict::hit || hit.face < 0 || std::size_t(hit.face) >= p.planes.size())
                return Vec3<T>::Zero();
            return detail::unit_vector<T>(p.planes[std::size_t(hit.face)].normal);
        },
        poly, h, r);
}

}  // namespace rayproof
