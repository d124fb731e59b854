// ray_sphere_oracle.hpp — internal to the oracle library: the exact answer for a ray against
// a Sphere, exact(ray, Sphere). Part of oracle.cpp's one translation unit, which includes
// it and instantiates it for float and double.
//
// How it is decided (the contract's definition, literally): with Δ = o - c: a = d·d,
// b = d·Δ, c = Δ·Δ - r², D = b² - a·c (exact). D < 0: miss. Otherwise the roots
// -b/a ∓ sqrt(D/a²) are kept symbolically (rational when D/a² is a square), and every
// comparison with them is exact (internal::sign_minus, oracle.cpp).
#pragma once

#include "exact_answer.hpp"

#include <array>
#include <cmath>

namespace rayproof::oracle {

template <class T> Exact<T> exact(const Ray<T>& ray, const Sphere<T>& sphere) {
    if (!valid(ray) || !valid(sphere)) return invalid_answer<T>();
    const std::array<Q, 3> o = q3(ray.origin), d = q3(ray.direction), c = q3(sphere.center);
    const std::array<Q, 3> delta = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
    const Q r = to_q(sphere.radius);
    const Q a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const Q b = d[0] * delta[0] + d[1] * delta[1] + d[2] * delta[2];
    const Q cc = delta[0] * delta[0] + delta[1] * delta[1] + delta[2] * delta[2] - r * r;
    const Q disc = b * b - a * cc;
    Exact<T> e;
    if (CGAL::sign(disc) == CGAL::NEGATIVE) return e;
    // Roots -b/a ∓ sqrt(disc/a²).
    const Q p = -b / a;
    const Q rr = disc / (a * a);
    const ExactValue t0 = internal::make_root(p, rr, -1), t1 = internal::make_root(p, rr, +1);
    // Hit iff t0 <= t_max and t_min <= t1.
    const auto below_or_at = [](const ExactValue& v, T t) {  // v <= t
        if (std::isinf(t)) return t > 0;
        return internal::sign_minus(*v.impl(), to_q(t)) <= 0;
    };
    const auto above_or_at = [](const ExactValue& v, T t) {  // v >= t
        if (std::isinf(t)) return t < 0;
        return internal::sign_minus(*v.impl(), to_q(t)) >= 0;
    };
    if (!below_or_at(t0, ray.t_max) || !above_or_at(t1, ray.t_min)) return e;
    e.verdict = Verdict::hit;
    e.t_enter = above_or_at(t0, ray.t_min) ? t0 : value_of(xq(ray.t_min));
    e.t_exit = below_or_at(t1, ray.t_max) ? t1 : value_of(xq(ray.t_max));
    return e;
}

}  // namespace rayproof::oracle
