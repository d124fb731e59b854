// rayproof/detail/ray_aabb_batch.hpp — the certified batch forms against one box (N rays,
// intersect.hpp's batch_of) with W rays at a time in the SIMD lanes of detail/simd.hpp.
//
// Per block of W rays, gathered into structure-of-arrays lanes (every value widened to
// double exactly, as aabb_lanes does), each lane runs the straight-line certified path
// of ray_aabb.hpp (aabb_lanes, aabb_certified_common) with the entry problem and the
// negated exit problem as two vectors instead of two lanes of one register: the same
// operations on the same operands, in the same order and with the same rounded()
// barriers (eft.hpp, class C3), so every value a decision or an answer is made from has
// the scalar path's bits:
//   t_lo = rounded(fl(lo - o)·inv), t_hn = rounded(fl(o - hi)·inv) (inv = fl(1/d), the
//   prepared ray's rinv or divided here), per axis entry = min(t_lo, -t_hn) and negated
//   exit = min(t_hn, -t_lo); the probe ((t_lo0 + t_hn0) + t_lo2) + (4d0 + 4d2) and
//   ((t_lo1 + t_hn1) + t_hn2) + (4d1 + 4d2) (d0 + d2 and d1 + d2 for float input) == 0
//   after s - s; m, the runner-up m2 and the winning axes; and for double input the
//   winners' correction tc = tt + rounded(((s - tt·dh) + (e - tt·dl))·inv).
// The one difference is the bound: the scalar path's bm = fl(fl(K|m|) + eta) is class C1
// (a fused K|m| + eta is allowed there), so its bits depend on the compiler's choice in
// each inlined copy. The lanes take a bound bm' that is at least bm in every evaluation
// order: K' = fl(K(1 + 2^-48)) and eta' = eta(1 + 2^-48) (exact). Each of bm's roundings
// (at most two) raises it by a factor of at most 1 + u, or, for a subnormal product,
// by at most 2^-1075 = 2^-53·eta; each of bm''s lowers it by at most a factor 1 - u or
// 2^-1075, and (1 + 2^-48)(1 - u)^2 > (1 + u)^2 + 2^-51 (u = 2^-53), so bm' >= bm. Every
// decision of the path is monotone in the bound (m_lo = fl(m - bm), m_hi = fl(m + bm),
// max and the sums of two are monotone, rounding is monotone): a lane proves a hit, a
// miss, an axis winning (m2 < m_lo, m_lo > limit) or the limit winning (m_hi < limit)
// only where the scalar path proves the same, and it computes the same winners and the
// same tc there. So a lane answers only where the scalar path answers from its
// straight-line code, with the scalar answer's bits; the bounds themselves contain the
// exact values (ray_aabb.hpp's derivation, which a wider bound only keeps).
// Everything a lane cannot answer (invalid input, ±0 and extreme directions, values that
// overflow, comparisons the bounds cannot separate, winners outside the correction's
// range) goes to the scalar certified query, ray by ray, as do the rays of a last,
// partial block and every ray when the box is not lo <= hi. A miss is Hit<T>{} on every
// path. The verdict batch answers from the proven verdicts alone (exact either way).
// The backend B is simd::native in batch_of and simd::portable beside it in the tests.
#pragma once

#include <rayproof/detail/batch_block.hpp>
#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/prepared.hpp>
#include <rayproof/detail/simd.hpp>
#include <rayproof/prepared_ray.hpp>
#include <rayproof/ray_aabb.hpp>
#include <rayproof/types.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <type_traits>

