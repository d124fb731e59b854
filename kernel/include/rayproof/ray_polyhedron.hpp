// rayproof/ray_polyhedron.hpp — ray against convex polyhedron.
//
// Shape:     the closed solid { p : n_k·p <= offset_k for every plane k } of a
//            ConvexPolyhedron (the normals point out). No planes: all of space. An
//            infeasible set: the empty set (always a miss). Unbounded solids are valid.
// Query:     per plane, num_k = offset_k - n_k·o and den_k = n_k·d; the ray is in the
//            closed half-space k exactly for the t with num_k - t·den_k >= 0, that is
//            t >= t_k = num_k/den_k when den_k < 0 (the ray enters through plane k),
//            t <= t_k when den_k > 0 (it leaves), every t when den_k == 0 and num_k >= 0
//            (parallel, the origin inside the half-space), no t when den_k == 0 and
//            num_k < 0. The answer is [t_enter, t_exit] = [max(t_min, entries), min(t_max,
//            exits)], a hit when t_enter <= t_exit. face = the index k of the entry
//            plane realizing t_enter, the lowest k on ties (duplicate and coincident
//            planes included); -1 when t_enter == t_min (the point at t_min is inside).
// Algorithm: the slab method generalized to k half-spaces (Kay & Kajiya, "Ray Tracing
//            Complex Scenes", SIGGRAPH 1986; E. Haines, "Fast Ray-Convex Polyhedron
//            Intersection", Graphics Gems II, 1991): one pass over the planes keeping the
//            latest entry and the earliest exit, leaving as soon as they cross.
// Degenerate cases: a ray parallel to a plane (den_k == 0 exactly, decided by the origin's
//            side, its boundary included); the origin on a plane; grazing an edge or a
//            vertex (t_enter == t_exit); duplicate and coincident planes (the lowest index
//            wins the face); no planes; infeasible and unbounded sets; a flat solid from
//            two opposite planes with equal offsets.
// Modes:     fast — the textbook loop in T: num_k and den_k are each a few roundings from
//            their values (|den~ - den| <= gamma(3)·Σ|n_j d_j|, |num~ - num| <=
//            gamma(4)·(|offset| + Σ|n_j o_j|)) and t_k one more; where den_k is of the
//            order of its own bound even its sign, and so the side, is unknown. Measured,
//            not promised; no allocation.
#pragma once

#include <rayproof/detail/prepared.hpp>
#include <rayproof/detail/validate.hpp>
#include <rayproof/types.hpp>

#include <cstddef>

namespace rayproof::detail {

// A polyhedron is prepared by reference (detail/prepared.hpp): its validity, every plane's,
// decided once.
template <class T> inline constexpr bool prepared_by_reference<ConvexPolyhedron<T>> = true;
template <class T> using PreparedPolyhedron = Prepared<ConvexPolyhedron<T>>;

template <class T> Hit<T> query(const Ray<T>& r, const PreparedPolyhedron<T>& p, fast_t) {
    if (!p.ok || !valid(r)) return invalid_hit<T>();
    Hit<T> h;
    T t0 = r.t_min, t1 = r.t_max;
    int face = -1;
    const std::span<const Plane<T>> planes = p.shape.planes;
    for (std::size_t k = 0; k < planes.size(); ++k) {
        const Plane<T>& q = planes[k];
        const T den = q.normal.dot(r.direction);
        const T num = q.offset - q.normal.dot(r.origin);
        if (den == 0) {
            if (num < 0) return h;  // parallel, outside
            continue;
        }
        const T t = num / den;
        if (den < 0) {
            if (t > t0) {
                t0 = t;
                face = int(k);
            }
        } else if (t < t1) {
            t1 = t;
        }
        if (t0 > t1) return h;
    }
    h.verdict = Verdict::hit;
    h.t_enter = t0;
    h.t_exit = t1;
    h.face = face;
    return h;
}

}  // namespace rayproof::detail
