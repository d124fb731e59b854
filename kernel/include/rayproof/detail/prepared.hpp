// rayproof/detail/prepared.hpp — a shape prepared for queries, and the validity check
// every mode's query starts with.
//
// The axis-aligned box, the plane and the sphere are prepared by reference: the
// validity decided once (the batch form prepares once per call) next to a reference to
// the caller's shape, which outlives the query (a copy would live on the stack whenever
// a general path takes its address, and every query would pay for it). The oriented
// box prepares a frame of its own (ray_obb.hpp).
#pragma once

#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/validate.hpp>
#include <rayproof/types.hpp>

namespace rayproof::detail {

template <class Shape> struct Prepared {
    const Shape& shape;
    bool ok;
};

template <class S> inline constexpr bool prepared_by_reference = false;
template <class T> inline constexpr bool prepared_by_reference<Aabb<T>> = true;
template <class T> inline constexpr bool prepared_by_reference<Plane<T>> = true;
template <class T> inline constexpr bool prepared_by_reference<Sphere<T>> = true;

template <class Shape>
    requires prepared_by_reference<Shape>
RAYPROOF_ALWAYS_INLINE Prepared<Shape> prepare(const Shape& s) {
    return {s, valid(s)};
}

// True when the query must answer Verdict::invalid: the prepared shape or the ray
// breaks a validity rule (paths that prove validity themselves skip this).
template <class T, class P> RAYPROOF_ALWAYS_INLINE bool rejects(const Ray<T>& r, const P& p) {
    return !p.ok || !valid(r);
}

}  // namespace rayproof::detail
