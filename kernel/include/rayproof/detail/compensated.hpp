// rayproof/detail/compensated.hpp — the faithful rounding of a quotient t = N/D of two
// short sums of products of doubles, in double-word arithmetic with proven error bounds.
// It sits between the interval filter, whose enclosures of t are a few ulps wide (too
// wide to pin a faithful rounding), and exact arithmetic (detail/exact.hpp): it answers
// when its bounds decide, and otherwise says so, never a guess.
//
// Sums (CompensatedSum): Sum2 of Ogita, Rump and Oishi ("Accurate sum and dot product",
// SIAM J. Sci. Comput. 26(6), 2005, Algorithm 4.4 without its last addition). Every term
// p_1..p_n is a double held exactly (an input, or either half of an exact two_prod); s
// accumulates them with two_sum, whose errors q_i are exact, and c = fl(Σ q_i). Then
// N = s + Σ q_i exactly, Σ|q_i| <= gamma(n-1)·Σ|p_i| (ibid., proof of Proposition 4.5)
// and |c - Σ q_i| <= gamma(n-2)·Σ|q_i| (recursive summation), so
//     |s + c - N| <= gamma(n-1)·gamma(n-2)·A <= gamma(n)²·A,   A = Σ|p_i|.
// bound() returns 2·gamma(n)²·fl(A) + 2^-1020: fl(A) >= A·(1 - gamma(n)), and doubling
// covers that and the three roundings of the product; 2^-1020 covers their underflow
// (at most 2^-1075 each). Exact while nothing overflows (guarded: fl(A) <= 2^1000, so
// every partial sum is far below 2^1022 and each two_sum is exact) and every product's
// error term is representable (guarded: |fl(x·y)| >= 2^-916 or a factor is 0; see
// two_prod). A sum that fails a guard is not ok() and the caller goes exact.
//
// Quotient (compensated_faithful_quotient): a candidate c from one correction of
// s_N/s_D; then t lies strictly between the neighbours c- and c+ of c (so c is one of
// the two doubles enclosing t, and t itself when t is a double) iff N - g·D has the
// sign of D at g = c- and the opposite sign at g = c+. Each sign comes from
// residual_sign, with its own bound (derivation there); an undecided sign, or a guard
// that fails, returns nothing.
#pragma once

#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/interval.hpp>

#include <cmath>
#include <optional>

namespace rayproof::detail {

class CompensatedSum {
public:
    void add(double x) {
        const Pair p = two_sum(s_, x);
        s_ = p.hi;
        c_ += p.lo;
        a_ += std::abs(x);
        ++n_;
    }
    // x·y, both halves of the exact product.
    void add_product(double x, double y) {
        const Pair p = two_prod(x, y);
        exact_ &= int(std::abs(p.hi) >= exact_impl::kMinExactProduct) | int(x == 0) | int(y == 0);
        add(p.hi);
        add(p.lo);
    }
    double hi() const { return s_; }
    double lo() const { return c_; }
    // Every two_sum and two_prod was exact (NaN and ±inf fail the comparison).
    bool ok() const { return exact_ && a_ <= 0x1p1000; }
    // |hi + lo - exact sum| <= bound() (see the header comment).
    double bound() const {
        const double g = exact_impl::gamma(n_);
        return 2 * (g * g * a_) + 0x1p-1020;
    }

private:
    double s_ = 0, c_ = 0, a_ = 0;
    int n_ = 0;
    bool exact_ = true;
};

// sign(N - g·D) for N in [hi_N + lo_N ± bn], D in [hi_D + lo_D ± bd]: 1, -1, or 2 when the
// bound cannot decide (or a guard fails).
// With (p, p') = two_prod(g, hi_D) exact and (a, a') = two_sum(hi_N, -p) exact,
//     N - g·D = a + a' - p' + lo_N - g·lo_D + δ,   |δ| <= bn + |g|·bd.
// r = fl(a + fl(fl(fl(a' - p') + lo_N) - e)), e = fl(g·lo_D): recursive summation of five
// terms is off by at most gamma(4)·(|a| + |a'| + |p'| + |lo_N| + |e|) (Higham, ASNA, 4.2),
// and |e - g·lo_D| <= u|e|/(1 - u) + 2^-1075. The threshold doubles the sum of these
// bounds (covering the relative error gamma(12) of its own evaluation) and adds 2^-1020
// (the underflow of its products).
inline int residual_sign(const CompensatedSum& N, const CompensatedSum& D, double bn, double bd, double g) {
    using exact_impl::gamma;
    const Pair p = two_prod(g, D.hi());
    const double e = g * D.lo();
    const Pair a = two_sum(N.hi(), -p.hi);
    const double r = a.hi + (((a.lo - p.lo) + N.lo()) - e);
    const double ag = std::abs(g), ae = std::abs(e);
    const double bound = bn + ag * bd + exact_impl::u * ae +
                         gamma(4) * (std::abs(a.hi) + std::abs(a.lo) + std::abs(p.lo) + std::abs(N.lo()) + ae);
    const double threshold = 2 * bound + 0x1p-1020;
    // two_prod exact (g == 0 gives an exact 0), two_sum far from overflow.
    const bool exact = (int(std::abs(p.hi) >= exact_impl::kMinExactProduct) | int(g == 0)) & int(std::abs(p.hi) <= 0x1p1000);
    if (!exact || !(threshold <= 0x1p1000)) return 2;
    if (r > threshold) return 1;
    if (r < -threshold) return -1;
    return 2;
}

// N/D faithfully rounded to double, given dsign = sign(D) (exact, nonzero), or nothing.
inline std::optional<double> compensated_faithful_quotient(const CompensatedSum& N, const CompensatedSum& D, int dsign) {
    if (!N.ok() || !D.ok() || D.hi() == 0) return std::nullopt;
    // Any candidate may be tried; this one is within about half an ulp of t.
    const double c0 = N.hi() / D.hi();
    const Pair p = two_prod(c0, D.hi());
    const double c = c0 + (((N.hi() - p.hi) - p.lo) + N.lo() - c0 * D.lo()) / D.hi();
    if (!std::isfinite(c)) return std::nullopt;
    const double bn = N.bound(), bd = D.bound();
    if (residual_sign(N, D, bn, bd, step_down(c)) != dsign) return std::nullopt;
    if (residual_sign(N, D, bn, bd, step_up(c)) != -dsign) return std::nullopt;
    return c;
}

}  // namespace rayproof::detail
