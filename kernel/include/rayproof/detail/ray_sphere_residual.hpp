// rayproof/detail/ray_sphere_residual.hpp — the sphere's double-word residual:
// q(t) = |(o - c) + t d|² - r² at a double t with a proven error bound (SphereResidual),
// for the certified Ray/Sphere query (ray_sphere.hpp): the general path's second filter
// and the straight-line path's proofs.
#pragma once

#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/types.hpp>

#include <array>
#include <cstddef>
#include <cmath>
#include <limits>

namespace rayproof::detail {

template <class T> std::array<double, 3> double3(const Vec3<T>& v) { return {double(v[0]), double(v[1]), double(v[2])}; }

// q(t) = |(o - c) + t d|² - r² at a double t in double-word arithmetic with a proven
// bound (value_at), and its sign when the bound decides (sign_at: 1, -1, or 2; a zero
// is never decided). With the exact splittings (two_sum, two_prod; Higham, ASNA, 4.3):
//   o_j - c_j = s_j + e_j,  t·d_j = P_j + p_j,  s_j + P_j = W_j + y_j,
//   ω_j = fl(fl(y_j + e_j) + p_j),  w_j = W_j + ω_j + ε_j,  |ε_j| <= β_j = gamma(2)(|y_j| + |e_j| + |p_j|),
//   w_j² = W_j² + 2 W_j ω_j + ω_j² + ε_j (2 W_j + 2 ω_j + ε_j),  the last term <= F_j = β_j (2|W_j| + 2|ω_j| + β_j);
//   W_j² = A_j + a_j and r² = R + ρ exactly, A_0 + A_1 + A_2 - R = σ + x_1 + x_2 + x_3 exactly
//   (a cascade of two_sum);
// the small terms τ = (x_1, x_2, x_3, a_j, fl(2 W_j ω_j), fl(ω_j²), -ρ), thirteen in all,
// are summed to L by the tree of value_at, t_j = fl(fl(a_j + m_j) + k_j) (m_j = fl(2 W_j ω_j),
// k_j = fl(ω_j²)), t_x = fl(fl(x_1 + x_2) + x_3), small = fl(...fl(fl(-ρ + t_0) + t_1)... + t_x).
// A term that passes d roundings is off by at most gamma(d)·|τ_i| ((1 + u)^d - 1 <=
// gamma(d); Higham, ASNA, 3.1 and 4.2), a product's own rounding counted as one
// (|p - fl(p)| <= u|fl(p)|, and u + gamma(d) <= gamma(d + 1)); per term, d =
//   -ρ:     small + t_0, + t_1, + t_2, + t_x                                    4
//   a_j:    a_j + m_j, + k_j, small + t_j, the 2 - j later + t_i, + t_x          6 - j
//   m_j:    its product, then as a_j                                            7 - j
//   k_j:    its product, + k_j, small + t_j, the 2 - j later + t_i, + t_x        6 - j
//   x_1, x_2: x_1 + x_2, + x_3, small + t_x; x_3: + x_3, small + t_x             3, 2
// so L is within gamma(7)·Σ|τ| of the terms' exact sum (products unrounded; the deepest
// term, m_0, sets the 7); v = fl(σ + L). Hence
//   |q(t) - v| <= gamma(7)·Σ|τ| + Σ_j F_j + u|v|/(1 - u),
// and err = 2(gamma(7)·Σ|τ| + Σ F_j) + 2u|v| + 2^-1000 bounds it: the doubling covers
// the roundings of the bound itself. Underflow: a two_prod whose error term is
// subnormal may round it by up to 2^-1075; β_j carries 2^-1070 for p_j, and 2^-1000
// covers a_j, ρ and the small products. Exact while nothing overflows: the two_sum
// cascade is guarded by A_0 + A_1 + A_2 + R <= 2^1000; any other overflow leaves an
// infinite or NaN err, which decides nothing.
// Contraction (detail/eft.hpp): the splittings are two_prod and two_sum, whose products
// are rounded() (class C3), so every W_j, A_j, σ and x_k is as derived; ω_j, the small
// products 2W_jω_j and ω_j², their sums and the bound are class C1 (a fused product in
// L or in err is that product with rounding error 0; in L its d is one less, and
// gamma(d - 1)(1 + u) <= gamma(d) covers its exact |p| <= (1 + u)|fl(p)| in Σ|τ|).
class SphereResidual {
public:
    SphereResidual(const std::array<double, 3>& o, const std::array<double, 3>& d, const std::array<double, 3>& c,
                   double radius)
        : d_(d), r2_(two_prod(radius, radius)) {
        for (std::size_t j = 0; j < 3; ++j) oc_[j] = two_sum(o[j], -c[j]);
    }
    struct Value {
        double v, err;  // |q(t) - v| <= err; err = +inf when a guard fails
    };
    Value value_at(double t) const {
        constexpr double g2 = gamma<double>(2), g7 = gamma<double>(7), u = unit_roundoff<double>;
        double W[3], om[3], A[3], small = -r2_.lo, abs_small = std::abs(r2_.lo), F = 0;
        for (std::size_t j = 0; j < 3; ++j) {
            const Pair p = two_prod(t, d_[j]);
            const Pair x = two_sum(oc_[j].hi, p.hi);
            W[j] = x.hi;
            om[j] = (x.lo + oc_[j].lo) + p.lo;
            const double beta = g2 * (std::abs(x.lo) + std::abs(oc_[j].lo) + std::abs(p.lo)) + 0x1p-1070;
            F += beta * (2 * std::abs(W[j]) + 2 * std::abs(om[j]) + beta);
            const Pair sq = two_prod(W[j], W[j]);
            A[j] = sq.hi;
            const double m = 2 * W[j] * om[j], k = om[j] * om[j];
            small += (sq.lo + m) + k;
            abs_small += (std::abs(sq.lo) + std::abs(m)) + k;
        }
        if (!(A[0] + A[1] + A[2] + r2_.hi <= 0x1p1000)) return {0, std::numeric_limits<double>::infinity()};
        const Pair s1 = two_sum(A[0], A[1]);
        const Pair s2 = two_sum(s1.hi, A[2]);
        const Pair s3 = two_sum(s2.hi, -r2_.hi);
        small += (s1.lo + s2.lo) + s3.lo;
        abs_small += (std::abs(s1.lo) + std::abs(s2.lo)) + std::abs(s3.lo);
        const double v = s3.hi + small;
        return {v, 2 * (g7 * abs_small + F) + 2 * u * std::abs(v) + 0x1p-1000};
    }
    int sign_at(double t) const {
        const Value q = value_at(t);
        if (q.v > q.err) return 1;
        if (q.v < -q.err) return -1;
        return 2;
    }

private:
    Pair oc_[3];
    std::array<double, 3> d_;
    Pair r2_;
};

}  // namespace rayproof::detail
