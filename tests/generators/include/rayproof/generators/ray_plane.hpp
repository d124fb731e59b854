// rayproof/generators/ray_plane.hpp — case generators for ray vs plane.
//
// Constructed families: an integer normal n and an integer point P give the exact offset
// n·P; d = n × w is exactly parallel to the plane, so o = P - s·d lies exactly in it.
#pragma once

#include <rayproof/generators/core.hpp>

namespace rayproof::gen {

namespace detail {
template <class T> bool plane_from_integers(const I3& n, const I3& point, const I3& origin, const Vec3<T>& d,
                                            std::int64_t offset_shift, Case<T, Plane<T>>& c) {
    const std::int64_t offset = dot(n, point) + offset_shift;
    if (!representable<T>(n) || !representable<T>(offset) || !ray_from_integers(origin, d, c.ray)) return false;
    c.shape.normal = to_vec<T>(n);
    c.shape.offset = narrow<T>(offset);
    return true;
}
}  // namespace detail

// General position: a random normal in [-1, 1]³, an offset in [-8, 8], an origin in
// [-16, 16]³ and a random direction (about half the rays cross the plane ahead).
template <class T> Case<T, Plane<T>> plane_general(Rng& rng) {
    Case<T, Plane<T>> c{{}, {}, "general"};
    c.shape.normal = nonzero_vec<T>(rng, [](Rng& g) { return uniform<T>(g, -1, 1); });
    c.shape.offset = uniform<T>(rng, -8, 8);
    for (int i = 0; i < 3; ++i) c.ray.origin[i] = uniform<T>(rng, -16, 16);
    c.ray.direction = nonzero_vec<T>(rng, [](Rng& g) { return uniform<T>(g, -1, 1); });
    random_t_range(c.ray, rng, 64);
    return c;
}

// Every number log-uniform over the whole exponent range of T.
template <class T> Case<T, Plane<T>> plane_log_uniform(Rng& rng) {
    Case<T, Plane<T>> c{{}, {}, "log_uniform"};
    c.shape.normal = nonzero_wide_vec<T>(rng);
    c.shape.offset = wide_value<T>(rng);
    for (int i = 0; i < 3; ++i) c.ray.origin[i] = wide_value<T>(rng);
    wide_direction_and_range(c.ray, rng);
    return c;
}

// Exact grazing for a plane: the ray lies exactly in it (n·d == 0 and n·o == offset
// exactly), on ranges finite, half-infinite or the whole line.
template <class T> Case<T, Plane<T>> plane_grazing(Rng& rng) {
    return constructed<T, Plane<T>>("grazing", rng, [&](Case<T, Plane<T>>& c) {
        const I3 n = random_nonzero_i3(rng, 8);
        const I3 d = cross(n, random_nonzero_i3(rng, 8));
        if (is_zero(d)) return false;
        const I3 p0 = random_i3(rng, -8, 8);
        const I3 p = add(p0, random_translation<T>(rng));
        const std::int64_t s = uniform_int(rng, -8, 8);
        if (!detail::plane_from_integers<T>(n, p, sub(p, mul(s, d)), to_vec_signed_zeros<T>(d, rng), 0, c))
            return false;
        if (chance(rng, 1, 2)) c.shape.normal = to_vec_signed_zeros<T>(n, rng);
        special_t_range(c.ray, rng, narrow<T>(s));
        return true;
    });
}

// The in-plane rays with one direction component moved by one ulp either way (a crossing
// at a huge |t|, ahead or behind), or the offset or one origin coordinate moved by one
// ulp (parallel, just off the plane).
template <class T> Case<T, Plane<T>> plane_near_grazing(Rng& rng) {
    return near_grazing_from(
        plane_grazing<T>(rng), rng, [](Case<T, Plane<T>>& c, int, Rng& g) { nudge_ulp(c.shape.offset, g); },
        nudge_origin);
}

// Exactly parallel rays (n·d == 0) off the plane by an integer distance, and axis-aligned
// normals with the matching direction component +0 or -0, origin on or off the plane.
template <class T> Case<T, Plane<T>> plane_parallel(Rng& rng) {
    return constructed<T, Plane<T>>("parallel", rng, [&](Case<T, Plane<T>>& c) {
        I3 n, d;
        if (chance(rng, 1, 2)) {
            n = random_nonzero_i3(rng, 8);
            d = cross(n, random_nonzero_i3(rng, 8));
        } else {
            const int a = int(below(rng, 3));
            n = {0, 0, 0};
            n[a] = signed_int(rng, 1, 8);
            d = random_nonzero_i3(rng, 8);
            d[a] = 0;
        }
        if (is_zero(d)) return false;
        const I3 p0 = random_i3(rng, -8, 8);
        const I3 p = add(p0, random_translation<T>(rng));
        const std::int64_t shift = chance(rng, 1, 3) ? 0 : signed_int(rng, 1, 16);
        const std::int64_t s = uniform_int(rng, -4, 4);
        if (!detail::plane_from_integers<T>(n, p, sub(p, mul(s, d)), to_vec_signed_zeros<T>(d, rng), shift, c))
            return false;
        c.shape.normal = to_vec_signed_zeros<T>(n, rng);
        random_t_range(c.ray, rng, 16);
        return true;
    });
}

// Origins exactly on the plane (the crossing at t = 0, with t_min = 0 or t_min just
// above), or crossings exactly at t_min or t_max (or a one-point range [s, s]).
template <class T> Case<T, Plane<T>> plane_on_boundary(Rng& rng) {
    return constructed<T, Plane<T>>("on_boundary", rng, [&](Case<T, Plane<T>>& c) {
        const I3 n = random_nonzero_i3(rng, 8);
        const I3 d = random_nonzero_i3(rng, 8);
        if (dot(n, d) == 0) return false;
        const I3 p0 = random_i3(rng, -8, 8);
        const I3 p = add(p0, random_translation<T>(rng));
        const BoundaryParameter at = boundary_parameter(rng, -8, 8);
        if (!detail::plane_from_integers<T>(n, p, sub(p, mul(at.s, d)), to_vec_signed_zeros<T>(d, rng), 0, c))
            return false;
        on_boundary_t_range(c.ray, rng, at, [](Ray<T>& r, Rng& g) {
            const auto k = below(g, 3);
            r.t_min = k == 0 ? T(0) : k == 1 ? std::numeric_limits<T>::denorm_min() : -T(0);
            r.t_max = chance(g, 1, 2) ? kInf<T> : narrow<T>(uniform_int(g, 0, 4));
        });
        return true;
    });
}

// Extreme scenes: nearly parallel rays (d rounded into the plane, so n·d is a few
// roundings from 0), a plane far from the origin, a denormal-sized normal, a huge
// normal and direction whose dot product overflows T, and a crossing near the top of
// the range with a limit a few percent from it, n·d computed with cancellation (terms
// 2^(p+25), the sum a few ulps of them, up to half an ulp off) so that for double the
// limit times the computed n·d overflows; and a far crossing (about 2^k away, from an
// origin near the plane) by a ray whose n·d cancels to 2^-k of its terms (k from 4 to
// most of T's precision), then scaled by powers of two anywhere in T's range, so that
// |t| times the bound on n·d dwarfs the numerator's terms (and products of the two
// bounds may underflow).
template <class T> Case<T, Plane<T>> plane_extreme(Rng& rng) {
    using L = std::numeric_limits<T>;
    Case<T, Plane<T>> c = renamed(plane_general<T>(rng), "extreme");
    const auto kind = below(rng, 6);
    if (kind == 0) {  // nearly parallel
        const Vec3<T> w = nonzero_vec<T>(rng, [](Rng& g) { return uniform<T>(g, -1, 1); });
        c.ray.direction = c.shape.normal.cross(w);
        if (c.ray.direction.isZero()) c.ray.direction = Vec3<T>(1, 0, 0);
        if (chance(rng, 1, 2)) {
            const int j = int(below(rng, 3));
            nudge_ulp(c.ray.direction[j], rng);
        }
    } else if (kind == 1) {  // far plane
        c.shape.offset = magnitude<T>(rng, 20, L::max_exponent - 2);
        c.ray.direction = c.shape.normal * (c.shape.offset < 0 ? T(-1) : T(1));
        const int j = int(below(rng, 3));
        c.ray.direction[j] = nudge(c.ray.direction[j], int(uniform_int(rng, -4, 4)));
        if (c.ray.direction.isZero()) c.ray.direction = Vec3<T>(0, 0, 1);
    } else if (kind == 2) {  // denormal normal
        for (int i = 0; i < 3; ++i)
            c.shape.normal[i] = magnitude<T>(rng, L::min_exponent - kPrecision<T>, L::min_exponent);
        c.shape.offset = magnitude<T>(rng, L::min_exponent - kPrecision<T>, L::min_exponent + 8);
    } else if (kind == 3) {  // huge normal and direction
        for (int i = 0; i < 3; ++i) {
            c.shape.normal[i] = magnitude<T>(rng, L::max_exponent / 2, L::max_exponent - 1);
            c.ray.direction[i] = magnitude<T>(rng, L::max_exponent / 2, L::max_exponent - 1);
            c.ray.origin[i] = wide_value<T>(rng);
        }
        c.shape.offset = wide_value<T>(rng);
    } else if (kind == 4) {  // a far crossing by a nearly parallel ray, scaled
        // The origin near the plane, the direction tilted out of it by 2^-k of its length
        // (so n·d cancels to about 2^-k of its terms) and the crossing about 2^j away, j
        // near k: the numerator offset - n·o = t·(n·d) is then not cancelled, and its
        // terms are far smaller than |t| times those of n·d.
        const Vec3<T>& n = c.shape.normal;
        const Vec3<T> w = nonzero_vec<T>(rng, [](Rng& g) { return uniform<T>(g, -1, 1); });
        const Vec3<T> along = n.cross(w);
        if (along.isZero()) return c;
        const int k = int(uniform_int(rng, 4, kPrecision<T> - 8));
        const T tilt = std::ldexp(along.norm() / n.norm(), -k) * narrow<T>(random_sign(rng));
        c.ray.direction = along + tilt * n;
        const int j = int(uniform_int(rng, k - 4, k + 8));
        const T t0 = std::ldexp(uniform<T>(rng, 1, 2), j) * narrow<T>(random_sign(rng));
        c.shape.offset = n.dot(c.ray.origin + t0 * c.ray.direction);
        const auto range = below(rng, 3);
        if (range == 0) {
            c.ray.t_min = 0;
            c.ray.t_max = kInf<T>;
        } else if (range == 1) {
            c.ray.t_min = -kInf<T>;
            c.ray.t_max = kInf<T>;
        } else {  // around t0, a few ulps to half of it wide
            const T half = std::ldexp(std::abs(t0), -int(uniform_int(rng, 1, kPrecision<T> - 4)));
            c.ray.t_min = t0 - half;
            c.ray.t_max = t0 + half;
        }
        random_exact_scaling(c, rng);
    } else {  // a far crossing next to a limit, n·d with cancellation
        const T s = narrow<T>(random_sign(rng)), big = std::ldexp(T(1), kPrecision<T> + 25);  // its ulp: 2^26
        const T x = std::ldexp(uniform<T>(rng, 8.5, 12.5), 26);
        c.shape.normal = Vec3<T>(s, s, s);
        c.ray.origin = Vec3<T>(0, 0, 0);
        c.ray.direction = Vec3<T>(big, x, -big);
        c.shape.offset = narrow<T>(random_sign(rng)) * uniform<T>(rng, 0.9, 1.0) * L::max();
        const T limit = narrow<T>(double(c.shape.offset) / (double(s) * double(x)) * uniform<double>(rng, 0.95, 1.05));
        if (chance(rng, 1, 2)) {
            c.ray.t_min = limit;
            c.ray.t_max = kInf<T>;
        } else {
            c.ray.t_min = -kInf<T>;
            c.ray.t_max = limit;
        }
    }
    return c;
}

// Invalid inputs: every ray rule, a zero normal (signed zeros mixed), NaN or inf in the
// normal or the offset.
template <class T> Case<T, Plane<T>> plane_invalid(Rng& rng) {
    return invalid_from(plane_general<T>, plane_grazing<T>, rng, 2, FaultAxis::none,
                        [&](Case<T, Plane<T>>& c, unsigned k, int) {
                            if (k == 0) {
                                for (int i = 0; i < 3; ++i) c.shape.normal[i] = (rng() & 1) ? T(0) : -T(0);
                            } else {
                                make_non_finite(c.shape.offset, c.shape.normal, rng);
                            }
                        });
}

}  // namespace rayproof::gen
