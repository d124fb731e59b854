// ray_plane_oracle.hpp — internal to the oracle library: the exact answer for a ray against
// a Plane, exact(ray, Plane). Part of oracle.cpp's one translation unit, which includes
// it and instantiates it for float and double.
//
// How it is decided (the contract's definition, literally): den = n·d, num = offset -
// n·o exactly; den == 0: the whole range when num == 0, otherwise a miss; else
// t = num/den, a hit iff t_min <= t <= t_max.
#pragma once

#include "exact_answer.hpp"

#include <array>

namespace rayproof::oracle {

template <class T> Exact<T> exact(const Ray<T>& ray, const Plane<T>& plane) {
    if (!valid(ray) || !valid(plane)) return invalid_answer<T>();
    const std::array<Q, 3> o = q3(ray.origin), d = q3(ray.direction), n = q3(plane.normal);
    const Q den = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
    const Q num = to_q(plane.offset) - (n[0] * o[0] + n[1] * o[1] + n[2] * o[2]);
    Exact<T> e;
    if (CGAL::sign(den) == CGAL::ZERO) {
        if (CGAL::sign(num) != CGAL::ZERO) return e;  // parallel, off the plane
        e.verdict = Verdict::hit;                     // lying in the plane: the whole range
        e.t_enter = value_of(xq(ray.t_min));
        e.t_exit = value_of(xq(ray.t_max));
        return e;
    }
    const XQ t{0, num / den};
    if (cmp(xq(ray.t_min), t) > 0 || cmp(t, xq(ray.t_max)) > 0) return e;
    e.verdict = Verdict::hit;
    e.t_enter = e.t_exit = value_of(t);
    return e;
}

}  // namespace rayproof::oracle
