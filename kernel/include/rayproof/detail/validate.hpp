// rayproof/detail/validate.hpp — the contract's validity rules, one function per input type.
//
// Invalid (every mode answers Verdict::invalid): any NaN or infinite number except
// t_min = -inf and t_max = +inf; t_min > t_max; a zero direction; lo > hi on an axis;
// radius < 0; a zero plane normal (also in any plane of a polyhedron); a negative Obb
// half extent; linearly dependent Obb axes (decided exactly: the sign of the
// determinant of the stored floats).
#pragma once

#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/float_util.hpp>
#include <rayproof/types.hpp>

namespace rayproof::detail {

// x - x is +0 for every finite x and NaN for ±inf and NaN, so a sum of such differences
// is 0 exactly when every term is finite: one comparison for many numbers, no branch per
// number (most queries are valid; the checks are joined with & for the same reason).
template <class T> RAYPROOF_ALWAYS_INLINE T finite_probe(const T* v) { return ((v[0] - v[0]) + (v[1] - v[1])) + (v[2] - v[2]); }

// v is not the zero vector (every component +0 or -0).
template <class T> RAYPROOF_ALWAYS_INLINE bool nonzero3(const T* v) { return (v[0] != 0) | (v[1] != 0) | (v[2] != 0); }

// The rules on t_min and t_max alone: t_min <= t_max is false when either is NaN; -inf
// and +inf are the allowed exceptions.
template <class T> RAYPROOF_ALWAYS_INLINE bool valid_range(const Ray<T>& r) {
    return (r.t_min <= r.t_max) & (r.t_min != inf<T>) & (r.t_max != -inf<T>);
}

// valid(r) for a ray whose direction is known to be finite and nonzero.
template <class T> RAYPROOF_ALWAYS_INLINE bool valid_apart_from_direction(const Ray<T>& r) {
    const bool range = valid_range(r);
    return (finite_probe(r.origin.data()) == 0) & range;
}

template <class T> RAYPROOF_ALWAYS_INLINE bool valid(const Ray<T>& r) {
    const T* d = r.direction.data();
    const bool rest = valid_apart_from_direction(r), finite = finite_probe(d) == 0, nonzero = nonzero3(d);
    return rest & finite & nonzero;
}

template <class T> RAYPROOF_ALWAYS_INLINE bool valid(const Aabb<T>& b) {
    const T* lo = b.lo.data();
    const T* hi = b.hi.data();
    return (finite_probe(lo) + finite_probe(hi) == 0) & (lo[0] <= hi[0]) & (lo[1] <= hi[1]) & (lo[2] <= hi[2]);
}

template <class T> RAYPROOF_ALWAYS_INLINE bool valid(const Sphere<T>& s) {
    // radius >= 0 is false for NaN; radius - radius is NaN for +inf.
    return (finite_probe(s.center.data()) + (s.radius - s.radius) == 0) & (s.radius >= 0);
}

template <class T> RAYPROOF_ALWAYS_INLINE bool valid(const Plane<T>& p) {
    const T* n = p.normal.data();
    const bool finite = finite_probe(n) + (p.offset - p.offset) == 0, nonzero = nonzero3(n);
    return finite & nonzero;
}

// Every plane valid (a finite offset, a finite nonzero normal); no planes is valid.
template <class T> bool valid(const ConvexPolyhedron<T>& c) {
    bool ok = true;
    for (const Plane<T>& p : c.planes) ok &= valid(p);
    return ok;
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
