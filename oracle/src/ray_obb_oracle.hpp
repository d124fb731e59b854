// ray_obb_oracle.hpp — internal to the oracle library: the exact answer for a ray against
// an Obb, exact(ray, Obb). Part of oracle.cpp's one translation unit, which includes
// it and instantiates it for float and double.
//
// How it is decided (the contract's definition, literally): the Aabb's slab clipping
// (clip_slabs, ray_aabb_oracle.hpp) in the box frame, with the exact rationals
// o'_i = (o - c)·a_i, d'_i = d·a_i and the slab [-h_i, h_i], a_i the stored columns.
#pragma once

#include "ray_aabb_oracle.hpp"

#include <array>

namespace rayproof::oracle {

template <class T> Exact<T> exact(const Ray<T>& ray, const Obb<T>& box) {
    if (!valid(ray) || !valid(box)) return invalid_answer<T>();
    const std::array<Q, 3> o = q3(ray.origin), d = q3(ray.direction), c = q3(box.center);
    const std::array<Q, 3> rel = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
    std::array<Q, 3> ol, dl, lo, hi;
    for (int i = 0; i < 3; ++i) {
        const std::array<Q, 3> a = q3(Vec3<T>(box.axes.col(i)));
        ol[i] = rel[0] * a[0] + rel[1] * a[1] + rel[2] * a[2];
        dl[i] = d[0] * a[0] + d[1] * a[1] + d[2] * a[2];
        hi[i] = to_q(box.half_extent[i]);
        lo[i] = -hi[i];
    }
    return clip_slabs(ol, dl, lo, hi, ray.t_min, ray.t_max);
}

}  // namespace rayproof::oracle
