// rayproof/detail/ray_sphere_verdict.hpp — the verdict filter of the certified Ray/Sphere
// query (sphere_verdict_common): signs only, no square root, division or root; it
// answers int(Verdict::miss), int(Verdict::hit) or verdict_declined
// (detail/certified.hpp).
#pragma once

#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/lanes.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/types.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rayproof::detail {

// The certified verdict alone: a filter of its own, with no square root, no division
// and no root (the full query's straight-line path estimates and proves roots; the
// verdict needs only signs), which also proves the input valid, so nothing is checked
// before it. q is convex with q(±inf) = +inf: an end of the range with q < 0 is inside
// (a hit); an end with q > 0 and the slope pointing away from the range (up at t_min,
// down at t_max) means q > 0 on the whole range (a miss); the slope pointing into the
// range at both ends puts the vertex t* = -b/a strictly inside it, where q(t*) = l² - r²
// (l the line's distance from the centre) has the sign of l - r; and l > r is a miss
// on any range. verdict_declined for the rest (see verdict_or, detail/certified.hpp).
// The ends, t_min in lane 0 and t_max in lane 1, with the bounds of sphere_cheap_signs
// (the same operations, two lanes at once): |fl(Σ w~_j² - r²) - q(t)| <= gamma(9)·(Σ M_j² +
// r²) and |fl(Σ d_j w~_j) - (a t + b)| <= gamma(6)·Σ|d_j| M_j, each threshold twice the
// bound plus 2^-1000; a sum that overflows makes its bound's sum (of terms at least as
// large) +inf, and NaN anywhere compares false, so no sign is taken then. An infinite
// end computes NaN or ±inf (nothing is decided from it) and is taken as q > 0 with the
// slope pointing into the range.
// The line: l² a = |w|², w = Δ × d, so l > r iff S = |w|² > R = r² a, and l < r iff S <
// R (a > 0). Computed: Δ~_j = Δ_j(1 + δ), |δ| <= u; per component the two products A~,
// B~ (e.g. fl(Δ~_y d_z), fl(Δ~_z d_y), each within gamma(2) of the exact product plus
// 2^-1075 for underflow) and w~ = fl(A~ - B~), so with M = |A~| + |B~|,
//     |w~ - w| <= gamma(2)(|Δ_y d_z| + |Δ_z d_y|) + u M + 2^-1074 <= gamma(4) M + 2^-1073;
// |w~| <= M, and summing the squares (three roundings),
//     |S~ - S| <= gamma(3)Σ w~_j² + Σ e_j(2|w~_j| + e_j) + 3·2^-1075 <= gamma(13)Σ M_j² + 2^-1070
// (the cross terms 2^-1072·M_j are below u·M_j² for M_j >= 2^-1018 and below 2^-2000
// otherwise). With a~ = fl(Σ d_j²) >= 2^-1000 (required: its own underflow, at most
// 3·2^-1075, is then far below u·a, so |a~ - a| <= gamma(4)a) and R~ = fl(fl(r·r)·a~),
//     |R~ - R| <= gamma(7)·R~ + 2^-1074·a~ + 2^-1074
// (the 2^-1074·a~ from r·r underflowing). So D~ = fl(S~ - R~) > E proves S > R and
// -D~ > E proves S < R, for E = fl(2·gamma(13)·ΣM~_j² + 2·gamma(7)·R~ + 2^-1072·max(a~,
// 2^50)) + 2^-1000 (the max keeps the term normal, below): the doubling covers the few
// roundings of E, of ΣM~² (each M~ = fl(|A~| + |B~|)) and of D~ itself. An overflow makes E +inf (ΣM~² >= S~, R~ itself) and decides nothing.
// Validity: every decision above rests on a finite bound, which an infinite or NaN
// number among o, d, c and r makes +inf or NaN (each Δ_j and d_j is multiplied by
// something in each bound, and 0·inf is NaN), and a~ >= 2^-1000 means d != 0, r >= 0 is
// checked, and t_min <= t_max, t_min < +inf and -t_max < +inf in the lanes as the Aabb
// checks them.
// Contraction (detail/eft.hpp): class C1. A fused w~ = fl(A - B~) or D~ = fl(S~ - r·r·a~)
// has one rounding fewer than counted; |w~| <= M then holds up to a factor (1 + u)^2,
// which the slack between the terms counted (11u·M² at most) and gamma(13)·M² covers.
// The line's certificate (derivation above): D = fl(|w~|² - r²·a~) with w = Δ × d and
// its bound E, so D > E proves the line's distance l > r and -D > E proves l < r (when
// a~ >= 2^-1000). Shared with the float straight-line path (ray_sphere_straight_line.hpp),
// which takes its root estimates from the same D.
struct SphereLineCertificate {
    double D, E;
};
RAYPROOF_ALWAYS_INLINE SphereLineCertificate sphere_line_certificate(const double (&d)[3], const double (&delta)[3],
                                                                     double rr, double a) {
    constexpr double eta = 0x1p-1000, g13 = 2 * gamma<double>(13), g7 = 2 * gamma<double>(7);
    double S = 0, MM = 0;
    RAYPROOF_UNROLL3
    for (int j = 0; j < 3; ++j) {
        const int k = (j + 1) % 3, m = (j + 2) % 3;
        const double A = delta[k] * d[m], B = delta[m] * d[k], w = A - B, M = std::abs(A) + std::abs(B);
        S += w * w;
        MM += M * M;
    }
    const double R = rr * a;
    // 2^-1072·max(a~, 2^50) >= 2^-1072·a~, so E only grows; and it is never subnormal
    // (at least 2^-1022): 2^-1072·a~ itself is for every a~ below 2^50, and a subnormal
    // result costs a microcode assist of about a hundred cycles on x86 (it took half the
    // time of the certified verdict on uniform input). NaN stays NaN (max keeps a~ when
    // the comparison is false), +inf stays +inf.
    return {S - R, (g13 * MM + g7 * R + 0x1p-1072 * std::max(a, 0x1p50)) + eta};
}

