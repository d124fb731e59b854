// rayproof/normal.hpp — the outward unit normal at t_enter.
//
// Boxes: exact from the face id (the axis, or the stored Obb column normalized, with the
// sign of the side); no "closest face within a tolerance" guessing. face == -1 (the ray
// starts in the box, so there is no entry face) gives the zero vector: query
// reversed(ray) for the exit face. Sphere: (p - c)/|p - c| at p = o + t_enter·d (for a
// point sphere, or p == c, the direction opposing the ray). Plane: the unit normal
// facing the ray's origin side (against d; for a ray lying in the plane, n itself).
// A hit that is not Verdict::hit gives the zero vector.
#pragma once

#include <rayproof/types.hpp>

namespace rayproof {

template <class T> [[nodiscard]] Vec3<T> normal(const Aabb<T>&, const Hit<T>& h, const Ray<T>&) noexcept {
    Vec3<T> n = Vec3<T>::Zero();
    if (h.verdict != Verdict::hit || h.face < 0 || h.face > 5) return n;
    n[h.face / 2] = (h.face % 2) ? T(1) : T(-1);
    return n;
}

template <class T> [[nodiscard]] Vec3<T> normal(const Obb<T>& b, const Hit<T>& h, const Ray<T>&) noexcept {
    if (h.verdict != Verdict::hit || h.face < 0 || h.face > 5) return Vec3<T>::Zero();
    const Vec3<T> a = b.axes.col(h.face / 2).normalized();
    return (h.face % 2) ? a : Vec3<T>(-a);
}

template <class T> [[nodiscard]] Vec3<T> normal(const Sphere<T>& s, const Hit<T>& h, const Ray<T>& r) noexcept {
    if (h.verdict != Verdict::hit) return Vec3<T>::Zero();
    const Vec3<T> v = r.origin + h.t_enter * r.direction - s.center;
    const T len = v.norm();
    if (len > 0 && std::isfinite(len)) return v / len;
    return -r.direction.normalized();
}

template <class T> [[nodiscard]] Vec3<T> normal(const Plane<T>& p, const Hit<T>& h, const Ray<T>& r) noexcept {
    if (h.verdict != Verdict::hit) return Vec3<T>::Zero();
    const Vec3<T> n = p.normal.normalized();
    return n.dot(r.direction) > 0 ? Vec3<T>(-n) : n;
}

}  // namespace rayproof
