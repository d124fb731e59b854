// rayproof/detail/ray_sphere_fixed_exact.hpp — the sphere's input as doubles, given or
// rescaled (SphereValues), and its exact discriminant sign and exact vertex in
// fixed-size sums of error-free products (GrowingSum, exact.hpp) instead of the
// expansion types (SphereFixedExact), for float input and for double input safe for
// expansions, as given or rescaled into that range: what an exact tangent costs, since
// the certified query asks both for every one (ray_sphere.hpp, sphere_tangent_shortcut;
// ray_sphere_general.hpp).
//
// Equations: with Δ = o - c, a = |d|², b = d·Δ, c' = |Δ|² - r², the discriminant
// b² - a c' equals a r² - |Δ × d|² (Lagrange's identity), and the vertex t* = -b/a has
// sign(g - t*) = sign(a g + b) for every g (a > 0).
// Rescaling (SphereQuadratic's exact signs take the same values): the positions o, c and
// the radius multiplied by 2^sp, the direction by 2^sd (each exact) multiply b² - a c'
// by 2^(2sp + 2sd) and t* by 2^(sp - sd) = 2^shift, signs unchanged.
// Exactness (the grain argument of expansion_safe, exact.hpp): every input is a multiple
// of 2^-149 below 2^128 (float), or 0 or in [2^-100, 2^100], a multiple of 2^-152
// (double, expansion_safe; a rescaled input always is). Δ_j = h_j + l_j exactly
// (two_sum), both multiples of the input's grain; d_j² and r² are each two doubles
// exactly (two_prod; for float one, exact in double), multiples of twice the grain;
// every product below is of two such multiples, its error term a multiple of 2^-608 at
// worst (the squares of the cross product's components), far above the 2^-1074
// two_prod needs (eft.hpp), and every magnitude is below 2^410, far below overflow. So
// every sum is exact, and only the fixed capacities can decline (`full`): then the
// caller takes the expansion types. The vertex's products g·d_j² with a double
// candidate g are checked (|g·d_j²| >= 2^-916 or 0, eft.hpp).
#pragma once

#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/types.hpp>

#include <cmath>
#include <optional>
#include <utility>

namespace rayproof::detail {

// The input in double, as given or rescaled; t's scale is 2^shift (0 as given).
struct SphereValues {
    double o[3], c[3], d[3], r;
    int shift;
};
template <class T> SphereValues sphere_given_values(const Ray<T>& ray, const Sphere<T>& s) {
    SphereValues v;
    for (int j = 0; j < 3; ++j) {
        v.o[j] = double(ray.origin[j]);
        v.c[j] = double(s.center[j]);
        v.d[j] = double(ray.direction[j]);
    }
    v.r = double(s.radius);
    v.shift = 0;
    return v;
}
// The input rescaled so that the positions (o, c, r) and the direction each lie in
// [2^-100, 2^100] (or are 0), where each group spans at most 199 binades (ExponentSpan).
template <class T> std::optional<SphereValues> sphere_rescaled_values(const Ray<T>& ray, const Sphere<T>& s) {
    ExponentSpan positions, directions;
    for (int j = 0; j < 3; ++j) {
        positions.add(double(ray.origin[j]));
        positions.add(double(s.center[j]));
        directions.add(double(ray.direction[j]));
    }
    positions.add(double(s.radius));
    const std::optional<int> sp = positions.safe_shift(), sd = directions.safe_shift();
    if (!sp || !sd) return std::nullopt;
    SphereValues v = sphere_given_values(ray, s);
    for (int j = 0; j < 3; ++j) {
        v.o[j] = times_pow2(v.o[j], *sp);
        v.c[j] = times_pow2(v.c[j], *sp);
        v.d[j] = times_pow2(v.d[j], *sd);
    }
    v.r = times_pow2(v.r, *sp);
    v.shift = *sp - *sd;
    return v;
}

class SphereFixedExact {
public:
    // floats: the values are floats widened (every float is in range, and its square is
    // exact in double).
    SphereFixedExact(const SphereValues& v, bool floats) : floats_(floats) {
        usable_ = floats || expansion_safe(v.r);
        for (int j = 0; j < 3; ++j) {
            usable_ = usable_ && (floats || (expansion_safe(v.o[j]) && expansion_safe(v.c[j]) && expansion_safe(v.d[j])));
            const Pair delta = two_sum(v.o[j], -v.c[j]);
            h_[j] = delta.hi;
            l_[j] = delta.lo;
            d_[j] = v.d[j];
            d2_[j] = square(d_[j]);
        }
        r2_ = square(v.r);
    }
    // Whether the input is in the range the derivation above covers.
    bool usable() const { return usable_; }

