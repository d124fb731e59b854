// rayproof/detail/ray_sphere_quadratic.hpp — the quadratic q(t) = |Δ + t d|² - r² of a ray
// and a sphere (SphereQuadratic): interval enclosures of its coefficients, discriminant,
// roots and values, its double-word residual, and its exact signs. The conservative mode
// answers from its enclosures, the certified general path (ray_sphere_general.hpp) decides
// on them.
#pragma once

#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/detail/ray_sphere_fixed_exact.hpp>
#include <rayproof/detail/ray_sphere_residual.hpp>
#include <rayproof/types.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>

namespace rayproof::detail {

// The careful quadratic's roots of a t² + 2 b t + c' (D = b² - a c' >= 0), each value
// given as mant·2^exp: q = -(b + sign(b)·sqrt(D)), roots q/a and c'/q, ascending. Each
// step keeps the exponents apart from the mantissas, so a, b, c' or D beyond the double
// range (a = |d|² of a direction with a subnormal component reaches 2^-2148) still give
// the roots wherever they lie in it; a root outside gives ±inf or 0.
inline std::pair<double, double> sphere_root_estimates(Approx a, Approx b, Approx c, Approx D) {
    if (b.mant == 0 && D.mant == 0) return {0.0, 0.0};  // the tangent at t = 0
    // sqrt(D) = sqrt(D.mant·2^(D.exp mod 2))·2^(D.exp div 2)
    const long half = D.exp >= 0 ? D.exp / 2 : -((1 - D.exp) / 2);
    const double sm = std::sqrt(std::ldexp(D.mant, int(D.exp - 2 * half)));
    // q = Q·2^k, k the larger exponent of b and sqrt(D) (both mantissas below 2).
    const long k = b.mant == 0 ? half : D.mant == 0 ? b.exp : std::max(b.exp, half);
    const auto at = [k](double m, long e) { return std::ldexp(m, int(std::clamp(e - k, -3000L, 3000L))); };
    const double bq = at(b.mant, b.exp);
    const double Q = -(bq + std::copysign(at(sm, half), bq));
    const auto scaled = [](double m, long e) { return std::ldexp(m, int(std::clamp(e, -3000L, 3000L))); };
    const double t0 = scaled(Q / a.mant, k - a.exp), t1 = scaled(c.mant / Q, c.exp - k);
    return {std::min(t0, t1), std::max(t0, t1)};
}

// The quadratic q(t) = |Δ + t d|² - r² of a ray and a sphere, with interval enclosures
// of its pieces and exact signs on demand.
template <class T> class SphereQuadratic {
public:
    using I = Interval<double>;
    // disc_sign: sign(b² - a c') where the caller decided it already (the tangent
    // shortcut, ray_sphere.hpp), else 2.
    SphereQuadratic(const Ray<T>& r, const Sphere<T>& s, int disc_sign = 2) : r_(&r), s_(&s), disc_sign_(disc_sign) {
        I a(0.0), b(0.0), dd(0.0);
        for (int j = 0; j < 3; ++j) {
            delta_[j] = I(double(r.origin[j])) - I(double(s.center[j]));
            const I d(double(r.direction[j]));
            a = a + sqr(d);
            b = b + times_point(delta_[j], double(r.direction[j]));
            dd = dd + sqr(delta_[j]);
        }
        a_ = a;
        b_ = b;
        r2_ = sqr(I(double(s.radius)));
        c_ = dd - r2_;
    }
    const I& a() const { return a_; }
    const I& b() const { return b_; }
    const I& c() const { return c_; }

    // Enclosure of the discriminant b² - a c' = a (r - l)(r + l), l = |Δ - (b/a) d|.
    I discriminant() const {
        const I f = b_ / a_;
        I l2(0.0);
        for (int j = 0; j < 3; ++j) l2 = l2 + sqr(delta_[j] - times_point(f, double(r_->direction[j])));
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
        for (int j = 0; j < 3; ++j) s = s + sqr(delta_[j] + times_point(ti, double(r_->direction[j])));
        return s - r2_;
    }
    I slope(double t) const { return times_point(a_, t) + b_; }  // a t + b, half the derivative

    // q in double-word arithmetic with a proven bound (SphereResidual): its sign_at(t) is
    // sign q(t), or 2 when the bound cannot decide (t finite). Built by the caller once
    // per query. Where the input is not safe for expansions it is built on the rescaled
    // input of the exact signs below (the same sign at the rescaled t), whose terms then
    // lie well inside the double range: at the given extreme scale they overflow its
    // guard or sink below the bound's absolute floor (2^-1000), and nothing is decided.
    struct Residual {
        SphereResidual res;
        int shift;  // t's scale
        int sign_at(double t) const {
            if (shift == 0) return res.sign_at(t);
            double u;
            return scale_exactly(t, shift, u) ? res.sign_at(u) : 2;
        }
    };
    Residual residual() const {
        const auto of = [](const Values& v) {
            return Residual{SphereResidual({v.o[0], v.o[1], v.o[2]}, {v.d[0], v.d[1], v.d[2]}, {v.c[0], v.c[1], v.c[2]}, v.r),
                            v.shift};
        };
        if (!safe())
            if (const std::optional<Values>& v = rescaled()) return of(*v);
        return of(given());
    }

    // Exact signs. Where the input is not safe for the Expansion type (extreme exponents)
    // they are taken, where possible, on the input rescaled into its safe range
    // (exact.hpp, ExponentSpan): the positions o, c and the radius by 2^sp, the
    // direction by 2^sd, and t by 2^(sp - sd) (when exact), which multiplies q(t) by
    // 2^(2sp), a t + b by 2^(sp + sd) and b² - a c' by 2^(2sp + 2sd), signs unchanged.
    // The discriminant's sign and the vertex come first from fixed-size sums
    // (SphereFixedExact, fixed_sums below) on the same given or rescaled input.
    // rescale = false keeps the input as it is, in the expansion types (the tests
    // compare the routes).
    int sign_at(double t, bool rescale = true) const {  // sign q(t), t finite
        return sign_of(rescale, t, [](const Values& v, double u, auto tag) {
            using E = typename decltype(tag)::type;
            const E et(u);
            E s(0.0);
            for (int j = 0; j < 3; ++j) {
                const E w = E(v.o[j]) - E(v.c[j]) + et * E(v.d[j]);
                s = s + w * w;
            }
            const E rad(v.r);
            return s - rad * rad;
        });
    }
    int sign_slope(double t, bool rescale = true) const {  // sign(a t + b), t finite
        return sign_of(rescale, t, [](const Values& v, double u, auto tag) {
            using E = typename decltype(tag)::type;
            return ea<E>(v) * E(u) + eb<E>(v);
        });
    }
    // The vertex t* = -b/a (a = |d|² > 0), where the slope a t + b changes sign, rounded
    // faithfully to f once, with the exact sign of f - t*: sign(a g + b) = sign(g - t*)
    // then follows for every double g, because t* is f itself or lies strictly between f
    // and its neighbour on the side that sign gives, and no double lies in between
    // (faithful_quotient, exact.hpp). One exact quotient per query instead of one exact
    // sign per slope the search asks.
    struct Vertex {
        double f;
        int side;  // sign(f - t*)
        int slope_sign(double g) const {  // sign(a g + b)
            if (side == 0) return (g > f) - (g < f);
            if (side > 0) return g >= f ? 1 : -1;  // t* in (prev(f), f)
            return g <= f ? -1 : 1;                // t* in (f, next(f))
        }
    };
    Vertex vertex(bool fixed = true) const {
        if (fixed)
            if (const std::optional<SphereFixedInput>& e = fixed_sums())
                if (const std::optional<std::pair<double, int>> v = e->vertex()) return Vertex{v->first, v->second};
        const Values v = given();
        return *with_exact(safe(), [&](auto tag) -> std::optional<Vertex> {
            using E = typename decltype(tag)::type;
            const E num = -eb<E>(v), den = ea<E>(v);
            if (any_overflowed(num, den)) return std::nullopt;
            const double f = faithful_quotient<double>(num, den);
            return Vertex{f, -compare_quotient(num, den, f)};
        });
    }
    // Estimates of the two roots, ascending, from a, b, c' and D = b² - a c' computed
    // exactly and each rounded once (relative error < 2^-50), by the careful quadratic
    // (q = -(b + sign(b)·sqrt(D)), roots q/a and c'/q: no cancellation), on the rescaled
    // input where the given one is not safe for expansions. A start for the search
    // where the intervals' roots are wide (near a tangent D is tiny and its interval
    // holds 0); the search proves every float it answers, so an estimate only saves
    // steps. NaN where D < 0; a root beyond the double range is ±inf, one below it ±0
    // (a, b, c' and D themselves may lie outside it: sphere_root_estimates).
    std::pair<double, double> root_estimates() const {
        constexpr double nan = std::numeric_limits<double>::quiet_NaN();
        const std::optional<Values>& scaled = safe() ? std::optional<Values>() : rescaled();
        const Values v = scaled ? *scaled : given();
        const std::pair<double, double> r =
            *with_exact(safe() || scaled.has_value(), [&](auto tag) -> std::optional<std::pair<double, double>> {
                using E = typename decltype(tag)::type;
                const E a = ea<E>(v), b = eb<E>(v), c = ec<E>(v);
                const E D = b * b - a * c;
                if (any_overflowed(a, b, c, D)) return std::nullopt;
                if (D.sign() < 0) return std::pair{nan, nan};
                return sphere_root_estimates(a.approx(), b.approx(), c.approx(), D.approx());
            });
        const int back = scaled ? -scaled->shift : 0;
        return {std::ldexp(r.first, back), std::ldexp(r.second, back)};
    }
    int sign_discriminant(bool rescale = true) const {  // sign(b² - a c')
        if (rescale) {
            if (disc_sign_ != 2) return disc_sign_;
            if (const std::optional<SphereFixedInput>& e = fixed_sums())
                if (const std::optional<int> s = e->sign_discriminant()) return *s;
        }
        return sign_of(rescale, 0.0, [](const Values& v, double, auto tag) {
            using E = typename decltype(tag)::type;
            const E b = eb<E>(v);
            return b * b - ea<E>(v) * ec<E>(v);
        });
    }

private:
    // The input in double, as given or rescaled (t's scale in shift: sp - sd).
    using Values = SphereValues;
    Values given() const { return sphere_given_values(*r_, *s_); }
    // The fixed-size sums (sphere_fixed_input) on the given or rescaled input; made on
    // first use, once for the discriminant's sign and the vertex.
    const std::optional<SphereFixedInput>& fixed_sums() const {
        if (!fixed_made_) {
            fixed_made_ = true;
            fixed_ = sphere_fixed_input(*r_, *s_, [&]() -> const std::optional<Values>& { return rescaled(); });
        }
        return fixed_;
    }
    // The rescaled input where the positions and the directions each span at most 199
    // binades; made on first use.
    const std::optional<Values>& rescaled() const {
        if (!rescaled_made_) {
            rescaled_made_ = true;
            rescaled_ = sphere_rescaled_values(*r_, *s_);
        }
        return rescaled_;
    }
    // The exact sign of value(values, t, tag): on the rescaled input where the given one
    // is not safe and t scales exactly, else on the given one.
    template <class F> int sign_of(bool rescale, double t, F&& value) const {
        if (rescale && !safe())
            if (const std::optional<Values>& v = rescaled()) {
                double u;
                if (scale_exactly(t, v->shift, u))
                    return detail::exact_sign(true, [&](auto tag) { return value(*v, u, tag); });
            }
        const Values v = given();
        return detail::exact_sign(safe(), [&](auto tag) { return value(v, t, tag); });
    }
    template <class E> static E ea(const Values& v) {
        E s(0.0);
        for (int j = 0; j < 3; ++j) s = s + E(v.d[j]) * E(v.d[j]);
        return s;
    }
    template <class E> static E eb(const Values& v) {
        E s(0.0);
        for (int j = 0; j < 3; ++j) s = s + E(v.d[j]) * (E(v.o[j]) - E(v.c[j]));
        return s;
    }
    template <class E> static E ec(const Values& v) {  // c' = |o - c|² - r²
        E s(0.0);
        for (int j = 0; j < 3; ++j) {
            const E dj = E(v.o[j]) - E(v.c[j]);
            s = s + dj * dj;
        }
        const E rad(v.r);
        return s - rad * rad;
    }
    bool safe() const {
        return expansion_safe(r_->origin) && expansion_safe(r_->direction) && expansion_safe(s_->center) &&
               expansion_safe(s_->radius);
    }
    const Ray<T>* r_;
    const Sphere<T>* s_;
    I delta_[3], a_, b_, c_, r2_;  // r2_: the radius squared
    mutable bool rescaled_made_ = false;
    mutable std::optional<Values> rescaled_;
    mutable bool fixed_made_ = false;
    mutable std::optional<SphereFixedInput> fixed_;
    int disc_sign_;
};

}  // namespace rayproof::detail
