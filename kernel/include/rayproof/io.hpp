// rayproof/io.hpp — printing of the public types in hexadecimal floating point, so that
// a printed failing case reproduces bit for bit (std::hexfloat round-trips exactly).
#pragma once

#include <rayproof/types.hpp>

#include <cstddef>
#include <ios>
#include <ostream>

namespace rayproof {

namespace detail {
template <class T> void put(std::ostream& os, T x) {
    const auto flags = os.flags();
    os << std::hexfloat << x;
    os.flags(flags);
}
template <class Derived> void put_vec(std::ostream& os, const Eigen::MatrixBase<Derived>& v) {
    os << '(';
    for (Eigen::Index i = 0; i < v.size(); ++i) {
        if (i) os << ", ";
        put(os, v(i));
    }
    os << ')';
}
}  // namespace detail

template <class T> std::ostream& operator<<(std::ostream& os, const Ray<T>& r) {
    os << "Ray{o=";
    detail::put_vec(os, r.origin);
    os << " d=";
    detail::put_vec(os, r.direction);
    os << " t=[";
    detail::put(os, r.t_min);
    os << ", ";
    detail::put(os, r.t_max);
    return os << "]}";
}
template <class T> std::ostream& operator<<(std::ostream& os, const Aabb<T>& b) {
    os << "Aabb{lo=";
    detail::put_vec(os, b.lo);
    os << " hi=";
    detail::put_vec(os, b.hi);
    return os << '}';
}
template <class T> std::ostream& operator<<(std::ostream& os, const Obb<T>& b) {
    os << "Obb{center=";
    detail::put_vec(os, b.center);
    os << " axes(columns)=";
    for (int i = 0; i < 3; ++i) detail::put_vec(os, b.axes.col(i));
    os << " half_extent=";
    detail::put_vec(os, b.half_extent);
    return os << '}';
}
template <class T> std::ostream& operator<<(std::ostream& os, const Plane<T>& p) {
    os << "Plane{normal=";
    detail::put_vec(os, p.normal);
    os << " offset=";
    detail::put(os, p.offset);
    return os << '}';
}
template <class T> std::ostream& operator<<(std::ostream& os, const Sphere<T>& s) {
    os << "Sphere{center=";
    detail::put_vec(os, s.center);
    os << " radius=";
    detail::put(os, s.radius);
    return os << '}';
}
template <class T> std::ostream& operator<<(std::ostream& os, const ConvexPolyhedron<T>& c) {
    os << "ConvexPolyhedron{";
    for (std::size_t k = 0; k < c.planes.size(); ++k) os << (k ? " " : "") << c.planes[k];
    return os << '}';
}
template <class T> std::ostream& operator<<(std::ostream& os, const Hit<T>& h) {
    os << "Hit{" << h.verdict;
    if (h.verdict == Verdict::hit) {
        os << " t=[";
        detail::put(os, h.t_enter);
        os << ", ";
        detail::put(os, h.t_exit);
        os << "] face=" << h.face;
    }
    return os << '}';
}

}  // namespace rayproof