    // sign(b² - a c') = sign(a r² - |Δ × d|²), or none where the input is not usable() or
    // a capacity did not suffice.
    std::optional<int> sign_discriminant() const {
        if (!usable_) return std::nullopt;
        GrowingSum<48> D;
        for (int j = 0; j < 3; ++j)
            for (const double x : {r2_.hi, r2_.lo})
                for (const double y : {d2_[j].hi, d2_[j].lo}) D.add_product(x, y);
        for (int k = 0; k < 3; ++k) {
            // w = (Δ × d)_k = Δ_y d_z - Δ_z d_y for (y, z) the two axes after k
            const int y = (k + 1) % 3, z = (k + 2) % 3;
            GrowingSum<8> w;
            w.add_product(h_[y], d_[z]);
            w.add_product(l_[y], d_[z]);
            w.add_product(-h_[z], d_[y]);
            w.add_product(-l_[z], d_[y]);
            if (w.full) return std::nullopt;
            // -w² = -Σ_i w_i² - Σ_{i<j} 2 w_i w_j (2 w_i exact)
            for (int i = 0; i < w.n; ++i) {
                D.add_product(-w.e[i], w.e[i]);
                for (int j = i + 1; j < w.n; ++j) D.add_product(-2 * w.e[i], w.e[j]);
            }
        }
        if (D.full) return std::nullopt;
        return D.sign();
    }

    // The vertex t* = -b/a as a double f with sign(f - t*), where t* is f itself or lies
    // strictly between f and its neighbour on that side (as SphereQuadratic::Vertex):
    // from the estimate -b~/a~, stepped one double at a time (at most four steps) until
    // sign(a g + b) changes; none where the input is not usable() or a capacity or a
    // product's range did not suffice.
    std::optional<std::pair<double, int>> vertex() const {
        if (!usable_) return std::nullopt;
        GrowingSum<16> b;
        for (int j = 0; j < 3; ++j) {
            b.add_product(h_[j], d_[j]);
            b.add_product(l_[j], d_[j]);
        }
        GrowingSum<8> a;
        for (int j = 0; j < 3; ++j) {
            a.add(d2_[j].lo);
            a.add(d2_[j].hi);
        }
        if (b.full || a.full) return std::nullopt;
        // sign(a g + b), or 2 where a product g·a_i may be inexact or the sum too long
        const auto side = [&](double g) {
            GrowingSum<32> s;
            for (int i = 0; i < b.n; ++i) s.add(b.e[i]);
            for (int i = 0; i < a.n; ++i) {
                const double p = std::abs(g * a.e[i]);
                if (!(p == 0 || (p >= exact_impl::kMinExactProduct && p <= 0x1p1000))) return 2;
                s.add_product(g, a.e[i]);
            }
            return s.full ? 2 : s.sign();
        };
        double f = -b.estimate() / a.estimate();
        if (!std::isfinite(f)) return std::nullopt;
        int s = side(f);
        for (int step = 0; step < 4 && s != 2; ++step) {
            if (s == 0) return std::pair{f, 0};
            const double g = s > 0 ? step_down(f) : step_up(f);  // towards t*
            const int sg = side(g);
            if (sg == 2) return std::nullopt;
            if (sg != s) return sg == 0 ? std::pair{g, 0} : std::pair{f, s};  // t* in (g, f) or (f, g)
            f = g;
            s = sg;
        }
        return std::nullopt;
    }

private:
    Pair square(double x) const { return floats_ ? Pair{x * x, 0.0} : two_prod(x, x); }  // x² exactly
    double h_[3], l_[3], d_[3];
    Pair d2_[3], r2_;
    bool floats_, usable_;
};

// The fixed-size sums on the values they take: the input as given where it is in their
// range, else as rescaled; the one place that chooses, for the tangent shortcut
// (ray_sphere.hpp) and SphereQuadratic's exact signs.
struct SphereFixedInput {
    SphereFixedInput(const SphereValues& v, bool floats) : values(v), sums(v, floats) {}
    SphereValues values;  // the values taken (t's scale in values.shift)
    SphereFixedExact sums;
    std::optional<int> sign_discriminant() const { return sums.sign_discriminant(); }
    // The vertex as SphereFixedExact::vertex() answers it, scaled back to the given t: a
    // faithful f stays faithful (no double lies closer); none where it does not scale
    // back exactly.
    std::optional<std::pair<double, int>> vertex() const {
        const std::optional<std::pair<double, int>> v = sums.vertex();
        double f;
        if (!v || !scale_exactly(v->first, -values.shift, f)) return std::nullopt;
        return std::pair{f, v->second};
    }
};
// rescaled(): the rescaled input (sphere_rescaled_values), asked only where the given
// input is out of range (a caller that keeps it makes it once); none where neither
// input is in range.
template <class T, class Rescaled>
std::optional<SphereFixedInput> sphere_fixed_input(const Ray<T>& r, const Sphere<T>& s, Rescaled&& rescaled) {
    std::optional<SphereFixedInput> e(std::in_place, sphere_given_values(r, s), std::is_same_v<T, float>);
    if (!e->sums.usable()) {
        if (const std::optional<SphereValues>& w = rescaled())
            e.emplace(*w, false);
        else
            e.reset();
    }
    return e;
}

}  // namespace rayproof::detail
