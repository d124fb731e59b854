// rayproof/generators/ray_sphere.hpp — case generators for ray vs sphere (the closed ball).
//
// Constructed families use Pythagorean quadruples (a, b, c, n), a² + b² + c² = n²: the
// point S = C + k·(a, b, c) lies exactly on the sphere of radius k·n about C, and a
// direction d = (a, b, c) × w is exactly perpendicular to the radius there, so the ray
// through S along d is exactly tangent. Integers keep it exact in T; exact translations
// and power-of-two scalings move it anywhere in the exponent range.
#pragma once

#include <rayproof/generators/core.hpp>

namespace rayproof::gen {

namespace detail {
template <class T> bool sphere_from_integers(const I3& center, std::int64_t radius, const I3& origin, const Vec3<T>& d,
                                             const I3& tau, Case<T, Sphere<T>>& c) {
    const I3 ct = add(center, tau);
    if (!representable<T>(ct) || !representable<T>(radius) || !ray_from_integers(add(origin, tau), d, c.ray)) return false;
    c.shape.center = to_vec<T>(ct);
    c.shape.radius = narrow<T>(radius);
    return true;
}
}  // namespace detail

// General position: a centre in [-8, 8]³, a radius in (0, 4], an origin in [-16, 16]³
// aimed at a random point of the sphere's bounding cube grown by a quarter.
template <class T> Case<T, Sphere<T>> sphere_general(Rng& rng) {
    Case<T, Sphere<T>> c{{}, {}, "general"};
    c.shape.radius = uniform<T>(rng, 0, 4);
    Vec3<T> target;
    for (int i = 0; i < 3; ++i) {
        c.shape.center[i] = uniform<T>(rng, -8, 8);
        c.ray.origin[i] = uniform<T>(rng, -16, 16);
        target[i] = c.shape.center[i] + T(1.25) * c.shape.radius * uniform<T>(rng, -1, 1);
    }
    c.ray.direction = target - c.ray.origin;
    if (c.ray.direction.isZero()) c.ray.direction = Vec3<T>(0, 1, 0);
    random_t_range(c.ray, rng, 64);
    return c;
}

// Every number log-uniform over the whole exponent range (the radius its magnitude).
template <class T> Case<T, Sphere<T>> sphere_log_uniform(Rng& rng) {
    Case<T, Sphere<T>> c{{}, {}, "log_uniform"};
    for (int i = 0; i < 3; ++i) {
        c.shape.center[i] = wide_value<T>(rng);
        c.ray.origin[i] = wide_value<T>(rng);
    }
    c.shape.radius = std::abs(wide_value<T>(rng));
    c.ray.direction = nonzero_wide_vec<T>(rng);
    if (chance(rng, 1, 4)) c.ray.t_min = -kInf<T>;
    return c;
}

// Exact tangents: the ray touches the sphere at exactly one point, at the exact parameter
// s (one time in eight: a point sphere, radius +0 or -0, that the ray passes through).
template <class T> Case<T, Sphere<T>> sphere_grazing(Rng& rng) {
    return constructed<T, Sphere<T>>("grazing", rng, [&](Case<T, Sphere<T>>& c) {
        const I3 center = random_i3(rng, -8, 8);
        const std::int64_t s = chance(rng, 1, 8) ? 0 : uniform_int(rng, 1, 8);
        const I3 tau = random_translation<T>(rng);
        if (chance(rng, 1, 8)) {
            const I3 d = random_nonzero_i3(rng, 8);
            if (!detail::sphere_from_integers<T>(center, 0, sub(center, mul(s, d)), to_vec_signed_zeros<T>(d, rng), tau, c))
                return false;
            if (rng() & 1) c.shape.radius = -T(0);
        } else {
            const Quadruple q = pythagorean_quadruple(rng);
            const std::int64_t k = uniform_int(rng, 1, 4);
            const I3 d = cross(q.v, random_nonzero_i3(rng, 8));
            if (is_zero(d)) return false;
            const I3 touch = add(center, mul(k, q.v));
            if (!detail::sphere_from_integers<T>(center, k * q.n, sub(touch, mul(s, d)), to_vec_signed_zeros<T>(d, rng),
                                                 tau, c))
                return false;
        }
        special_t_range(c.ray, rng, narrow<T>(s));
        return true;
    });
}

// The tangent rays with one direction component moved by one ulp either way, or the
// radius or one origin coordinate moved by one ulp: a hair inside or outside tangency.
template <class T> Case<T, Sphere<T>> sphere_near_grazing(Rng& rng) {
    const auto nudge_radius = [](Case<T, Sphere<T>>& c, int, Rng& g) {
        if (c.shape.radius == 0)
            c.shape.radius = std::numeric_limits<T>::denorm_min();
        else
            nudge_ulp(c.shape.radius, g);
    };
    return near_grazing_from(sphere_grazing<T>(rng), rng, nudge_radius, nudge_origin);
}

// Axis-aligned directions (the other components +0 or -0) passing the centre at an
// integer offset from a Pythagorean triple: exactly tangent, one unit inside or outside,
// or through the centre.
template <class T> Case<T, Sphere<T>> sphere_parallel(Rng& rng) {
    return constructed<T, Sphere<T>>("parallel", rng, [&](Case<T, Sphere<T>>& c) {
        const int a = int(below(rng, 3)), b = (a + 1) % 3, e = (a + 2) % 3;
        const std::int64_t m = uniform_int(rng, 1, 5), n = uniform_int(rng, 0, m - 1), k = uniform_int(rng, 1, 4);
        std::int64_t p = k * (m * m - n * n), q = k * 2 * m * n;
        const std::int64_t h = k * (m * m + n * n);
        if (rng() & 1) std::swap(p, q);
        const I3 center = random_i3(rng, -8, 8);
        I3 origin = center, d = {0, 0, 0};
        std::int64_t radius = h;
        switch (below(rng, 4)) {
            case 0: radius = h + 1; break;                  // crossing
            case 1: radius = h - 1; break;                  // passing just outside
            case 2: p = q = 0; break;                       // through the centre
            default: break;                                 // exactly tangent
        }
        origin[b] += random_sign(rng) * p;
        origin[e] += random_sign(rng) * q;
        origin[a] += uniform_int(rng, -2 * h - 4, 2 * h + 4);
        d[a] = signed_int(rng, 1, 8);
        if (!detail::sphere_from_integers<T>(center, radius, origin, to_vec<T>(d), random_translation<T>(rng), c))
            return false;
        c.ray.direction[b] = (rng() & 1) ? T(0) : -T(0);
        c.ray.direction[e] = (rng() & 1) ? T(0) : -T(0);
        random_t_range(c.ray, rng, 16);
        return true;
    });
}

// Origins exactly on the sphere (directions inward, outward, exactly tangent or radial),
// or t_min / t_max exactly at the parameter of a point on the sphere; or, one case in
// four, an origin c + r·u rounded to T for a random centre, radius and unit u (q at the
// origin tiny, of either sign, with general mantissas: the sign a filter must not
// guess from rounded arithmetic), t_min = 0 and the ray leaving the sphere or not.
template <class T> Case<T, Sphere<T>> sphere_on_boundary(Rng& rng) {
    if (chance(rng, 1, 4)) {
        Case<T, Sphere<T>> c{{}, {}, "on_boundary"};
        double u[3], n2 = 0;
        do {
            n2 = 0;
            for (double& x : u) {
                x = uniform<double>(rng, -1, 1);
                n2 += x * x;
            }
        } while (n2 < 0x1p-4 || n2 > 1);
        const double rad = uniform<double>(rng, 0.25, 8), n = std::sqrt(n2);
        c.shape.radius = narrow<T>(rad);
        for (int j = 0; j < 3; ++j) {
            c.shape.center[j] = uniform<T>(rng, -16, 16);
            c.ray.origin[j] = narrow<T>(double(c.shape.center[j]) + double(c.shape.radius) * (u[j] / n));
            // mostly along u (leaving the sphere), else at random
            const double w = uniform<double>(rng, -1, 1);
            c.ray.direction[j] = narrow<T>(chance(rng, 1, 3) ? w : u[j] + 0.5 * w);
        }
        if (c.ray.direction == Vec3<T>::Zero()) c.ray.direction[0] = T(1);
        c.ray.t_min = 0;
        c.ray.t_max = chance(rng, 1, 2) ? kInf<T> : uniform<T>(rng, 0, 16);
        return c;
    }
    return constructed<T, Sphere<T>>("on_boundary", rng, [&](Case<T, Sphere<T>>& c) {
        const I3 center = random_i3(rng, -8, 8);
        const Quadruple q = pythagorean_quadruple(rng);
        const std::int64_t k = uniform_int(rng, 1, 4);
        const I3 surface = add(center, mul(k, q.v));
        I3 d;
        switch (below(rng, 4)) {
            case 0: d = cross(q.v, random_nonzero_i3(rng, 8)); break;         // tangent
            case 1: d = mul(signed_int(rng, 1, 3), q.v); break;  // radial
            default: d = random_nonzero_i3(rng, 8); break;
        }
        if (is_zero(d)) return false;
        const BoundaryParameter at = boundary_parameter(rng, 1, 8);
        const Vec3<T> dv = to_vec_signed_zeros<T>(d, rng);
        if (!detail::sphere_from_integers<T>(center, k * q.n, sub(surface, mul(at.s, d)), dv, random_translation<T>(rng), c))
            return false;
        on_boundary_t_range(c.ray, rng, at, 8);
        return true;
    });
}

// Extreme scenes: a tiny sphere (radius 1e-3, or far below the ulp of its centre) far
// from the origin and aimed at to within a few ulps; a huge sphere; a point sphere far
// away; a sphere of denormal size.
template <class T> Case<T, Sphere<T>> sphere_extreme(Rng& rng) {
    using L = std::numeric_limits<T>;
    Case<T, Sphere<T>> c{{}, {}, "extreme"};
    const auto kind = below(rng, 4);
    if (kind == 0 || kind == 2) {  // tiny (or a point) and far
        const int far = chance(rng, 1, 2) ? L::max_exponent / 2 - 4 : L::max_exponent - 8;
        for (int i = 0; i < 3; ++i) c.shape.center[i] = magnitude<T>(rng, 20, far);
        const T dist = c.shape.center.cwiseAbs().maxCoeff();
        c.shape.radius = kind == 2 ? T(0)
                         : chance(rng, 1, 2) ? narrow<T>(1e-3)
                                             : std::ldexp(dist, -int(uniform_int(rng, 10, kPrecision<T> + 20)));
        for (int i = 0; i < 3; ++i) c.ray.origin[i] = uniform<T>(rng, -1, 1);
        c.ray.direction = c.shape.center - c.ray.origin;
        const int j = int(below(rng, 3));
        c.ray.direction[j] = nudge(c.ray.direction[j], int(uniform_int(rng, -3, 3)));
    } else if (kind == 1) {  // huge
        c.shape.radius = magnitude<T>(rng, L::max_exponent - 6, L::max_exponent - 1, false);
        for (int i = 0; i < 3; ++i) {
            c.shape.center[i] = wide_value<T>(rng);
            c.ray.origin[i] = chance(rng, 1, 2) ? wide_value<T>(rng) : c.shape.radius * narrow<T>(uniform01(rng));
        }
        c.ray.direction = nonzero_wide_vec<T>(rng);
    } else {  // denormal sized
        for (int i = 0; i < 3; ++i) {
            c.shape.center[i] = magnitude<T>(rng, L::min_exponent - kPrecision<T>, L::min_exponent);
            c.ray.origin[i] = magnitude<T>(rng, L::min_exponent - kPrecision<T>, L::min_exponent + 4);
        }
        c.shape.radius = magnitude<T>(rng, L::min_exponent - kPrecision<T>, L::min_exponent, false);
        c.ray.direction = chance(rng, 1, 2) ? Vec3<T>(c.shape.center - c.ray.origin)
                                            : nonzero_wide_vec<T>(rng);
    }
    if (c.ray.direction.isZero()) c.ray.direction = Vec3<T>(1, 0, 0);
    if (chance(rng, 1, 4)) c.ray.t_min = -kInf<T>;
    return c;
}

// Invalid inputs: every ray rule, a negative radius (down to -denorm_min; -0 is valid
// and never produced here), NaN or inf in the centre or the radius.
template <class T> Case<T, Sphere<T>> sphere_invalid(Rng& rng) {
    return invalid_from(sphere_general<T>, sphere_grazing<T>, rng, 2, FaultAxis::none,
                        [&](Case<T, Sphere<T>>& c, unsigned k, int) {
                            if (k == 0) {
                                c.shape.radius = chance(rng, 1, 2) ? -std::numeric_limits<T>::denorm_min()
                                                                   : -uniform<T>(rng, 0.5, 8);
                            } else {
                                make_non_finite(c.shape.radius, c.shape.center, rng);
                            }
                        });
}

}  // namespace rayproof::gen
