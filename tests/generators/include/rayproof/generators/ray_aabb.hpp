// rayproof/generators/ray_aabb.hpp — case generators for ray vs axis-aligned box.
//
// The constructed families (grazing, near_grazing, parallel, on_boundary) are built in
// small integers, where every coordinate and every parameter t of the special point is
// exact, then moved by an exactly representable translation and rescaled by exact powers
// of two: the special geometry (a corner touched, an origin on a face) survives exactly in
// T, at every magnitude.
#pragma once

#include <rayproof/generators/core.hpp>

namespace rayproof::gen {

namespace detail {
struct IBox {
    I3 lo, hi;
};
// Even integer coordinates in [-16, 16], extents 0 (a flat axis) to 16: the odd
// integers strictly inside are free for interior points.
inline IBox integer_box(Rng& rng) {
    IBox b;
    for (int i = 0; i < 3; ++i) {
        b.lo[i] = 2 * uniform_int(rng, -8, 8);
        b.hi[i] = b.lo[i] + 2 * (chance(rng, 1, 8) ? 0 : uniform_int(rng, 1, 8));
    }
    return b;
}
// A coordinate on axis i: 0 lo, 1 hi, 2 strictly inside (or lo on a flat axis).
inline std::int64_t box_coord(const IBox& b, int i, int where, Rng& rng) {
    if (where == 0) return b.lo[i];
    if (where == 1) return b.hi[i];
    if (b.hi[i] == b.lo[i]) return b.lo[i];
    return b.lo[i] + 1 + 2 * uniform_int(rng, 0, (b.hi[i] - b.lo[i]) / 2 - 1);
}
// The integer case translated by tau, or false when some number is not exact in T.
template <class T> bool aabb_from_integers(const IBox& b, const I3& o, const Vec3<T>& d, const I3& tau,
                                           Case<T, Aabb<T>>& c) {
    const I3 lo = add(b.lo, tau), hi = add(b.hi, tau);
    if (!representable<T>(lo) || !representable<T>(hi) || !ray_from_integers(add(o, tau), d, c.ray)) return false;
    c.shape.lo = to_vec<T>(lo);
    c.shape.hi = to_vec<T>(hi);
    return true;
}
}  // namespace detail

// General position: a box in [-8, 8]³, an origin in [-16, 16]³ aimed at a random point of
// the box grown by a quarter (about half the rays hit).
template <class T> Case<T, Aabb<T>> aabb_general(Rng& rng) {
    Case<T, Aabb<T>> c{{}, {}, "general"};
    for (int i = 0; i < 3; ++i) {
        T a = uniform<T>(rng, -8, 8), b = uniform<T>(rng, -8, 8);
        if (b < a) std::swap(a, b);
        c.shape.lo[i] = a;
        c.shape.hi[i] = b;
    }
    Vec3<T> target;
    for (int i = 0; i < 3; ++i) {
        const double m = 0.5 * (double(c.shape.lo[i]) + double(c.shape.hi[i]));
        const double h = 0.625 * (double(c.shape.hi[i]) - double(c.shape.lo[i]));
        target[i] = uniform<T>(rng, m - h, m + h);
        c.ray.origin[i] = uniform<T>(rng, -16, 16);
    }
    c.ray.direction = target - c.ray.origin;
    if (c.ray.direction.isZero()) c.ray.direction = Vec3<T>(1, 0, 0);
    random_t_range(c.ray, rng, 64);
    return c;
}

// Every number log-uniform over the whole exponent range of T (denormals, ±0 and the
// other special values included); lo and hi sorted per axis.
template <class T> Case<T, Aabb<T>> aabb_log_uniform(Rng& rng) {
    Case<T, Aabb<T>> c{{}, {}, "log_uniform"};
    for (int i = 0; i < 3; ++i) {
        T a = wide_value<T>(rng), b = wide_value<T>(rng);
        if (b < a) std::swap(a, b);
        c.shape.lo[i] = a;
        c.shape.hi[i] = b;
        c.ray.origin[i] = wide_value<T>(rng);
    }
    wide_direction_and_range(c.ray, rng);
    return c;
}

// Exact grazing: the ray passes exactly through a corner or an edge point of the box at
// the exact parameter s (touching it only, or entering there: the direction decides),
// with t_min or t_max sometimes exactly at s.
template <class T> Case<T, Aabb<T>> aabb_grazing(Rng& rng) {
    return constructed<T, Aabb<T>>("grazing", rng, [&](Case<T, Aabb<T>>& c) {
        const detail::IBox b = detail::integer_box(rng);
        const int free_axis = chance(rng, 1, 2) ? -1 : int(below(rng, 3));  // -1: a corner
        I3 p;
        for (int i = 0; i < 3; ++i) p[i] = detail::box_coord(b, i, i == free_axis ? 2 : int(below(rng, 2)), rng);
        const I3 d = random_nonzero_i3(rng, 8);
        const std::int64_t s = chance(rng, 1, 8) ? 0 : uniform_int(rng, 1, 8);
        const Vec3<T> dv = to_vec_signed_zeros<T>(d, rng);
        if (!detail::aabb_from_integers<T>(b, sub(p, mul(s, d)), dv, random_translation<T>(rng), c)) return false;
        special_t_range(c.ray, rng, narrow<T>(s));
        return true;
    });
}

// The grazing rays with one direction component moved by one ulp either way (or, one
// time in four, one origin coordinate): a hair off the corner or edge.
template <class T> Case<T, Aabb<T>> aabb_near_grazing(Rng& rng) {
    return near_grazing_from(aabb_grazing<T>(rng), rng, [&](Case<T, Aabb<T>>& c, int i) {
        if (chance(rng, 1, 4))
            nudge_ulp(c.ray.origin[i], rng);
        else
            nudge_ulp(c.ray.direction[i], rng);
    });
}

// Direction components +0 and -0 on one or two axes, with the origin strictly inside,
// outside, or exactly on a slab plane of each such axis; the other axes aim at the box.
template <class T> Case<T, Aabb<T>> aabb_parallel(Rng& rng) {
    return constructed<T, Aabb<T>>("parallel", rng, [&](Case<T, Aabb<T>>& c) {
        const detail::IBox b = detail::integer_box(rng);
        const unsigned mask = 1u + unsigned(below(rng, 6));  // 1..6: one or two axes, never all three
        I3 o, d;
        Vec3<T> dv;
        const std::int64_t s = uniform_int(rng, 1, 8);
        for (int i = 0; i < 3; ++i) {
            if (mask & (1u << i)) {
                d[i] = 0;
                const auto where = below(rng, 4);
                o[i] = where < 3 ? detail::box_coord(b, i, int(where), rng)
                                 : (chance(rng, 1, 2) ? b.lo[i] - uniform_int(rng, 1, 4) : b.hi[i] + uniform_int(rng, 1, 4));
            } else {
                d[i] = signed_int(rng, 1, 8);
                o[i] = detail::box_coord(b, i, int(below(rng, 3)), rng) - s * d[i];
            }
        }
        dv = to_vec<T>(d);
        for (int i = 0; i < 3; ++i)
            if (d[i] == 0 && (rng() & 1)) dv[i] = -T(0);
        if (!detail::aabb_from_integers<T>(b, o, dv, random_translation<T>(rng), c)) return false;
        random_t_range(c.ray, rng, 16);
        return true;
    });
}

// Origins exactly on faces, edges and corners (t_min = 0 there), or rays whose t_min or
// t_max is exactly the parameter of such a boundary point.
template <class T> Case<T, Aabb<T>> aabb_on_boundary(Rng& rng) {
    return constructed<T, Aabb<T>>("on_boundary", rng, [&](Case<T, Aabb<T>>& c) {
        const detail::IBox b = detail::integer_box(rng);
        I3 p;
        bool boundary = false;
        for (int i = 0; i < 3; ++i) {
            const int where = int(below(rng, 3));
            boundary = boundary || where < 2;
            p[i] = detail::box_coord(b, i, where, rng);
        }
        if (!boundary) p[0] = b.lo[0];
        const I3 d = random_nonzero_i3(rng, 8);
        const BoundaryParameter at = boundary_parameter(rng, 1, 8);
        const Vec3<T> dv = to_vec_signed_zeros<T>(d, rng);
        if (!detail::aabb_from_integers<T>(b, sub(p, mul(at.s, d)), dv, random_translation<T>(rng), c)) return false;
        on_boundary_t_range(c.ray, rng, at, 16);
        return true;
    });
}

// Extreme scenes: a tiny box far from the origin (aimed at to within a few ulps), a
// huge box near the overflow threshold, a box of denormal size, a long thin box.
template <class T> Case<T, Aabb<T>> aabb_extreme(Rng& rng) {
    using L = std::numeric_limits<T>;
    Case<T, Aabb<T>> c{{}, {}, "extreme"};
    const auto kind = below(rng, 4);
    if (kind == 0) {  // tiny and far
        Vec3<T> center;
        for (int i = 0; i < 3; ++i) center[i] = magnitude<T>(rng, 20, L::max_exponent - 8);
        const T size = std::ldexp(center.cwiseAbs().maxCoeff(), -int(uniform_int(rng, 8, kPrecision<T> + 24)));
        for (int i = 0; i < 3; ++i) {
            const T h = size * narrow<T>(uniform01(rng));
            c.shape.lo[i] = center[i] - h;
            c.shape.hi[i] = center[i] + h;
            c.ray.origin[i] = uniform<T>(rng, -1, 1);
        }
        c.ray.direction = center - c.ray.origin;
        const int j = int(below(rng, 3));
        c.ray.direction[j] = nudge(c.ray.direction[j], int(uniform_int(rng, -3, 3)));
    } else if (kind == 1) {  // huge
        for (int i = 0; i < 3; ++i) {
            c.shape.lo[i] = -magnitude<T>(rng, L::max_exponent - 6, L::max_exponent - 1, false);
            c.shape.hi[i] = magnitude<T>(rng, L::max_exponent - 6, L::max_exponent - 1, false);
            c.ray.origin[i] = chance(rng, 1, 2) ? wide_value<T>(rng) : narrow<T>(random_sign(rng)) * L::max();
        }
        c.ray.direction = nonzero_wide_vec<T>(rng);
    } else if (kind == 2) {  // denormal sized
        for (int i = 0; i < 3; ++i) {
            T a = magnitude<T>(rng, L::min_exponent - kPrecision<T>, L::min_exponent + 1);
            T b = magnitude<T>(rng, L::min_exponent - kPrecision<T>, L::min_exponent + 1);
            if (b < a) std::swap(a, b);
            c.shape.lo[i] = a;
            c.shape.hi[i] = b;
            c.ray.origin[i] = magnitude<T>(rng, L::min_exponent - kPrecision<T>, L::min_exponent + 4);
        }
        c.ray.direction = nonzero_wide_vec<T>(rng);
    } else {  // long and thin, the ray nearly along the long axis
        const int a = int(below(rng, 3));
        for (int i = 0; i < 3; ++i) {
            const T h = i == a ? magnitude<T>(rng, 20, L::max_exponent - 8, false)
                               : magnitude<T>(rng, -30, 0, false);
            c.shape.lo[i] = -h;
            c.shape.hi[i] = h;
            c.ray.origin[i] = i == a ? -T(2) * h : uniform<T>(rng, -2, 2);
            c.ray.direction[i] = i == a ? T(1) : magnitude<T>(rng, -60, -10);
        }
    }
    if (c.ray.direction.isZero()) c.ray.direction = Vec3<T>(1, 0, 0);
    if (chance(rng, 1, 4)) c.ray.t_min = -kInf<T>;
    return c;
}

// Invalid inputs, one contract rule each: NaN or inf anywhere, t_min > t_max, t_min =
// +inf, t_max = -inf, a zero direction (signed zeros mixed), lo > hi on an axis.
template <class T> Case<T, Aabb<T>> aabb_invalid(Rng& rng) {
    return invalid_from(aabb_general<T>, aabb_grazing<T>, rng, 3, FaultAxis::drawn,
                        [&](Case<T, Aabb<T>>& c, unsigned k, int i) {
                            if (k == 0) {  // NaN or inf in the box
                                T& x = chance(rng, 1, 2) ? c.shape.lo[i] : c.shape.hi[i];
                                x = non_finite<T>(rng);
                            } else {  // lo > hi, by one ulp or more
                                c.shape.lo[i] = chance(rng, 1, 2) ? step_up(c.shape.hi[i])
                                                                  : c.shape.hi[i] + narrow<T>(uniform_int(rng, 1, 8));
                                if (!(c.shape.lo[i] > c.shape.hi[i])) c.shape.lo[i] = step_up(c.shape.hi[i]);
                            }
                        });
}

}  // namespace rayproof::gen
