// ray_polyhedron_oracle.hpp — internal to the oracle library: the exact answer for a ray
// against a ConvexPolyhedron, exact(ray, ConvexPolyhedron). Part of oracle.cpp's one
// translation unit, which includes it and instantiates it for float and double.
//
// How it is decided (the contract's definition, literally): the solid is the set of p
// with n_k·p <= offset_k for every plane k. On the ray p = o + t·d, plane k holds when
// t·den_k <= num_k, with den_k = n_k·d and num_k = offset_k - n_k·o, both exact
// rationals. Per plane:
//   den_k == 0  the ray is parallel to the plane: every t when num_k >= 0 (the ray in
//               the closed half space, the plane itself included), none otherwise (miss);
//   den_k <  0  an entering crossing: t >= num_k/den_k;
//   den_k >  0  an exiting crossing:  t <= num_k/den_k.
// t_enter = max(t_min, every entering crossing), t_exit = min(t_max, every exiting
// crossing), exactly; a hit iff t_enter <= t_exit. No planes: the whole range. An
// infeasible set needs no case of its own: the line meets the empty set nowhere, so
// some entering crossing lies above some exiting one (or a parallel plane excludes it).
// The face is the lowest k whose entering crossing equals t_enter and lies strictly
// above t_min (strict comparisons in plane order, duplicates included), else -1 (the
// point at t_min lies in the solid; with t_min = -inf, no entering plane at all).
#pragma once

#include "exact_answer.hpp"

#include <array>
#include <cstddef>

namespace rayproof::oracle {

template <class T> Exact<T> exact(const Ray<T>& ray, const ConvexPolyhedron<T>& poly) {
    if (!valid(ray) || !valid(poly)) return invalid_answer<T>();
    const std::array<Q, 3> o = q3(ray.origin), d = q3(ray.direction);
    Exact<T> e;
    XQ enter = xq(ray.t_min), exit = xq(ray.t_max);
    int face = -1;
    for (std::size_t k = 0; k < poly.planes.size(); ++k) {
        const std::array<Q, 3> n = q3(poly.planes[k].normal);
        const Q den = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
        const Q num = to_q(poly.planes[k].offset) - (n[0] * o[0] + n[1] * o[1] + n[2] * o[2]);
        const CGAL::Sign sd = CGAL::sign(den);
        if (sd == CGAL::ZERO) {
            if (CGAL::sign(num) == CGAL::NEGATIVE) return e;  // parallel, outside the half space: miss
            continue;
        }
        const XQ t{0, num / den};
        if (sd == CGAL::NEGATIVE) {
            if (cmp(t, enter) > 0) {  // strict: t_min and lower planes win ties
                enter = t;
                face = int(k);
            }
        } else if (cmp(t, exit) < 0) {
            exit = t;
        }
    }
    if (cmp(enter, exit) > 0) return e;
    e.verdict = Verdict::hit;
    e.t_enter = value_of(enter);
    e.t_exit = value_of(exit);
    e.face = face;
    return e;
}

}  // namespace rayproof::oracle
