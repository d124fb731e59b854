// rayproof/detail/prepared.hpp — a shape prepared for queries.
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

// A query's out-of-line fallback is a lambda that captures the shape itself (`&s =
// p.shape`), never the Prepared: where g++ leaves the lambda's call out of line (it
// sits on a cold path), a closure holding &p makes it store p in memory, its flag
// included, so that prepare()'s validity test (valid(s)) is evaluated on every query
// even where nothing reads the flag (a Ray's fast, conservative and certified queries
// of the box, the plane and the sphere). Measured in the benchmarks' build (g++ -O2):
// the fast plane query 5.1 against 3.5 ns, the fast sphere 15.7 against 14.7.
//
// Each mode's query opens with `if (!p.ok || !valid(r)) return invalid_hit<T>();`,
// written out: the same test as a function returning bool, even forced inline, changes
// g++'s block layout and inlining around it (a few instructions per conservative query,
// measured with tests/unit/kernel_measure).

}  // namespace rayproof::detail
