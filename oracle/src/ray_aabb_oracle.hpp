// ray_aabb_oracle.hpp — internal to the oracle library: the exact answer for a ray against
// an Aabb, exact(ray, Aabb). Part of oracle.cpp's one translation unit, which includes
// it and instantiates it for float and double.
//
// How it is decided (the contract's definition, literally): per axis, the slab
// lo_i <= o_i + t·d_i <= hi_i: for d_i != 0 the exact rationals (lo_i - o_i)/d_i and
// (hi_i - o_i)/d_i; for d_i == 0 the test lo_i <= o_i <= hi_i. t_enter = max(t_min,
// entries), t_exit = min(t_max, exits), hit iff t_enter <= t_exit. The face is the axis
// of the largest entry that is strictly above t_min, the lowest axis on ties (strict
// comparisons in axis order), else -1. The Obb (ray_obb_oracle.hpp) clips the same way.
#pragma once

#include "exact_answer.hpp"

#include <array>

namespace rayproof::oracle {

namespace {

// The slab clipping of o + t·d against lo <= p <= hi (all exact), on [t_min, t_max].
template <class T> Exact<T> clip_slabs(const std::array<Q, 3>& o, const std::array<Q, 3>& d, const std::array<Q, 3>& lo,
                                       const std::array<Q, 3>& hi, T t_min, T t_max) {
    Exact<T> e;
    XQ enter = xq(t_min), exit = xq(t_max);
    int face = -1;
    for (int i = 0; i < 3; ++i) {
        const CGAL::Sign sd = CGAL::sign(d[i]);
        if (sd == CGAL::ZERO) {
            if (o[i] < lo[i] || hi[i] < o[i]) return e;  // parallel, outside the slab: miss
            continue;
        }
        const Q t_lo = (lo[i] - o[i]) / d[i];
        const Q t_hi = (hi[i] - o[i]) / d[i];
        const bool neg = sd == CGAL::NEGATIVE;
        const XQ in{0, neg ? t_hi : t_lo}, out{0, neg ? t_lo : t_hi};
        if (cmp(in, enter) > 0) {  // strict: t_min and lower axes win ties
            enter = in;
            face = 2 * i + (neg ? 1 : 0);
        }
        if (cmp(out, exit) < 0) exit = out;
    }
    if (cmp(enter, exit) > 0) return e;
    e.verdict = Verdict::hit;
    e.t_enter = value_of(enter);
    e.t_exit = value_of(exit);
    e.face = face;
    return e;
}

}  // namespace

template <class T> Exact<T> exact(const Ray<T>& ray, const Aabb<T>& box) {
    if (!valid(ray) || !valid(box)) return invalid_answer<T>();
    return clip_slabs(q3(ray.origin), q3(ray.direction), q3(box.lo), q3(box.hi), ray.t_min, ray.t_max);
}

}  // namespace rayproof::oracle