template <class T> RAYPROOF_ALWAYS_INLINE int sphere_verdict_common(const Ray<T>& r, const Sphere<T>& s) {
    using namespace lanes;
    constexpr double eta = 0x1p-1000, g9 = 2 * gamma<double>(9), g6 = 2 * gamma<double>(6),
                     inf = std::numeric_limits<double>::infinity();
    const double rad = double(s.radius), rr = rad * rad;
    double d[3], delta[3];
    RAYPROOF_UNROLL3
    for (int j = 0; j < 3; ++j) {
        d[j] = double(r.direction[j]);
        delta[j] = double(r.origin[j]) - double(s.center[j]);
    }
    // The line's certificate.
    const double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const SphereLineCertificate lc = sphere_line_certificate(d, delta, rr, a);
    const bool line_out = lc.D > lc.E, line_in = -lc.D > lc.E;
    // The ends.
    const D2 t = make(double(r.t_min), double(r.t_max));
    D2 v = splat(-rr), bq = splat(rr), sl = splat(0.0), bs = splat(0.0);
    RAYPROOF_UNROLL3
    for (int j = 0; j < 3; ++j) {
        const D2 dj = splat(d[j]), P = t * dj, W = splat(delta[j]) + P, M = splat(std::abs(delta[j])) + abs(P);
        v = v + W * W;
        bq = bq + M * M;
        sl = sl + dj * W;
        bs = bs + abs(dj) * M;
    }
    const D2 tq = bq * splat(g9) + splat(eta), ts = bs * splat(g6) + splat(eta), out = negate_lane1(sl);
    const M2 infinite = abs(t) == splat(inf);
    const M2 inside = v < -tq, outside = (v > tq) | infinite;
    const M2 away = out > ts, toward = (out < -ts) | infinite;  // the slope at each end
    const D2 ordered = negate_lane1(t);                              // (t_min, -t_max)
    const M2 limits = valid_range_lanes(ordered);
    const bool usable = int(bits(limits) == 3) & int(rad >= 0) & int(a >= 0x1p-1000);
    const bool hit = (bits(inside) != 0) | (int(bits(toward) == 3) & int(line_in));
    const bool miss = int(line_out) | int(bits(outside & away) != 0);
    return usable & (int(hit) | int(miss)) ? int(hit) : verdict_declined;
}

}  // namespace rayproof::detail
