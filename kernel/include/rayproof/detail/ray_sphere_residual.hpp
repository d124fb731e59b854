// rayproof/detail/ray_sphere_residual.hpp — the sphere's double-word residual:
// q(t) = |(o - c) + t d|² - r² at a double t with a proven error bound (SphereResidual),
// for the certified Ray/Sphere query (ray_sphere.hpp): the general path's second filter
// and the straight-line path's proofs.
#pragma once

#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/lanes.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/types.hpp>

#include <array>
#include <cstddef>
#include <cmath>
#include <limits>
#include <type_traits>

namespace rayproof::detail {

template <class T> std::array<double, 3> double3(const Vec3<T>& v) { return {double(v[0]), double(v[1]), double(v[2])}; }

// q(t) = |(o - c) + t d|² - r² at a double t in double-word arithmetic with a proven
// bound (value_at), and its sign when the bound decides (sign_at: 1, -1, or 2; a zero
// is never decided). With the exact splittings (two_sum, two_prod; Higham, ASNA, 4.3):
//   o_j - c_j = s_j + e_j,  t·d_j = P_j + p_j,  s_j + P_j = W_j + y_j,
//   ω_j = fl(fl(y_j + e_j) + p_j),  w_j = W_j + ω_j + ε_j,  |ε_j| <= β*_j = gamma(2)·B_j + 2^-1075,
//   B_j = |y_j| + |e_j| + |p_j| (two_prod's fused lo is off by at most 2^-1075 when subnormal),
//   w_j² = W_j² + 2 W_j ω_j + ω_j² + ε_j (2 W_j + 2 ω_j + ε_j),  the last term <= F*_j = β*_j (X_j + β*_j),
//   X_j = 2|W_j| + 2|ω_j|;
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
// term, m_0, sets the 7); v = fl(σ + L). Round to nearest (the kernel's environment,
// detail/fp_env.hpp) gives |x - fl(x)| <= u|fl(x)| for every sum (Higham, ASNA, (2.5)),
// so |σ + L - v| <= u|v|. Hence
//   |q(t) - v| <= gamma(7)·S + Σ_j F*_j + u|v|,  S = Σ|τ|.
// The bound is computed in floating point, round to nearest, every operand >= 0: each
// rounding is fl(x) >= (1 - u)x - η (η <= 2^-1075, products only), and a term that
// passes k roundings is at least (1 - u)^k times its exact value, less its η's. The
// computed constants: g_n = fl(n·u / (1 - n·u)) >= (1 - u)·gamma(n) (n·u and 1 - n·u
// exact; one division). Counting per quantity (a hat is the computed value):
//   Ŝ = abs_small, the 13 |τ_i| by value_at's tree, 6 additions deep:    S <= (1 - u)^-6 Ŝ
//   fl(g_7·Ŝ): g_7, the product:                   gamma(7)·S <= (1 - u)^-8 (fl(g_7·Ŝ) + η)
//   B̂_j: 2 additions; fl(g_2·B̂_j): g_2, the product; + 2^-1022: 1 addition, and
//     (1 - u)(2^-1022 - η) >= 2^-1075:                                  β*_j <= (1 - u)^-5 β̂_j
//   F*_j <= (1 - u)^-10 β̂_j (X_j + β̂_j); X̂_j: 1 addition (2|W_j|, 2|ω_j| exact), + β̂_j: 1,
//     the product: 1:                                                   F*_j <= (1 - u)^-13 (F̂_j + η)
//   F̂ = F̂_0 + F̂_1 + F̂_2: 2 additions:                       Σ F*_j <= (1 - u)^-15 F̂ + 3η(1 - u)^-13
//   Ê = fl(fl(g_7·Ŝ) + F̂): 1 addition:                   gamma(7)·S + Σ F*_j <= (1 - u)^-16 Ê + 4η'
//   T̂ = fl(Ê + fl(u·|v|)): 1 addition (u·|v| exact but for its η):  the bound <= (1 - u)^-17 T̂ + 5η'
//   err = fl(fl(c·T̂) + 2^-1000): the product, 1 addition:  err >= (1 - u)^2 c T̂ + (1 - u)2^-1000 - η
// (η' = (1 - u)^-13 2^-1075). So err bounds |q(t) - v| when (1 - u)^2 c >= (1 - u)^-17,
// i.e. c >= (1 - u)^-19, which 1 + gamma(19) is (Higham, ASNA, Lemma 3.1), and when
// 2^-1000 covers the η's (here six; with those of the small terms below, well under 2^-1060).
// c = fl(1 + g_20) = 1 + 20u exactly (static_assert), and 1 + 20u >= 1 + gamma(19)
// (gamma(19) = 19u/(1 - 19u) < 20u). Hence err = (1 + 20u)(gamma(7)·Σ|τ| + Σ F*_j + u|v|)
// + 2^-1000 up to its own roundings, every one of them counted above.
// Underflow: a two_prod whose error term is subnormal may round it by up to 2^-1075; β
// carries 2^-1022 for p_j (above), and 2^-1000 covers a_j, ρ and the small products.
// The 2^-1022 is the least normal double, not the 2^-1075 that suffices: a subnormal
// addend that the compiler fuses with g_2·B̂_j into one fma (class C1, -mfma) costs a
// microcode assist of about a hundred cycles on x86, three per value_at, which doubled
// the certified sphere's time on uniform double input in such builds.
// Exact while nothing overflows: the two_sum cascade is guarded by
// A_0 + A_1 + A_2 + R <= 2^1000; any other overflow leaves an infinite or NaN err, which
// decides nothing.
// Contraction (detail/eft.hpp): the splittings are two_prod and two_sum, whose products
// are rounded() (class C3), so every W_j, A_j, σ and x_k is as derived; ω_j, the small
// products 2W_jω_j and ω_j², their sums and the bound are class C1 (a fused product in
// L or in err is that product with rounding error 0; in L its d is one less, and
// gamma(d - 1)(1 + u) <= gamma(d) covers its exact |p| <= (1 + u)|fl(p)| in Σ|τ|; in Ŝ
// and in err every operand is >= 0, so an unrounded product only raises the bound, and
// the count above, with fewer roundings, still holds).
// Two points side by side (value_at on lanes::D2, lane 0 and lane 1): the same operations
// in each lane, with lanes::exact_product for two_prod. Both are exact under
// exact_product's conditions (detail/lanes.hpp: factors of magnitude at most 2^995, not
// subnormal, a nonzero product at least 2^-916), and then each lane computes the scalar
// value_at's bits. The caller keeps every d_j 0 or of magnitude in [2^-300, 2^300] (the
// certified straight-line path's range); a lane whose t is not 0 or in [2^-600, 2^620],
// or one of whose W_j is not 0 or in [2^-450, 2^450], gets err = +inf (it decides
// nothing): otherwise every nonzero product t·d_j and W_j² lies in [2^-900, 2^920]. The
// overflow guard is the same comparison, per lane.
class SphereResidual {
public:
    SphereResidual(const std::array<double, 3>& o, const std::array<double, 3>& d, const std::array<double, 3>& c,
                   double radius)
        : d_(d), r2_(two_prod(radius, radius)) {
        for (std::size_t j = 0; j < 3; ++j) oc_[j] = two_sum(o[j], -c[j]);
    }
    template <class V> struct ValueOf {
        V v, err;  // |q(t) - v| <= err; err = +inf when a guard fails
    };
    using Value = ValueOf<double>;
    Value value_at(double t) const { return value_of(t); }
    // Two points at once, lane by lane (see the class comment).
    RAYPROOF_ALWAYS_INLINE ValueOf<lanes::D2> value_at(lanes::D2 t) const { return value_of(t); }
    int sign_at(double t) const {
        const Value q = value_at(t);
        if (q.v > q.err) return 1;
        if (q.v < -q.err) return -1;
        return 2;
    }

private:
    template <class V> RAYPROOF_ALWAYS_INLINE ValueOf<V> value_of(V t) const {
        using std::abs;
        using lanes::abs;
        constexpr bool paired = std::is_same_v<V, lanes::D2>;
        const auto k = [](double x) {
            if constexpr (paired)
                return lanes::splat(x);
            else
                return x;
        };
        const auto product = [](V a, V b) {
            if constexpr (paired)
                return lanes::exact_product(a, b);
            else
                return two_prod(a, b);
        };
        constexpr double g2 = gamma<double>(2), g7 = gamma<double>(7), u = unit_roundoff<double>;
        constexpr double c = 1 + gamma<double>(20);  // >= 1 + gamma(19) >= (1 - u)^-19: see above
        static_assert(c == 1 + 20 * u);
        V W[3], om[3], A[3], small = k(-r2_.lo), abs_small = k(std::abs(r2_.lo)), F = k(0.0);
        [[maybe_unused]] lanes::M2 exact;
        if constexpr (paired) exact = lanes::in_band(t, k(0x1p-600), k(0x1p620));
        for (std::size_t j = 0; j < 3; ++j) {
            const SumOf<V> p = product(t, k(d_[j]));
            const SumOf<V> x = two_sum(k(oc_[j].hi), p.hi);
            W[j] = x.hi;
            om[j] = (x.lo + k(oc_[j].lo)) + p.lo;
            const V beta = k(g2) * ((abs(x.lo) + k(std::abs(oc_[j].lo))) + abs(p.lo)) + k(0x1p-1022);
            F = F + beta * ((k(2.0) * abs(W[j]) + k(2.0) * abs(om[j])) + beta);
            if constexpr (paired) exact = exact & lanes::in_band(W[j], k(0x1p-450), k(0x1p450));
            const SumOf<V> sq = product(W[j], W[j]);
            A[j] = sq.hi;
            const V m = k(2.0) * W[j] * om[j], kk = om[j] * om[j];
            small = small + ((sq.lo + m) + kk);
            abs_small = abs_small + ((abs(sq.lo) + abs(m)) + kk);
        }
        const V top = ((A[0] + A[1]) + A[2]) + k(r2_.hi);
        if constexpr (!paired)
            if (!(top <= 0x1p1000)) return {0, std::numeric_limits<double>::infinity()};
        const SumOf<V> s1 = two_sum(A[0], A[1]);
        const SumOf<V> s2 = two_sum(s1.hi, A[2]);
        const SumOf<V> s3 = two_sum(s2.hi, -k(r2_.hi));
        small = small + ((s1.lo + s2.lo) + s3.lo);
        abs_small = abs_small + ((abs(s1.lo) + abs(s2.lo)) + abs(s3.lo));
        const V v = s3.hi + small;
        const V err = k(c) * ((k(g7) * abs_small + F) + k(u) * abs(v)) + k(0x1p-1000);
        if constexpr (paired)
            return {v, lanes::select(exact & (top <= k(0x1p1000)), err, k(std::numeric_limits<double>::infinity()))};
        else
            return {v, err};
    }
    Pair oc_[3];
    std::array<double, 3> d_;
    Pair r2_;
};

}  // namespace rayproof::detail
