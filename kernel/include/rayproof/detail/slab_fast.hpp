// rayproof/detail/slab_fast.hpp — the slab method in plain floating point, shared by
// Ray/Aabb and (after the change of frame) Ray/Obb.
//
// For each axis i the ray is inside the closed slab lo_i <= o_i + t d_i <= hi_i for t
// between (lo_i - o_i)/d_i and (hi_i - o_i)/d_i; the box interval is the intersection
// of the three slab intervals with [t_min, t_max] (Kay & Kajiya 1986; Williams et al.,
// "An Efficient and Robust Ray-Box Intersection Algorithm", JGT 2005).
//
// Parallel axes (d_i = +0 or -0) need no branch: 1/d_i is ±inf, so a plane strictly
// on the far side of the origin gives +inf as an entry (the slab is never entered)
// and a plane behind gives -inf (no constraint). An origin exactly on the plane gives
// 0·inf = NaN; the comparisons below are written so that a NaN candidate never
// replaces the running value, which is the exact meaning of a closed slab (the origin
// on its boundary is inside). d_i = -0 counts as negative on both sides: 1/-0 = -inf
// and signbit(-0) is set, so the entry plane is hi, consistent with the NaN rule.
#pragma once

#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/types.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <type_traits>

namespace rayproof::detail {

// The ray o + t·d against the box lo <= p <= hi, all in the same frame. The inputs
// are assumed valid; the result follows the contract's face rule: -1 when t_min
// already lies in every slab, otherwise the axis of the latest entry, lowest index on
// ties (strict > keeps the earlier axis and keeps t_min on a tie with it).
// inv(i) gives 1/d_i: divided here (slab_fast), or as a prepared ray holds it
// (slab_fast_with, ray_aabb.hpp).
template <class T, class Inv>
RAYPROOF_ALWAYS_INLINE Hit<T> slab_fast_with(const T* o, const T* d, Inv inv_of, const T* lo, const T* hi, T t_min,
                                             T t_max) {
    T t_enter = t_min, t_exit = t_max;
    int face = -1;
    RAYPROOF_UNROLL3
    for (int i = 0; i < 3; ++i) {
        const T inv = inv_of(i);
        const T t_lo = (lo[i] - o[i]) * inv;
        const T t_hi = (hi[i] - o[i]) * inv;
        const bool neg = std::signbit(d[i]);
        const T t_in = pick(neg, t_hi, t_lo);
        const T t_out = pick(neg, t_lo, t_hi);
        const bool later = t_in > t_enter;          // false for NaN: NaN never wins
        face = pick_int(later, 2 * i + int(neg), face);
        t_enter = t_in > t_enter ? t_in : t_enter;  // maxsd: keeps t_enter on NaN
        t_exit = t_out < t_exit ? t_out : t_exit;   // minsd: keeps t_exit on NaN
    }
    Hit<T> h;
    h.verdict = t_enter <= t_exit ? Verdict::hit : Verdict::miss;
    h.t_enter = t_enter;
    h.t_exit = t_exit;
    h.face = face;
    return h;
}

template <class T> struct DividedInverse {
    const T* d;
    RAYPROOF_ALWAYS_INLINE T operator()(int i) const { return T(1) / d[i]; }
};

template <class T>
RAYPROOF_ALWAYS_INLINE Hit<T> slab_fast(const T* o, const T* d, const T* lo, const T* hi, T t_min, T t_max) {
    return slab_fast_with(o, d, DividedInverse<T>{d}, lo, hi, t_min, t_max);
}

}  // namespace rayproof::detail
