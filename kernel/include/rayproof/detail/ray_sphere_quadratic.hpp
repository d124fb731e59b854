// rayproof/detail/ray_sphere_quadratic.hpp — the quadratic q(t) = |Δ + t d|² - r² of a ray
// and a sphere (SphereQuadratic): interval enclosures of its coefficients, discriminant,
// roots and values, its double-word residual, and its exact signs. The conservative mode
// answers from its enclosures, the certified general path (ray_sphere_general.hpp) decides
// on them.
#pragma once

#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/detail/ray_sphere_residual.hpp>
#include <rayproof/types.hpp>

#include <optional>
#include <utility>

namespace rayproof::detail {

// The quadratic q(t) = |Δ + t d|² - r² of a ray and a sphere, with interval enclosures
// of its pieces and exact signs on demand.
template <class T> class SphereQuadratic {
public:
    using I = Interval<double>;
    SphereQuadratic(const Ray<T>& r, const Sphere<T>& s) : r_(&r), s_(&s) {
        I a(0.0), b(0.0), dd(0.0);
        for (int j = 0; j < 3; ++j) {
            delta_[j] = I(double(r.origin[j])) - I(double(s.center[j]));
            const I d(double(r.direction[j]));
            a = a + sqr(d);
            b = b + d * delta_[j];
            dd = dd + sqr(delta_[j]);
        }
        a_ = a;
        b_ = b;
        c_ = dd - sqr(I(double(s.radius)));
    }
    const I& a() const { return a_; }
    const I& b() const { return b_; }
    const I& c() const { return c_; }

    // Enclosure of the discriminant b² - a c' = a (r - l)(r + l), l = |Δ - (b/a) d|.
    I discriminant() const {
        const I f = b_ / a_;
        I l2(0.0);
        for (int j = 0; j < 3; ++j) l2 = l2 + sqr(delta_[j] - f * I(double(r_->direction[j])));
        const I l = sqrt_nonneg(l2), rad(double(s_->radius));
        return a_ * ((rad - l) * (rad + l));
    }
    // Enclosures of the two roots, given the discriminant's enclosure (hi >= 0).
    std::pair<I, I> roots(const I& disc) const {
        const I sq = sqrt_nonneg(disc);
        if (b_.lo > 0 || b_.hi < 0) {
            const I q = b_.lo > 0 ? -(b_ + sq) : sq - b_;  // no cancellation: same signs
            if (!q.contains_zero()) {
                const I r1 = q / a_, r2 = c_ / q;
                return b_.lo > 0 ? std::pair{r1, r2} : std::pair{r2, r1};
            }
        }
        return {(-b_ - sq) / a_, (sq - b_) / a_};
    }
    I at(double t) const {  // q(t)
        const I ti(t);
        I s(0.0);
        for (int j = 0; j < 3; ++j) s = s + sqr(delta_[j] + ti * I(double(r_->direction[j])));
        return s - sqr(I(double(s_->radius)));
    }
    I slope(double t) const { return a_ * I(t) + b_; }  // a t + b, half the derivative

    // q in double-word arithmetic with a proven bound: its sign_at(t) is sign q(t), or 2
    // when the bound cannot decide (t finite). Built by the caller once per query.
    SphereResidual residual() const {
        return SphereResidual(double3(r_->origin), double3(r_->direction), double3(s_->center), double(s_->radius));
    }

    // Exact signs.
    int sign_at(double t) const {  // sign q(t), t finite
        return exact_sign([&](auto tag) {
            using E = typename decltype(tag)::type;
            const E et(t);
            E s(0.0);
            for (int j = 0; j < 3; ++j) {
                const E v = E(double(r_->origin[j])) - E(double(s_->center[j])) + et * E(double(r_->direction[j]));
                s = s + v * v;
            }
            const E rad(double(s_->radius));
            return s - rad * rad;
        });
    }
    int sign_slope(double t) const {  // sign(a t + b), t finite
        return exact_sign([&](auto tag) {
            using E = typename decltype(tag)::type;
            return ea<E>() * E(t) + eb<E>();
        });
    }
    int sign_discriminant() const {  // sign(b² - a c')
        return exact_sign([&](auto tag) {
            using E = typename decltype(tag)::type;
            const E b = eb<E>();
            E c(0.0);
            for (int j = 0; j < 3; ++j) {
                const E dj = E(double(r_->origin[j])) - E(double(s_->center[j]));
                c = c + dj * dj;
            }
            const E rad(double(s_->radius));
            c = c - rad * rad;
            return b * b - ea<E>() * c;
        });
    }

private:
    template <class E> E ea() const {
        E s(0.0);
        for (int j = 0; j < 3; ++j) s = s + E(double(r_->direction[j])) * E(double(r_->direction[j]));
        return s;
    }
    template <class E> E eb() const {
        E s(0.0);
        for (int j = 0; j < 3; ++j)
            s = s + E(double(r_->direction[j])) * (E(double(r_->origin[j])) - E(double(s_->center[j])));
        return s;
    }
    bool safe() const {
        return expansion_safe(r_->origin) && expansion_safe(r_->direction) && expansion_safe(s_->center) &&
               expansion_safe(s_->radius);
    }
    template <class F> int exact_sign(F&& value) const { return detail::exact_sign(safe(), value); }
    const Ray<T>* r_;
    const Sphere<T>* s_;
    I delta_[3], a_, b_, c_;
};

}  // namespace rayproof::detail