namespace rayproof::detail::batch {

// x_w for w the winning axis per lane: 2 where c2, else 1 where c01, else 0.
template <class V, class M>
RAYPROOF_ALWAYS_INLINE V pick3(const M& c01, const M& c2, const V& x0, const V& x1, const V& x2) {
    return select(c2, x2, select(c01, x1, x0));
}
template <class V> RAYPROOF_ALWAYS_INLINE auto in_correction_range(const V& m, const V& dd) {
    const V am = abs(m), ad = abs(dd);
    return (V::splat(0x1p-400) <= am) & (am <= V::splat(0x1p400)) & (V::splat(0x1p-500) <= ad) &
           (ad <= V::splat(0x1p500));
}

// The lanes' answers: which lanes are decided, their verdicts, and for the full query
// the fields (in double; for float rays clamped to the floats' range, faithful_to's
// clamp) and the face.
template <int W> struct AabbDecided {
    std::uint32_t decided, hit;
    alignas(32) double t_enter[std::size_t(W)];
    alignas(32) double t_exit[std::size_t(W)];
    int face[std::size_t(W)];
};

// Full: the winners and their values too (the verdict query needs only the proofs).
template <class B, bool Full, class T, int W>
RAYPROOF_ALWAYS_INLINE void aabb_block(const RayBlock<W>& g, bool prepared, const Aabb<T>& b, AabbDecided<W>& out) {
    using V = simd::Vec<double, W, B>;
    using M = simd::Mask<double, W, B>;
    constexpr double K = 2 * gamma<double>(3), eta = 0x1p-1022;
    // The widened bound (see the header comment): K' >= K(1 + 2^-48)(1 - u).
    constexpr double Kw = K + K * 0x1p-48, etaw = eta + eta * 0x1p-48;
    constexpr bool from_float = std::is_same_v<T, float>;
    V o[3], d[3], inv[3], t_lo[3], t_hn[3], Ve[3], Vx[3];
    RAYPROOF_UNROLL3
    for (int a = 0; a < 3; ++a) {
        o[a] = V::load(g.o[a]);
        d[a] = V::load(g.d[a]);
        inv[a] = prepared ? V::load(g.inv[a]) : V::splat(1.0) / d[a];
        const V lo = V::splat(double(b.lo[a])), hi = V::splat(double(b.hi[a]));
        // Class C3, as in aabb_lanes: the probe adds the very values the lanes compare.
        t_lo[a] = rounded((lo - o[a]) * inv[a]);
        t_hn[a] = rounded((o[a] - hi) * inv[a]);
        Ve[a] = min(t_lo[a], -t_hn[a]);
        Vx[a] = min(t_hn[a], -t_lo[a]);
    }
    V de0, dx0;  // the direction terms of aabb_lanes' probe, lane 0 and lane 1
    if constexpr (from_float) {
        de0 = d[0] + d[2];
        dx0 = d[1] + d[2];
    } else {
        const V four = V::splat(4.0), d2 = rounded(d[2] * four);
        de0 = rounded(d[0] * four) + d2;
        dx0 = rounded(d[1] * four) + d2;
    }
    const V se = ((t_lo[0] + t_hn[0]) + t_lo[2]) + de0, sx = ((t_lo[1] + t_hn[1]) + t_hn[2]) + dx0;
    const V zero = V::splat(0.0);
    const M usable = ((se - se) == zero) & ((sx - sx) == zero);
    const V limit_e = V::load(g.t_min), limit_x = -V::load(g.t_max);
    // Per problem (entry: e, negated exit: x) as in aabb_lanes / aabb_certified_common.
    const V v01e = max(Ve[0], Ve[1]), v01x = max(Vx[0], Vx[1]);
    const V me = max(v01e, Ve[2]), mx = max(v01x, Vx[2]);
    const V bme = abs(me) * V::splat(Kw) + V::splat(etaw), bmx = abs(mx) * V::splat(Kw) + V::splat(etaw);
    const V me_lo = me - bme, me_hi = me + bme, mx_lo = mx - bmx, mx_hi = mx + bmx;
    const V he = max(me_hi, limit_e), hx = max(mx_hi, limit_x), ge = max(me_lo, limit_e), gx = max(mx_lo, limit_x);
    const M range = (limit_e + limit_x) <= zero;  // valid_range_lanes
    const M hit_proven = ((he + hx) < zero) & range, miss_proven = (zero < (ge + gx)) & range;
    if constexpr (!Full) {
        out.decided = (usable & (hit_proven | miss_proven)).bits();
        out.hit = hit_proven.bits();
        return;
    } else {
        const V m2e = max(min(Ve[0], Ve[1]), min(v01e, Ve[2])), m2x = max(min(Vx[0], Vx[1]), min(v01x, Vx[2]));
        const M c01e = Ve[0] < Ve[1], c2e = v01e < Ve[2], c01x = Vx[0] < Vx[1], c2x = v01x < Vx[2];
        const M axis_e = (m2e < me_lo) & (limit_e < me_lo), axis_x = (m2x < mx_lo) & (limit_x < mx_lo);
        const M limit_wins_e = me_hi < limit_e, limit_wins_x = mx_hi < limit_x;
        const M hit = (axis_e | limit_wins_e) & (axis_x | limit_wins_x) & hit_proven;
        // The winner's direction (axis w for the entry, v for the exit) per lane.
        const V dw = pick3(c01e, c2e, d[0], d[1], d[2]), dv = pick3(c01x, c2x, d[0], d[1], d[2]);
        const M neg_w = dw < zero, neg_v = dv < zero;
        V tce = me, tcx = mx;
        M decided = miss_proven | hit;
        if constexpr (!from_float) {
            // The correction of aabb_certified_common, lane 0 (entry) and lane 1 (exit).
            V lo3[3], hi3[3];
            RAYPROOF_UNROLL3
            for (int a = 0; a < 3; ++a) {
                lo3[a] = V::splat(double(b.lo[a]));
                hi3[a] = V::splat(double(b.hi[a]));
            }
            const V p_in = select(neg_w, pick3(c01e, c2e, hi3[0], hi3[1], hi3[2]), pick3(c01e, c2e, lo3[0], lo3[1], lo3[2]));
            const V p_out = select(neg_v, pick3(c01x, c2x, lo3[0], lo3[1], lo3[2]), pick3(c01x, c2x, hi3[0], hi3[1], hi3[2]));
            const V o_w = pick3(c01e, c2e, o[0], o[1], o[2]), o_v = pick3(c01x, c2x, o[0], o[1], o[2]);
            const V inv_w = pick3(c01e, c2e, inv[0], inv[1], inv[2]), inv_v = pick3(c01x, c2x, inv[0], inv[1], inv[2]);
            const SumOf<V> s_e = two_sum(p_in, -o_w), s_x = two_sum(o_v, -p_out);
            const V tte = high26(me), ttx = high26(mx), dhe = high26(dw), dhx = high26(dv);
            // tt·dh and tt·(d - dh) exact (class C2); the product with 1/d rounded() (C3).
            tce = tte + rounded(((s_e.hi - tte * dhe) + (s_e.lo - tte * (dw - dhe))) * inv_w);
            tcx = ttx + rounded(((s_x.hi - ttx * dhx) + (s_x.lo - ttx * (dv - dhx))) * inv_v);
            const M ok_e = limit_wins_e | in_correction_range(me, dw) | (s_e.hi == zero);
            const M ok_x = limit_wins_x | in_correction_range(mx, dv) | (s_x.hi == zero);
            decided = miss_proven | (hit & ok_e & ok_x);
        }
        out.decided = (usable & decided).bits();
        out.hit = hit.bits();
        // (t_enter, t_exit) as aabb_certified_common: max(tc, limit), the exit negated
        // back, + 0.0, then t_enter = min(t_enter, t_exit).
        // For float rays, faithful_to's clamp to the floats' range here in the lanes.
        const V ue = max(tce, limit_e) + zero, ux = -max(tcx, limit_x) + zero;
        V te = select(ue < ux, ue, ux), tx = ux;
        if constexpr (from_float) {
            const V big = V::splat(double(std::numeric_limits<float>::max()));
            te = min(max(te, -big), big);
            tx = min(max(tx, -big), big);
        }
        te.store(out.t_enter);
        tx.store(out.t_exit);
        const std::uint32_t c01 = c01e.bits(), c2 = c2e.bits(), neg = neg_w.bits(), lim = limit_wins_e.bits();
        RAYPROOF_UNROLL_LANES
        for (int i = 0; i < W; ++i) {
            const int w = ((c2 >> i) & 1) ? 2 : int((c01 >> i) & 1);
            out.face[i] = ((lim >> i) & 1) ? -1 : 2 * w + int((neg >> i) & 1);
        }
    }
}

// out[i] = the certified answer (Out = Hit<T>) or verdict (Out = Verdict) for rays[i],
// the environment already the default one (batch_of).
template <class B, class R, class T, class Out>
void certified_lanes(std::span<const R> rays, const PreparedAabb<T>& p, std::span<Out> out) {
    constexpr int W = kBatchLanes;
    const Aabb<T>& b = p.shape;
    const bool box_ok = int(b.lo[0] <= b.hi[0]) & int(b.lo[1] <= b.hi[1]) & int(b.lo[2] <= b.hi[2]);
    for_each_block<T, false>(rays, p, out, box_ok, [&](std::size_t k, const RayBlock<W>& g) RAYPROOF_INLINE_LAMBDA {
        AabbDecided<W> dec;
        aabb_block<B, std::is_same_v<Out, Hit<T>>>(g, is_prepared_ray_v<R>, b, dec);
        RAYPROOF_UNROLL_LANES
        for (int i = 0; i < W; ++i) {
            const std::size_t j = k + std::size_t(i);
            const bool hit = (dec.hit >> i) & 1;
            if constexpr (std::is_same_v<Out, Hit<T>>) {
                // Without a branch (hit_when picks): hits and misses are as random as
                // the rays, and the ternaries written here before became a jump that
                // fresh rays mispredicted (a float ray then cost 1.4× the scalar loop's
                // time, measured in pairs). A miss is Hit<T>{}, as on every certified
                // path; the lanes clamped t to T's range, so narrow is faithful_to.
                out[j] = hit_when(hit, narrow<T>(dec.t_enter[i]), narrow<T>(dec.t_exit[i]), dec.face[i]);
            } else {
                out[j] = Verdict(int(hit));
            }
        }
        return ~dec.decided & ((1u << W) - 1u);
    });
}

// The batch_of hook (intersect.hpp): the certified query and verdict, W rays at a time,
// wherever a native register holds two doubles or more (SSE2, AVX2; kLanesPay). Measured
// in pairs within one program on the bench's batch workload, 1,000,000 uniform rays
// answered in calls of 10,000 (fresh rays in every call: on the same rays again and
// again the branch predictor learns their outcomes), the lanes take of the scalar loop's
// time at -O2: in the default x86-64 build (SSE2, two lanes) 0.80× (double rays) and
// 0.93-0.96× (float) for the full query, 0.76× and 0.79× for the verdict; in an AVX2
// build (four lanes) 0.53× and 0.55× for the full query, 0.52× and 0.47× for the verdict.
template <class R, class T, CertifiedOut<T> Out>
    requires kLanesPay
RAYPROOF_ALWAYS_INLINE void lane_batch(std::span<const R> rays, const PreparedAabb<T>& p, std::span<Out> out,
                                       certified_t) {
    certified_lanes<simd::native>(rays, p, out);
}

}  // namespace rayproof::detail::batch
