// rayproof/detail/ray_sphere_straight_line.hpp — the straight-line path of the certified
// Ray/Sphere query (sphere_certified_common): the roots estimated in double as the fast
// mode does, each refined and proven, or a miss proven; anything it cannot prove is left
// to the general path (ray_sphere_general.hpp), whose answers it gives bit for bit.
#pragma once

#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/lanes.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/detail/ray_sphere_residual.hpp>
#include <rayproof/detail/ray_sphere_verdict.hpp>
#include <rayproof/detail/validate.hpp>
#include <rayproof/types.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <type_traits>
#include <utility>

namespace rayproof::detail {

// Signs of q(t) and of the slope a t + b at a finite t from one plain evaluation and a
// static bound (1, -1, or 2 when the bound cannot decide), with Δ~_j = fl(o_j - c_j):
//     w~_j = fl(Δ~_j + fl(t d_j)),  M_j = |Δ~_j| + |fl(t d_j)|,  |w~_j - w_j| <= gamma(2)·M_j
// (Δ~_j and fl(t d_j) are each within u/(1 - u) of their exact values, the sum one more
// rounding). Then |w~_j² - w_j²| <= |w~_j - w_j|·|w~_j + w_j| <= 2·gamma(2)(1 + gamma(3))·M_j²,
// and the sum of four rounded squares is off by gamma(4)·Σ terms (Higham, ASNA, 3.1):
//     |fl(Σ w~_j² - r²) - q(t)| <= gamma(9)·(Σ M_j² + r²).
// Likewise |fl(Σ d_j w~_j) - (a t + b)| <= (gamma(2) + gamma(3)(1 + u))·Σ|d_j| M_j <= gamma(6)·Σ|d_j| M_j.
// Each threshold is twice the bound evaluated in floating point (the doubling covers the
// few roundings of the bound itself) plus 2^-1000 for underflow (at most 2^-1075 per
// rounding, times at most 3·M_j where a square amplifies it, which for M_j >= 1 the
// relative bound absorbs). A threshold above 2^1000 (an overflow near) decides nothing.
// Contraction (detail/eft.hpp): every bound in this file is class C1 (fused, fl(Δ~_j +
// t d_j) and the sums of squares round fewer times than counted); the distance
// certificate and the sign checks of sign_near likewise; the Newton candidate g may
// differ when fused, but the answer does not: it is the float where the proven signs
// change, whatever candidate leads there.
struct SphereCheapSigns {
    int q, slope;
};
struct SphereCheapPair {
    int pos, neg;
};
RAYPROOF_ALWAYS_INLINE SphereCheapSigns sphere_cheap_signs(const double (&delta)[3], const double (&d)[3], double rad,
                                                           double t) {
    constexpr double eta = 0x1p-1000, g9 = 2 * gamma<double>(9), g6 = 2 * gamma<double>(6);
    double v = -rad * rad, bq = rad * rad, sl = 0, bs = 0;
    for (int j = 0; j < 3; ++j) {
        const double p = t * d[j];
        const double w = delta[j] + p, m = std::abs(delta[j]) + std::abs(p);
        v += w * w;
        bq += m * m;
        sl += d[j] * w;
        bs += std::abs(d[j]) * m;
    }
    const double tq = g9 * bq + eta, ts = g6 * bs + eta;
    SphereCheapSigns out{2, 2};
    if (tq <= 0x1p1000) out.q = v > tq ? 1 : v < -tq ? -1 : 2;
    if (ts <= 0x1p1000) out.slope = sl > ts ? 1 : sl < -ts ? -1 : 2;
    return out;
}

// The straight-line path of the certified mode: the roots estimated as the fast mode
// does (in double), then proven. It answers a miss only when the line's distance from
// the centre certainly exceeds r, or the sphere certainly lies beyond an end of the
// range; a hit only with the signs of q at the estimates' floats and their neighbours
// proven (cheap bound, else double-word), which pins t_enter as the least float g with
// q(g) <= 0 after q(g-) > 0 (q convex: q decreases up to g, so every float below g is
// outside, as the general path's search predicate also says), and t_exit likewise from
// above. Anything else, nothing: the general path answers. Its answers are therefore the
// general path's, bit for bit.
// Distance certificate, with Δ~_j = fl(o_j - c_j), f = fl(b~/a~), P_j = fl(f d_j),
// m~_j = fl(Δ~_j - P_j), n = fl(sqrt(fl(Σ m~_j²))), exact Δ, a, b:
//   |m~_j - (Δ_j - f d_j)| <= gamma(2)(|Δ~_j| + |P_j|), so |Δ - f d| >= n(1 - gamma(3)) - gamma(2)·Σ(|Δ~_j| + |P_j|);
//   |b~ - b| <= gamma(4)·Σ|d_j Δ~_j| and |a~ - a| <= gamma(3)·a give |f - b/a| <= gamma(8)·Σ|d_j Δ~_j|/a~,
//   and by Cauchy-Schwarz ε² = a (f - b/a)² <= (gamma(9)·Σ|Δ~_j|)²;
//   the line's distance l satisfies l² = |Δ - f d|² - ε² >= (|Δ - f d| - ε)², so
//   l >= n - K, K = gamma(3)·n + gamma(2)·Σ(|Δ~_j| + |P_j|) + gamma(9)·Σ|Δ~_j| <= gamma(11)·(n + Σ|Δ~_j| + Σ|P_j|).
// A miss is answered when fl(n - r) > 2·fl(gamma(11)·(...)) + 2^-500: the doubling covers
// the roundings of both sides, 2^-500 the underflow of the squares under the square
// root (at most 3·2^-1075 inside, 2^-535 outside). Valid while every nonzero input
// magnitude (o, c, d, r) lies in [2^-300, 2^300]: then a, b, f and every product stay
// far from overflow and only the squares of m~ and the tiny products can underflow.
// The line o + t·d against the centre, in double, for the straight-line path: Δ~, a~,
// b~, n (the estimate of the line's distance from the centre) and the threshold of the
// distance certificate.
struct SphereLine {
    double d[3], delta[3];
    double rad, a, b, n, cc;
    double threshold;  // 2·fl(gamma(11)·(n + Σ|Δ~_j| + Σ|P_j|)) + 2^-500
    bool in_range;     // every nonzero input magnitude in [2^-300, 2^300]
};
// Written out per axis in locals: with the values stored to arrays in a loop, g++ -O2
// packed pairs of them into 16-byte loads of what had just been stored as 8-byte values,
// whose store forwarding fails; that stall took 26 of this routine's 33 ns.
template <class T> RAYPROOF_ALWAYS_INLINE SphereLine sphere_line(const Ray<T>& r, const Sphere<T>& s) {
    constexpr double g11 = 2 * gamma<double>(11), lo_mag = 0x1p-300, hi_mag = 0x1p300;
    SphereLine L;
    const double rad = double(s.radius);
    const double o0 = double(r.origin[0]), o1 = double(r.origin[1]), o2 = double(r.origin[2]);
    const double c0 = double(s.center[0]), c1 = double(s.center[1]), c2 = double(s.center[2]);
    const double d0 = double(r.direction[0]), d1 = double(r.direction[1]), d2 = double(r.direction[2]);
    const double e0 = o0 - c0, e1 = o1 - c1, e2 = o2 - c2;
    // The range test reads the inputs again from the ray and the sphere, in a loop, rather
    // than taking the locals above: a max/min tree over those locals measured slower
    // (misses 26 -> 52 ns, hits 169 -> 198, the branches of nonzero_abs in the tree).
    auto nonzero_abs = [](double v) { return v == 0 ? 1.0 : std::abs(v); };
    double largest = std::abs(rad), smallest = nonzero_abs(rad);
    for (int j = 0; j < 3; ++j) {
        const double o = double(r.origin[j]), c = double(s.center[j]), dj = double(r.direction[j]);
        largest = std::max(largest, std::max(std::max(std::abs(o), std::abs(c)), std::abs(dj)));
        smallest = std::min(smallest, std::min(std::min(nonzero_abs(o), nonzero_abs(c)), nonzero_abs(dj)));
    }
    L.in_range = largest <= hi_mag && smallest >= lo_mag;
    const double a = d0 * d0 + d1 * d1 + d2 * d2, b = d0 * e0 + d1 * e1 + d2 * e2;
    const double f = b / a;
    const double p0 = f * d0, p1 = f * d1, p2 = f * d2, m0 = e0 - p0, m1 = e1 - p1, m2 = e2 - p2;
    const double n2 = m0 * m0 + m1 * m1 + m2 * m2;
    L.cc = ((-rad * rad + e0 * e0) + e1 * e1) + e2 * e2;
    L.n = std::sqrt(n2);
    const double sum_dl = (std::abs(e0) + std::abs(e1)) + std::abs(e2), sum_p = (std::abs(p0) + std::abs(p1)) + std::abs(p2);
    L.threshold = g11 * (L.n + sum_dl + sum_p) + 0x1p-500;
    L.rad = rad, L.a = a, L.b = b;
    L.d[0] = d0, L.d[1] = d1, L.d[2] = d2;
    L.delta[0] = e0, L.delta[1] = e1, L.delta[2] = e2;
    return L;
}

// The float where q's proven sign changes, from a candidate g (+0 for -0) and the proven
// signs of q at g and at its neighbours g- and g+. t_enter, q decreasing through t0: g
// when q(g-) > 0 > q(g), g+ when q(g) > 0 > q(g+); q is convex, so every float below is
// outside and the slope negative there, and the general path's search predicate
// (a g + b >= 0 or q(g) <= 0) turns true exactly at that float. t_exit, q increasing
// through t1: g when q(g) < 0 < q(g+), g- when q(g-) < 0 < q(g). The answer does not
// depend on the candidate, only on the proven signs: any candidate that lands on the
// float or its neighbour gives the same float. Not ok (the general path answers) when
// the signs are not proven or the float leaves the range. Both straight-line paths pin
// with these two routines: the double path with every sign from paired evaluations, the
// float path with the sign at g+ (t_enter) or g- (t_exit) read only when g is not the
// answer.
template <class T> RAYPROOF_ALWAYS_INLINE T sphere_canonical(T x) { return x == 0 ? T(0) : x; }  // step_up(-min) is -0
struct PinSigns {  // each true only when proven
    bool at_pos, at_neg, below_pos, below_neg, above_pos, above_neg;
};
template <class T> RAYPROOF_ALWAYS_INLINE Pinned<T> sphere_pin_enter(const Ray<T>& r, T g, const PinSigns& s) {
    const bool on_g = s.at_neg && g <= r.t_max && s.below_pos;
    const bool on_up = s.at_pos && s.above_neg && step_up(g) <= r.t_max;
    return {on_g ? g : sphere_canonical(step_up(g)), std::isfinite(g) && g > r.t_min && (on_g || on_up)};
}
template <class T> RAYPROOF_ALWAYS_INLINE Pinned<T> sphere_pin_exit(const Ray<T>& r, T g, const PinSigns& s) {
    const bool on_g = s.at_neg && g >= r.t_min && s.above_pos;
    const bool on_down = s.at_pos && s.below_neg && step_down(g) >= r.t_min;
    return {on_g ? g : sphere_canonical(step_down(g)), std::isfinite(g) && g < r.t_max && (on_g || on_down)};
}

template <class T> RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> sphere_certified_common(const Ray<T>& r,
                                                                                          const Sphere<T>& s) {
    const SphereLine L = sphere_line(r, s);
    // The input vouched for (the certified query checks no validity before this path):
    // the threshold is finite only when every Δ~_j = fl(o_j - c_j) is (it sums their
    // magnitudes), hence o and c are finite (inf - x is infinite, inf - inf NaN), and
    // when d is (a non-finite d_j makes a non-finite or NaN, and f = b/a NaN, which the
    // sum of |f d_j| carries); c' = Δ~·Δ~ - r² is finite only with a finite radius; a > 0
    // means d nonzero; r >= 0 (false for NaN) and valid_range do the rest. What this
    // declines is validated in full (sphere_certified_answer).
    const double probe = L.threshold + L.cc;
    const bool input_ok = int(probe - probe == 0) & int(L.a > 0) & int(s.radius >= 0) & int(valid_range(r));
    if (!(L.in_range && input_ok)) return std::nullopt;
    const double(&d)[3] = L.d;
    const double(&delta)[3] = L.delta;
    const double rad = L.rad, a = L.a, b = L.b, n = L.n, cc = L.cc;
    Hit<T> h;
    if (!(n <= rad)) {  // the estimate says the line misses: prove it, or hand over
        if (n - rad > L.threshold) return h;
        return std::nullopt;
    }
    // The roots as the fast mode estimates them: q = -(b + sign(b)·sqrt(disc)), t = q/a, c'/q.
    const double disc = a * ((rad - n) * (rad + n));
    const double qq = -(b + std::copysign(std::sqrt(disc), b));
    double t0 = qq / a, t1 = cc / qq;
    if (t1 < t0) std::swap(t0, t1);
    if (!(std::isfinite(t0) && std::isfinite(t1))) return std::nullopt;

    // Signs at the ends of the range (q(±inf) = +1: it grows without bound).
    const bool min_inf = std::isinf(r.t_min), max_inf = std::isinf(r.t_max);
    const SphereCheapSigns at_min = min_inf ? SphereCheapSigns{1, -1} : sphere_cheap_signs(delta, d, rad, double(r.t_min));
    const SphereCheapSigns at_max = max_inf ? SphereCheapSigns{1, 1} : sphere_cheap_signs(delta, d, rad, double(r.t_max));
    const SphereResidual res(double3(r.origin), double3(r.direction), double3(s.center), rad);
    const int q_min = at_min.q != 2 ? at_min.q : res.sign_at(double(r.t_min));
    const int q_max = at_max.q != 2 ? at_max.q : res.sign_at(double(r.t_max));
    if (q_min == 2 || q_max == 2) return std::nullopt;
    // The sphere certainly behind t_min, or beyond t_max: outside there, moving away
    // (q is convex, so its slope only grows).
    if (q_min > 0 && at_min.slope == 1) return h;
    if (q_max > 0 && at_max.slope < 0) return h;

    // A root estimate x refined and proven: q(x) ≈ v in double-word arithmetic, one
    // Newton step x - v/(2(a x + b)) rounded to T gives the candidate g, and the sign of
    // q at g and at a neighbour y of g comes from the exact expansion of the quadratic,
    //     q(y) = q(x) + δ·σ,  δ = y - x (checked exact),  σ = a(2x + δ) + 2b,
    // evaluated as V = fl(v + fl(δ·σ~)), σ~ = fl(A~ + 2b~), A~ = fl(a~·fl(2x + δ)), with a
    // and b of the exact Δ = o - c. Every rounding counted (θ_k: some |θ_k| <= gamma(k);
    // the inputs' magnitudes in [2^-300, 2^300] keep d_j Δ~_j and the squares normal):
    //   fl(2x + δ) = (2x + δ)(1 + θ_1)                                   (2x is exact)
    //   a~ = Σ d_j²(1 + θ_3)                         (one product, at most two sums)
    //   A~ = a~·fl(2x + δ)(1 + θ_1) = a(2x + δ)(1 + θ_5)
    //   |A~ - a(2x + δ)| <= gamma(5)|a(2x + δ)| <= 5u/(1 - 10u)·|A~|
    //   b~ = Σ d_j Δ_j(1 + θ_4)              (Δ~_j = fl(o_j - c_j), product, two sums)
    //   C = fl(Σ|fl(d_j Δ~_j)|) >= (1 - u)^3·Σ|d_j Δ~_j| >= (1 - u)^4·Σ|d_j Δ_j|
    //   |b~ - b| <= gamma(4)·Σ|d_j Δ_j| <= gamma(4)/(1 - u)^4·C,  |b~| <= (1 + u)^2/(1 - u)^2·C
    //   σ~ = (A~ + 2b~)(1 + θ_1): |σ~ - σ| <= |A~ - a(2x + δ)| + 2|b~ - b| + u(|A~| + 2|b~|)
    //        <= (6u + O(u²))·|A~| + 2(5u + O(u²))·C <= gamma(7)·(|A~| + 2C) =: e_σ
    //   fl(δ·σ~) = δ·σ~(1 + θ_1)                 (off by at most u|δ σ~|, plus underflow)
    //   V = fl(v + fl(δ·σ~)), off by at most u|V|/(1 - u)       (|q(x) - v| <= err_v)
    //   |V - q(y)| <= B + u|V|/(1 - u),  B = err_v + |δ|·e_σ + u|δ σ~| (+ underflow)
    // The threshold is 2B as evaluated plus 2^-1000: its six roundings (gamma(7) itself,
    // the sum and the product of e_σ, the sum with u|σ~|, the product by |δ|, the sum with
    // err_v) leave it at least 2(1 - u)^6·B, so |V| above it gives
    //     B + u|V|/(1 - u) < |V|·(1/(2(1 - u)^6) + u/(1 - u)) < |V|:
    // V has the sign of q(y); the 2^-1000 covers the underflows. The factor 2 is the only
    // slack: e_σ is not doubled again, and the realized |σ~ - σ| can reach about
    // 5u|A~| + 8u·C + u|σ~| (every rounding above at its worst, aligned).
    constexpr double g7 = gamma<double>(7), u = unit_roundoff<double>;
    using namespace lanes;
    const double cab = std::abs(d[0] * delta[0]) + std::abs(d[1] * delta[1]) + std::abs(d[2] * delta[2]);
    // Both roots side by side: lane 0 refines and proves the entry root's estimate t0,
    // lane 1 the exit root's t1, each lane the scalar formulas above (value_at on D2,
    // ray_sphere_residual.hpp).
    const D2 x = make(t0, t1);
    const SphereResidual::ValueOf<D2> qx = res.value_at(x);
    const D2 gx = x - qx.v / ((splat(a) * x + splat(b)) * splat(2.0));
    const T g0 = sphere_canonical(narrow<T>(lane0(gx))), g1 = sphere_canonical(narrow<T>(lane1(gx)));
    // The signs of q at y (lane 0 next to t0, lane 1 next to t1): bit k of pos (neg) set
    // when q(y_k) is proven > 0 (< 0).
    const D2 va = splat(a), vb2 = splat(2 * b), vcab2 = splat(2 * cab);
    auto sign_near = [&](T y0, T y1) RAYPROOF_INLINE_LAMBDA {
        const SumOf<D2> dd = two_sum(make(double(y0), double(y1)), -x);
        const D2 del = dd.hi;
        const D2 ax = va * (x * splat(2.0) + del), sig = ax + vb2;
        const D2 e_sig = splat(g7) * (abs(ax) + vcab2);
        const D2 V = qx.v + del * sig;
        const D2 thr = splat(2.0) * (qx.err + abs(del) * (e_sig + splat(u) * abs(sig))) + splat(0x1p-1000);
        const M2 usable = (dd.lo == splat(0.0)) & (thr <= splat(0x1p1000));
        return SphereCheapPair{bits(usable & (V > thr)), bits(usable & (V < -thr))};
    };
    const SphereCheapPair at = sign_near(g0, g1), inner = sign_near(step_down(g0), step_up(g1)),
                          outer = sign_near(step_up(g0), step_down(g1));
    // The signs at g's neighbours on both sides are computed whichever the pins read:
    // which side of the root g lands on is a coin toss, and a branch on it cost more than
    // the third evaluation.
    const auto lane = [](int bitsk, int k) { return bool(bitsk & k); };
    const Pinned<T> e = sphere_pin_enter(r, g0,
                                         PinSigns{lane(at.pos, 1), lane(at.neg, 1), lane(inner.pos, 1),
                                                  lane(inner.neg, 1), lane(outer.pos, 1), lane(outer.neg, 1)});
    const Pinned<T> xp = sphere_pin_exit(r, g1,
                                         PinSigns{lane(at.pos, 2), lane(at.neg, 2), lane(outer.pos, 2),
                                                  lane(outer.neg, 2), lane(inner.pos, 2), lane(inner.neg, 2)});
    if (!(int(q_min <= 0 || e.ok) & int(q_max <= 0 || xp.ok))) return std::nullopt;
    const T t_enter = q_min <= 0 ? r.t_min : e.t;
    const T t_exit = q_max <= 0 ? r.t_max : xp.t;
    h.verdict = Verdict::hit;
    h.t_enter = t_enter > t_exit ? t_exit : t_enter;
    h.t_exit = t_exit;
    return h;
}

// sphere_cheap_signs's q at two points at once (lane 0: y0, lane 1: y1), the same
// operations and the same bound in each lane; bit k of pos (neg) set when q(y_k) is
// certainly > 0 (< 0). A threshold above 2^1000 decides nothing, as there.
RAYPROOF_ALWAYS_INLINE SphereCheapPair sphere_cheap_q2(const double (&delta)[3], const double (&d)[3], double rad,
                                                       double y0, double y1) {
    using namespace lanes;
    constexpr double eta = 0x1p-1000, g9 = 2 * gamma<double>(9);
    const D2 t = make(y0, y1);
    D2 v = splat(-rad * rad), bq = splat(rad * rad);
    RAYPROOF_UNROLL3
    for (int j = 0; j < 3; ++j) {
        const D2 P = t * splat(d[j]), W = splat(delta[j]) + P, M = splat(std::abs(delta[j])) + abs(P);
        v = v + W * W;
        bq = bq + M * M;
    }
    const D2 tq = bq * splat(g9) + splat(eta);
    const M2 usable = tq <= splat(0x1p1000);
    return {bits(usable & (v > tq)), bits(usable & (v < -tq))};
}

// The float straight-line path, in front of sphere_certified_common for T = float: no
// double-word arithmetic at all. The roots are estimated in double as above and rounded
// to float (no Newton step), and every sign comes from sphere_cheap_signs, the plain
// evaluation in double with its gamma(9) bound, at a float y. For float input that bound
// decides the signs the answer needs: near the root t0 a float step moves q by about
// 2|a t0 + b|·2^-24|t0|, while the bound is about 2^-49·(Σ M_j² + r²), so only a ray
// within about 2^-25 (relative) of tangency, or a root within about 2^-25 of a float's
// step from a float, is left undecided, and goes to sphere_cheap_signs's double-word
// sibling (sphere_certified_common), then to the general path. Every answer rests on
// proven signs only: a miss on the line's distance (below) or on the signs at an end of
// the range, as sphere_certified_common; a hit on the end signs and on the float where
// the proven sign of q changes (sphere_pin_enter / sphere_pin_exit, with the signs at
// the float on the estimate's side of the root and its neighbour across it from one
// paired evaluation, sphere_cheap_q2), which is the general
// path's search answer whatever the candidate; so the answer is the general path's bit
// for bit.
// The miss on the line's distance comes from the verdict filter's certificate
// (sphere_line_certificate, ray_sphere_verdict.hpp: no division, no square root), valid
// when a~ >= 2^-1000, which every valid float direction gives (a nonzero float component
// is at least 2^-149, its square 2^-298, exact in double); and float input cannot
// overflow it (every magnitude below 2^128, every product of four below 2^520). The
// root estimates reuse its D (-D ≈ b² - a c'): qq = -(b + sign(b)·sqrt(-D)), t0 = qq/a,
// t1 = c'/qq; they need no proof (a NaN or infinite one declines), the signs decide.
// The float path's inputs in double: d exact, Δ~_j = fl(o_j - c_j), r exact.
struct SphereFloatLine {
    double d[3], delta[3], rad;
};
template <class T> RAYPROOF_ALWAYS_INLINE SphereFloatLine sphere_float_line(const Ray<T>& r, const Sphere<T>& s) {
    SphereFloatLine L;
    L.rad = double(s.radius);
    for (int j = 0; j < 3; ++j) {
        L.d[j] = double(r.direction[j]);
        L.delta[j] = double(r.origin[j]) - double(s.center[j]);
    }
    return L;
}
// t_enter from a candidate g (q(t_min) > 0 proven): the signs at g- and g from one
// paired evaluation, the sign at g+ only when they do not make g the answer. Any
// candidate gives the general path's t_enter or not ok.
template <class T> RAYPROOF_ALWAYS_INLINE Pinned<T> sphere_float_pin_enter(const Ray<T>& r, const SphereFloatLine& L,
                                                                           T g) {
    const SphereCheapPair p = sphere_cheap_q2(L.delta, L.d, L.rad, double(step_down(g)), double(g));
    PinSigns s{bool(p.pos & 2), bool(p.neg & 2), bool(p.pos & 1), bool(p.neg & 1), false, false};
    if (!(s.at_neg && s.below_pos)) [[unlikely]] {
        const int above = sphere_cheap_signs(L.delta, L.d, L.rad, double(step_up(g))).q;
        s.above_pos = above == 1, s.above_neg = above == -1;
    }
    return sphere_pin_enter(r, g, s);
}
// t_exit likewise (q(t_max) > 0 proven): the signs at g and g+ paired, at g- when needed.
template <class T> RAYPROOF_ALWAYS_INLINE Pinned<T> sphere_float_pin_exit(const Ray<T>& r, const SphereFloatLine& L,
                                                                          T g) {
    const SphereCheapPair p = sphere_cheap_q2(L.delta, L.d, L.rad, double(g), double(step_up(g)));
    PinSigns s{bool(p.pos & 1), bool(p.neg & 1), false, false, bool(p.pos & 2), bool(p.neg & 2)};
    if (!(s.at_neg && s.above_pos)) [[unlikely]] {
        const int below = sphere_cheap_signs(L.delta, L.d, L.rad, double(step_down(g))).q;
        s.below_pos = below == 1, s.below_neg = below == -1;
    }
    return sphere_pin_exit(r, g, s);
}

template <class T> RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> sphere_certified_float(const Ray<T>& r,
                                                                                         const Sphere<T>& s) {
    static_assert(std::is_same_v<T, float>);
    const SphereFloatLine L = sphere_float_line(r, s);
    const double(&d)[3] = L.d;
    const double(&delta)[3] = L.delta;
    const double rad = L.rad, rr = rad * rad;
    const double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const double b = d[0] * delta[0] + d[1] * delta[1] + d[2] * delta[2];
    const double cc = ((delta[0] * delta[0] - rr) + delta[1] * delta[1]) + delta[2] * delta[2];
    const SphereLineCertificate lc = sphere_line_certificate(d, delta, rr, a);
    // The input vouched for (the certified query checks no validity before this path):
    // with a > 0 (d nonzero), E is finite only when o, c, d and r are: a non-finite d_j
    // makes a, hence max(a, 2^50), non-finite or NaN; a non-finite Δ_j = o_j - c_j (o_j or
    // c_j non-finite) enters two of the M_k as Δ_j times a component of d, infinite, or
    // NaN when that component is 0; a non-finite radius makes R = r²·a infinite or NaN.
    // r >= 0 (false for NaN) and valid_range do the rest. What this declines is
    // validated in full (sphere_certified_declined).
    if (!(int(lc.E < inf<double>) & int(a > 0) & int(s.radius >= 0) & int(valid_range(r)))) return std::nullopt;
    Hit<T> h;
    if (lc.D > lc.E) return h;  // the line's distance from the centre exceeds r
    // b² - a c' = a (r² - l²) = r² a - |Δ × d|² = -D, up to rounding: the estimates. -D
    // may be negative here (0 < D <= E, near a tangent): clamped at 0, as the square root
    // of a negative number goes through the library's error path to set errno, and an
    // estimate needs no proof (at -D = 0 both are the vertex, which the signs then judge).
    const double qq = -(b + std::copysign(std::sqrt(-lc.D > 0 ? -lc.D : 0.0), b));
    double t0 = qq / a, t1 = cc / qq;
    if (t1 < t0) std::swap(t0, t1);
    if (!(std::isfinite(t0) && std::isfinite(t1))) return std::nullopt;
    const bool min_inf = std::isinf(r.t_min), max_inf = std::isinf(r.t_max);
    const SphereCheapSigns at_min = min_inf ? SphereCheapSigns{1, -1} : sphere_cheap_signs(delta, d, rad, double(r.t_min));
    const SphereCheapSigns at_max = max_inf ? SphereCheapSigns{1, 1} : sphere_cheap_signs(delta, d, rad, double(r.t_max));
    if (at_min.q == 2 || at_max.q == 2) return std::nullopt;
    if (at_min.q > 0 && at_min.slope == 1) return h;
    if (at_max.q > 0 && at_max.slope < 0) return h;
    T t_enter = r.t_min, t_exit = r.t_max;
    if (at_min.q > 0) {
        T g = sphere_canonical(narrow<T>(t0));
        if (double(g) < t0) g = sphere_canonical(step_up(g));
        const Pinned<T> e = sphere_float_pin_enter(r, L, g);
        if (!e.ok) return std::nullopt;
        t_enter = e.t;
    }
    if (at_max.q > 0) {
        T g = sphere_canonical(narrow<T>(t1));
        if (double(g) > t1) g = sphere_canonical(step_down(g));
        const Pinned<T> e = sphere_float_pin_exit(r, L, g);
        if (!e.ok) return std::nullopt;
        t_exit = e.t;
    }
    h.verdict = Verdict::hit;
    h.t_enter = t_enter > t_exit ? t_exit : t_enter;
    h.t_exit = t_exit;
    return h;
}

}  // namespace rayproof::detail
