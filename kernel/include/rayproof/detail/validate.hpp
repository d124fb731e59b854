// rayproof/detail/validate.hpp — the contract's validity rules, one function per input type.
//
// Invalid (every mode answers Verdict::invalid): any NaN or infinite number except
// t_min = -inf and t_max = +inf; t_min > t_max; a zero direction; lo > hi on an axis;
// radius < 0; a zero plane normal; a negative Obb half extent; linearly dependent
// Obb axes (decided exactly: the sign of the determinant of the stored floats).
#pragma once

#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/float_util.hpp>
#include <rayproof/types.hpp>

namespace rayproof::detail {

template <class T> bool valid(const Ray<T>& r) {
    if (!finite3(r.origin.data()) || !finite3(r.direction.data())) return false;
    if (std::isnan(r.t_min) || std::isnan(r.t_max)) return false;
    if (r.t_min == inf<T> || r.t_max == -inf<T>) return false;  // -inf / +inf are the allowed exceptions
    if (!(r.t_min <= r.t_max)) return false;
    return r.direction[0] != 0 || r.direction[1] != 0 || r.direction[2] != 0;
}

template <class T> bool valid(const Aabb<T>& b) {
    if (!finite3(b.lo.data()) || !finite3(b.hi.data())) return false;
    return b.lo[0] <= b.hi[0] && b.lo[1] <= b.hi[1] && b.lo[2] <= b.hi[2];
}

template <class T> bool valid(const Sphere<T>& s) {
    return finite3(s.center.data()) && std::isfinite(s.radius) && s.radius >= 0;
}

template <class T> bool valid(const Plane<T>& p) {
    if (!finite3(p.normal.data()) || !std::isfinite(p.offset)) return false;
    return p.normal[0] != 0 || p.normal[1] != 0 || p.normal[2] != 0;
}

template <class T> bool valid(const Obb<T>& b) {
    if (!finite3(b.center.data()) || !finite3(b.half_extent.data())) return false;
    for (int i = 0; i < 9; ++i)
        if (!std::isfinite(b.axes.data()[i])) return false;
    if (!(b.half_extent[0] >= 0 && b.half_extent[1] >= 0 && b.half_extent[2] >= 0)) return false;
    return det3_sign(b.axes) != 0;  // exact: dependent axes <=> det == 0
}

template <class T> Hit<T> invalid_hit() {
    Hit<T> h;
    h.verdict = Verdict::invalid;
    return h;
}

}  // namespace rayproof::detail
