// rayproof/generators/ray_obb.hpp — case generators for ray vs oriented box.
//
// The constructed families use integer axes (permuted scaled identities, integer
// rotations with orthogonal non-normalized columns, sheared integer matrices with
// det != 0). A point p = center + v is put exactly on the plane of axis i by choosing
// half_extent_i = |v·a_i| (an integer), so corners, edge points and faces are exact in T
// and stay exact under translation and power-of-two scaling.
#pragma once

#include <rayproof/generators/core.hpp>

#include <cstdlib>

namespace rayproof::gen {

namespace detail {
// The Obb built from integers, translated by tau; false when some number is not exact.
template <class T> bool obb_from_integers(const IMat3& a, const I3& center, const I3& h, const I3& origin,
                                          const Vec3<T>& d, const I3& tau, Case<T, Obb<T>>& c) {
    const I3 ct = add(center, tau);
    if (!representable<T>(ct) || !representable<T>(h)) return false;
    for (const auto& col : a.col)
        if (!representable<T>(col)) return false;
    if (!ray_from_integers(add(origin, tau), d, c.ray)) return false;
    c.shape.center = to_vec<T>(ct);
    c.shape.axes = to_mat<T>(a);
    c.shape.half_extent = to_vec<T>(h);
    return true;
}
// A rotation matrix in T from a random unit quaternion (rounded, so only nearly orthonormal).
template <class T> Mat3<T> random_rotation(Rng& rng) {
    double q[4], n2 = 0;
    for (;;) {
        n2 = 0;
        for (double& x : q) {
            x = 2 * uniform01(rng) - 1;
            n2 += x * x;
        }
        if (n2 > 1e-3 && n2 <= 1) break;
    }
    const double n = std::sqrt(n2), w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
    Mat3<T> m;
    m << narrow<T>(1 - 2 * (y * y + z * z)), narrow<T>(2 * (x * y - w * z)), narrow<T>(2 * (x * z + w * y)),  //
        narrow<T>(2 * (x * y + w * z)), narrow<T>(1 - 2 * (x * x + z * z)), narrow<T>(2 * (y * z - w * x)),   //
        narrow<T>(2 * (x * z - w * y)), narrow<T>(2 * (y * z + w * x)), narrow<T>(1 - 2 * (x * x + y * y));
    return m;
}
}  // namespace detail

// General position: a rotated unit-axis box (float rotation) around a centre in [-8, 8]³,
// half extents up to 4, an origin in [-16, 16]³ aimed near the centre.
template <class T> Case<T, Obb<T>> obb_general(Rng& rng) {
    Case<T, Obb<T>> c{{}, {}, "general"};
    c.shape.axes = detail::random_rotation<T>(rng);
    Vec3<T> target;
    for (int i = 0; i < 3; ++i) {
        c.shape.center[i] = uniform<T>(rng, -8, 8);
        c.shape.half_extent[i] = uniform<T>(rng, 0, 4);
        c.ray.origin[i] = uniform<T>(rng, -16, 16);
        target[i] = c.shape.center[i] + uniform<T>(rng, -4, 4);
    }
    c.ray.direction = target - c.ray.origin;
    if (c.ray.direction.isZero()) c.ray.direction = Vec3<T>(0, 0, 1);
    random_t_range(c.ray, rng, 64);
    return c;
}

// Every number log-uniform over the whole exponent range (axes included: they are
// linearly independent with overwhelming probability; the oracle decides exactly).
template <class T> Case<T, Obb<T>> obb_log_uniform(Rng& rng) {
    Case<T, Obb<T>> c{{}, {}, "log_uniform"};
    for (int i = 0; i < 9; ++i) c.shape.axes.data()[i] = wide_value<T>(rng);
    for (int i = 0; i < 3; ++i) {
        c.shape.center[i] = wide_value<T>(rng);
        c.shape.half_extent[i] = std::abs(wide_value<T>(rng));
        c.ray.origin[i] = wide_value<T>(rng);
    }
    c.ray.direction = nonzero_wide_vec<T>(rng);
    if (chance(rng, 1, 4)) c.ray.t_min = -kInf<T>;
    return c;
}

// Obb with integer, non-normalized, rotated (or sheared) axes in general position: an
// integer centre and half extents, an integer origin aimed near the centre.
template <class T> Case<T, Obb<T>> obb_rotated_integer(Rng& rng) {
    return constructed<T, Obb<T>>("rotated_integer", rng, [&](Case<T, Obb<T>>& c) {
        const IMat3 a = integer_axes(rng);
        I3 h;
        for (int i = 0; i < 3; ++i) {
            const std::int64_t l1 = std::abs(a.col[i][0]) + std::abs(a.col[i][1]) + std::abs(a.col[i][2]);
            h[i] = uniform_int(rng, 0, 4) * l1;
        }
        const I3 center = random_i3(rng, -8, 8);
        const I3 origin = random_i3(rng, -32, 32);
        const I3 d = sub(add(center, random_i3(rng, -4, 4)), origin);
        if (is_zero(d)) return false;
        const Vec3<T> dv = to_vec_signed_zeros<T>(d, rng);
        if (!detail::obb_from_integers<T>(a, center, h, origin, dv, random_translation<T>(rng), c))
            return false;
        random_t_range(c.ray, rng, 4);
        return true;
    });
}

namespace detail {
// Integer Obb with the point center + v exactly on the planes of the axes in `on_mask`
// (side chosen by the sign of v·a_i) and strictly inside the other slabs (or, when
// `outside_ok`, sometimes outside them).
inline I3 half_extents_through(const IMat3& a, const I3& v, unsigned on_mask, Rng& rng, bool outside_ok = false) {
    I3 h;
    for (int i = 0; i < 3; ++i) {
        const std::int64_t k = std::abs(dot(v, a.col[i]));
        if (on_mask & (1u << i))
            h[i] = k;
        else if (outside_ok && k > 0 && chance(rng, 1, 3))
            h[i] = uniform_int(rng, 0, k - 1);
        else
            h[i] = k + uniform_int(rng, 1, 6);
    }
    return h;
}
}  // namespace detail

// Exact grazing: the ray passes exactly through a corner or an edge point of an integer
// Obb at the exact parameter s (touching it, or entering there).
template <class T> Case<T, Obb<T>> obb_grazing(Rng& rng) {
    return constructed<T, Obb<T>>("grazing", rng, [&](Case<T, Obb<T>>& c) {
        const IMat3 a = integer_axes(rng);
        const I3 center = random_i3(rng, -8, 8);
        const I3 v = random_nonzero_i3(rng, 6);
        const unsigned mask = chance(rng, 1, 2) ? 7u : (7u & ~(1u << below(rng, 3)));  // corner or edge
        const I3 h = detail::half_extents_through(a, v, mask, rng);
        const I3 d = random_nonzero_i3(rng, 8);
        const std::int64_t s = chance(rng, 1, 8) ? 0 : uniform_int(rng, 1, 8);
        const Vec3<T> dv = to_vec_signed_zeros<T>(d, rng);
        if (!detail::obb_from_integers<T>(a, center, h, sub(add(center, v), mul(s, d)), dv, random_translation<T>(rng), c))
            return false;
        special_t_range(c.ray, rng, narrow<T>(s));
        return true;
    });
}

// The grazing rays with one direction component (or one origin coordinate, or one axis
// entry: the box the floats describe moves) nudged by one ulp either way.
template <class T> Case<T, Obb<T>> obb_near_grazing(Rng& rng) {
    return near_grazing_from(obb_grazing<T>(rng), rng, nudge_origin, [](Case<T, Obb<T>>& c, int i, Rng& g) {
        T& x = c.shape.axes(i, int(below(g, 3)));
        nudge_ulp(x, g);
    });
}

// Directions exactly perpendicular to one box axis (d·a_i == 0 exactly: d = a_i × w, or
// ±0 components for axis-aligned boxes), with the origin exactly on that slab's plane,
// strictly inside it, or outside it.
template <class T> Case<T, Obb<T>> obb_parallel(Rng& rng) {
    return constructed<T, Obb<T>>("parallel", rng, [&](Case<T, Obb<T>>& c) {
        const IMat3 a = integer_axes(rng);
        const int i = int(below(rng, 3));
        const I3 d = chance(rng, 1, 2) ? cross(a.col[i], random_nonzero_i3(rng, 4))
                                       : cross(a.col[i], a.col[(i + 1 + below(rng, 2)) % 3]);
        if (is_zero(d)) return false;
        const I3 center = random_i3(rng, -8, 8);
        const I3 v = random_nonzero_i3(rng, 6);
        I3 h = detail::half_extents_through(a, v, 0u, rng);
        const std::int64_t k = std::abs(dot(v, a.col[i]));
        const auto where = below(rng, 3);  // on the plane, inside, outside
        h[i] = where == 0 ? k : where == 1 ? k + uniform_int(rng, 1, 6) : (k > 0 ? uniform_int(rng, 0, k - 1) : k);
        const std::int64_t s = uniform_int(rng, 0, 4);
        const Vec3<T> dv = to_vec_signed_zeros<T>(d, rng);
        if (!detail::obb_from_integers<T>(a, center, h, sub(add(center, v), mul(s, d)), dv, random_translation<T>(rng), c))
            return false;
        random_t_range(c.ray, rng, 8);
        return true;
    });
}

// Origins exactly on faces, edges and corners of an integer Obb, or t_min / t_max exactly
// at the parameter of such a boundary point.
template <class T> Case<T, Obb<T>> obb_on_boundary(Rng& rng) {
    return constructed<T, Obb<T>>("on_boundary", rng, [&](Case<T, Obb<T>>& c) {
        const IMat3 a = integer_axes(rng);
        const I3 center = random_i3(rng, -8, 8);
        const I3 v = random_nonzero_i3(rng, 6);
        const unsigned mask = 1u + unsigned(below(rng, 7));
        const I3 h = detail::half_extents_through(a, v, mask, rng);
        const I3 d = random_nonzero_i3(rng, 8);
        const BoundaryParameter at = boundary_parameter(rng, 1, 8);
        const Vec3<T> dv = to_vec_signed_zeros<T>(d, rng);
        if (!detail::obb_from_integers<T>(a, center, h, sub(add(center, v), mul(at.s, d)), dv, random_translation<T>(rng), c))
            return false;
        on_boundary_t_range(c.ray, rng, at, 8);
        return true;
    });
}

// Extreme scenes: a tiny box far away aimed at to within a few ulps, a huge box, nearly
// dependent axes (valid: det != 0 by one ulp), axes of denormal or huge magnitude.
template <class T> Case<T, Obb<T>> obb_extreme(Rng& rng) {
    using L = std::numeric_limits<T>;
    Case<T, Obb<T>> c = renamed(obb_general<T>(rng), "extreme");
    const auto kind = below(rng, 4);
    if (kind == 0) {  // tiny and far
        for (int i = 0; i < 3; ++i) c.shape.center[i] = magnitude<T>(rng, 20, L::max_exponent - 8);
        const T scale = std::ldexp(c.shape.center.cwiseAbs().maxCoeff(), -int(uniform_int(rng, 8, kPrecision<T> + 24)));
        for (int i = 0; i < 3; ++i) c.shape.half_extent[i] = scale * narrow<T>(uniform01(rng));
        for (int i = 0; i < 3; ++i) c.ray.origin[i] = uniform<T>(rng, -1, 1);
        c.ray.direction = c.shape.center - c.ray.origin;
        const int j = int(below(rng, 3));
        c.ray.direction[j] = nudge(c.ray.direction[j], int(uniform_int(rng, -3, 3)));
    } else if (kind == 1) {  // huge
        for (int i = 0; i < 3; ++i) {
            c.shape.half_extent[i] = magnitude<T>(rng, L::max_exponent - 6, L::max_exponent - 1, false);
            c.ray.origin[i] = chance(rng, 1, 2) ? wide_value<T>(rng) : narrow<T>(random_sign(rng)) * L::max();
        }
        c.ray.direction = nonzero_wide_vec<T>(rng);
    } else if (kind == 2) {  // nearly dependent axes: a2 = a0 + a1 with one entry nudged
        const IMat3 a = integer_axes(rng);
        c.shape.axes = to_mat<T>(a);
        c.shape.axes.col(2) = c.shape.axes.col(0) + c.shape.axes.col(1);
        // Nudge a row where a0 × a1 is nonzero: only that moves a2 off the plane of a0, a1.
        const I3 n = cross(a.col[0], a.col[1]);
        int r = int(below(rng, 3));
        while (n[r] == 0) r = (r + 1) % 3;
        T& x = c.shape.axes(r, 2);
        x = x == 0 ? narrow<T>(random_sign(rng)) * L::denorm_min() : nudge(x, random_sign(rng));
        for (int i = 0; i < 3; ++i) c.shape.half_extent[i] = narrow<T>(uniform_int(rng, 0, 16));
    } else {  // axes of extreme magnitude
        const int e = chance(rng, 1, 2) ? int(uniform_int(rng, L::min_exponent - kPrecision<T> + 8, L::min_exponent))
                                        : int(uniform_int(rng, L::max_exponent / 2, L::max_exponent - 4));
        for (int i = 0; i < 9; ++i) c.shape.axes.data()[i] = std::ldexp(c.shape.axes.data()[i], e);
        for (int i = 0; i < 3; ++i) c.shape.half_extent[i] = std::ldexp(c.shape.half_extent[i], e);
    }
    if (c.ray.direction.isZero()) c.ray.direction = Vec3<T>(1, 0, 0);
    return c;
}

// Invalid inputs: every ray rule, NaN or inf in the centre, the axes or the half
// extents, a negative half extent (down to -denorm_min), and linearly dependent axes
// (a zero column, a repeated or scaled column, a column that is an exact integer
// combination of the others, at any scale).
template <class T> Case<T, Obb<T>> obb_invalid(Rng& rng) {
    return invalid_from(obb_general<T>, obb_grazing<T>, rng, 3, FaultAxis::drawn,
                        [&](Case<T, Obb<T>>& c, unsigned k, int i) {
                            if (k == 0) {
                                const T bad = non_finite<T>(rng);
                                const auto where = below(rng, 3);
                                if (where == 0) c.shape.center[i] = bad;
                                else if (where == 1) c.shape.axes(i, int(below(rng, 3))) = bad;
                                else c.shape.half_extent[i] = bad;
                            } else if (k == 1) {
                                c.shape.half_extent[i] =
                                    chance(rng, 1, 2) ? -std::numeric_limits<T>::denorm_min() : -narrow<T>(uniform_int(rng, 1, 8));
                            } else {
                                const IMat3 a = integer_axes(rng);
                                Mat3<T> m = to_mat<T>(a);
                                const int j = (i + 1 + int(below(rng, 2))) % 3, l = 3 - i - j;
                                switch (below(rng, 4)) {
                                    case 0: m.col(i).setZero(); if (rng() & 1) m(0, i) = -T(0); break;
                                    case 1: m.col(i) = m.col(j); break;
                                    case 2: m.col(i) = narrow<T>(signed_int(rng, 1, 4)) * m.col(j); break;
                                    default: {
                                        const T u = narrow<T>(uniform_int(rng, -3, 3)), v = narrow<T>(uniform_int(rng, -3, 3));
                                        m.col(i) = u * m.col(j) + v * m.col(l);
                                        break;
                                    }
                                }
                                const int e = chance(rng, 1, 2) ? 0 : int(uniform_int(rng, -100, 100));
                                for (int q = 0; q < 9; ++q) m.data()[q] = std::ldexp(m.data()[q], e);
                                c.shape.axes = m;
                            }
                        });
}

}  // namespace rayproof::gen
