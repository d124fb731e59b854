// rayproof/detail/ray_plane_batch.hpp — the certified batch forms against one plane
// (intersect.hpp's batch_of), W rays at a time in the SIMD lanes of detail/simd.hpp.
//
// Float rays. The certified float query (ray_plane.hpp, plane_certified_common) opens
// with the conservative enclosure: plane_sums and plane_enclosure in double, then
// plane_nearest_float. Per block of W rays, gathered into lanes (detail/batch_block.hpp,
// every value widened to double exactly), each lane runs those same operations on the
// same operands in the same order:
//   p_j = n_j·o_j and p'_j = n_j·d_j (exact: products of two floats), N~ = -(((-f + p_0)
//   + p_1) + p_2), D~ = (p'_0 + p'_1) + p'_2, S_N and S_D the same sums of the |terms|,
//   e_N = rounded(K·S_N) + eta, e_D = rounded(K·S_D) + eta, inv = 1/D~, t~ =
//   rounded(N~·inv), E = 2·(rounded(e_N·|inv|) + rounded(|t~|·(rounded(e_D·|inv|) +
//   3u))) + eta, [lo, hi] = [t~ - E, t~ + E] and ok;
// each an IEEE operation in both the scalar code and the lanes, with every product
// that a compiler could fuse either exact or behind rounded() (class C3, detail/eft.hpp),
// so a lane's lo, hi and ok are the scalar query's bits. The lane then answers exactly
// where the scalar query answers from the enclosure (its first branch): ok, t_min <= t_max
// with t_min != +inf and t_max != -inf (valid_range; a prepared ray's validity is the
// same, since ok and the range prove the ray valid), and the enclosure inside [t_min,
// t_max] with both ends rounding to one float (a hit at that float, nearest_float per
// lane) or outside it (a miss). Every other ray (invalid input, a parallel or nearly
// parallel ray, an overflow, an enclosure straddling t_min or t_max or two floats) goes
// to the scalar certified query, as do the rays of a last, partial block and every ray
// when the plane is invalid. The verdict batch answers where the enclosure lies inside
// or outside the range (validity proven as above): the verdict is exact on either path,
// so it is the scalar verdict; the rest goes to the scalar verdict query.
// Double rays: their products are not exact, and the certified query pins t in
// double-word arithmetic (plane_pin), which the lanes do not repeat. The lanes run the
// verdict filter instead (plane_filter_block, plane_verdict_common's arithmetic in
// vertical lanes, with its derivation): the verdict batch answers every lane the filter
// decides, and the full batch every lane it proves a miss (Hit<double>{}, which every
// certified path answers for a miss); a hit needs its t and goes to the scalar query, as
// does everything the filter leaves undecided.
// The backend B is simd::native in batch_of and simd::portable beside it in the tests.
#pragma once

#include <rayproof/detail/batch_block.hpp>
#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/simd.hpp>
#include <rayproof/prepared_ray.hpp>
#include <rayproof/ray_plane.hpp>
#include <rayproof/types.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <type_traits>

namespace rayproof::detail::batch {

// The lanes' answers: which lanes are decided, which of them hit (full query: inside
// with its ends rounding to one float; verdict: inside), and for the full query each
// lane's t, the float both ends round to where they do (nearest_float).
template <int W> struct PlaneDecided {
    std::uint32_t decided, hit;
    float t[std::size_t(W)];
};

// Full: the hit lanes need their ends to round to one float (the full query's t).
template <class B, bool Full, int W>
RAYPROOF_ALWAYS_INLINE void plane_block(const RayBlock<W>& g, const Plane<float>& p, PlaneDecided<W>& out) {
    using V = simd::Vec<double, W, B>;
    using M = simd::Mask<double, W, B>;
    constexpr double K = gamma<double>(4), eta = 0x1p-1022, u = unit_roundoff<double>;
    constexpr double big = std::numeric_limits<double>::max(), inf = std::numeric_limits<double>::infinity();
    const double f = p.offset;
    V po[3], pd[3];
    RAYPROOF_UNROLL3
    for (int j = 0; j < 3; ++j) {
        const V n = V::splat(double(p.normal[j]));
        po[j] = n * V::load(g.o[j]);  // exact (two floats), as plane_sums'
        pd[j] = n * V::load(g.d[j]);
    }
    // plane_sums
    const V num = -(((V::splat(-f) + po[0]) + po[1]) + po[2]), den = (pd[0] + pd[1]) + pd[2];
    const V sn = ((V::splat(std::abs(f)) + abs(po[0])) + abs(po[1])) + abs(po[2]);
    const V sd = (abs(pd[0]) + abs(pd[1])) + abs(pd[2]);
    const V en = rounded(V::splat(K) * sn) + V::splat(eta), ed = rounded(V::splat(K) * sd) + V::splat(eta);
    // plane_enclosure
    const V inv = V::splat(1.0) / den, ai = abs(inv);
    const V t = rounded(num * inv);
    const V rel = rounded(ed * ai) + V::splat(3 * u);
    const V bound = V::splat(2.0) * (rounded(en * ai) + rounded(abs(t) * rel)) + V::splat(eta);
    const M ok = (ed <= V::splat(0x1p-20) * abs(den)) & (V::splat(std::numeric_limits<double>::min()) <= ai) &
                 (ai <= V::splat(big)) & (bound <= V::splat(big));
    const V lo = rounded(t - bound), hi = rounded(t + bound);
    // valid_range, and where the enclosure lies against [t_min, t_max]
    const V t_min = V::load(g.t_min), t_max = V::load(g.t_max);
    const M range = (t_min <= t_max) & (t_min < V::splat(inf)) & (V::splat(-inf) < t_max);
    const M inside = (t_min <= lo) & (hi <= t_max), outside = (hi < t_min) | (t_max < lo);
    const std::uint32_t usable = (ok & range).bits();
    if constexpr (Full) {
        alignas(32) double lo_i[std::size_t(W)], hi_i[std::size_t(W)];
        lo.store(lo_i);
        hi.store(hi_i);
        // nearest_float per lane: the inside lanes whose ends round to one float
        std::uint32_t one_float = 0;
        RAYPROOF_UNROLL_LANES
        for (int i = 0; i < W; ++i) {
            const Pinned<float> f1 = nearest_float(lo_i[i], hi_i[i], true);
            out.t[i] = f1.t;
            one_float |= std::uint32_t(f1.ok) << i;
        }
        const std::uint32_t in = inside.bits() & one_float;
        out.decided = usable & (in | outside.bits());
        out.hit = in;
    } else {
        out.decided = usable & (inside | outside).bits();
        out.hit = inside.bits();
    }
}

// The certified verdict filter of plane_verdict_common for W double rays, in vertical
// lanes: per lane the same sums, bounds and tests (its derivation holds lane by lane; the
// filter's bits need not be the scalar copy's, since a verdict it decides is exact).
// decided: the filter proved the verdict and the input valid; hit: the verdict.
struct FilterDecided {
    std::uint32_t decided, hit;
};
template <class B, int W>
RAYPROOF_ALWAYS_INLINE FilterDecided plane_filter_block(const RayBlock<W>& g, const Plane<double>& p) {
    using V = simd::Vec<double, W, B>;
    using M = simd::Mask<double, W, B>;
    constexpr double K = gamma<double>(4), eta = 0x1p-1022, inf = std::numeric_limits<double>::infinity();
    const double f = p.offset;
    V po[3], pd[3];
    RAYPROOF_UNROLL3
    for (int j = 0; j < 3; ++j) {
        const V n = V::splat(p.normal[j]);
        po[j] = n * V::load(g.o[j]);
        pd[j] = n * V::load(g.d[j]);
    }
    // -N~ and D~ as plane_verdict_common's lanes 0 and 1, and their bounds e_N, e_D.
    const V neg_n = ((V::splat(-f) + po[0]) + po[1]) + po[2], den = (pd[0] + pd[1]) + pd[2];
    const V sn = ((V::splat(std::abs(f)) + abs(po[0])) + abs(po[1])) + abs(po[2]);
    const V sd = (abs(pd[0]) + abs(pd[1])) + abs(pd[2]);
    const V en = sn * V::splat(K) + V::splat(eta), ed = sd * V::splat(K) + V::splat(eta);
    const V t_min = V::load(g.t_min), t_max = V::load(g.t_max);
    // A~ = sigma·(N~ - t_min·D~) and C~ = sigma·(t_max·D~ - N~), sigma = sign(D~); the
    // sign is moved by a product with ±1 (exact).
    const V zero = V::splat(0.0), sigma = select(den < zero, V::splat(-1.0), V::splat(1.0));
    const V a = (-neg_n + -t_min * den) * sigma, c = (neg_n + t_max * den) * sigma;
    const V ea = V::splat(2.0) * (en + abs(t_min) * ed), ec = V::splat(2.0) * (en + abs(t_max) * ed);
    const M fa = abs(a) < V::splat(inf), fc = abs(c) < V::splat(inf);
    const M holds = (((ea <= a) & fa) | (t_min == V::splat(-inf))) & (((ec <= c) & fc) | (t_max == V::splat(inf)));
    const M fails = ((a < -ea) & fa) | ((c < -ec) & fc);
    // valid_range_lanes: t_min - t_max <= 0 (false for t_min = +inf, t_max = -inf, NaN).
    const M valid = (en < V::splat(inf)) & (ed < V::splat(inf)) & (t_min - t_max <= zero);
    const M usable = valid & (ed < abs(den));
    return {(usable & (holds | fails)).bits(), holds.bits()};
}

// out[i] = the certified answer (Out = Hit<T>) or verdict (Out = Verdict) for rays[i],
// the environment already the default one (batch_of).
template <class B, class R, class T, class Out>
void certified_lanes(std::span<const R> rays, const PreparedPlane<T>& p, std::span<Out> out) {
    constexpr int W = kBatchLanes;
    constexpr bool full = std::is_same_v<Out, Hit<T>>;
    // Double rays' full query leaves every hit to the scalar query: about half the rays.
    constexpr bool defer = std::is_same_v<T, double> && full;
    for_each_block<T, defer>(rays, p, out, p.ok, [&](std::size_t k, const RayBlock<W>& g) RAYPROOF_INLINE_LAMBDA {
        if constexpr (std::is_same_v<T, double>) {
            // The filter's verdicts: the full query answers its misses, the verdict all.
            const FilterDecided f = plane_filter_block<B>(g, p.shape);
            RAYPROOF_UNROLL_LANES
            for (int i = 0; i < W; ++i) {
                const std::size_t j = k + std::size_t(i);
                if constexpr (full)
                    out[j] = Hit<T>{};
                else
                    out[j] = Verdict(int((f.hit >> i) & 1));
            }
            // Left to the scalar query: the undecided lanes, and the full query's hits.
            const std::uint32_t answered = full ? f.decided & ~f.hit : f.decided;
            return ~answered & ((1u << W) - 1u);
        } else {
            PlaneDecided<W> dec;
            plane_block<B, full>(g, p.shape, dec);
            RAYPROOF_UNROLL_LANES
            for (int i = 0; i < W; ++i) {
                const std::size_t j = k + std::size_t(i);
                const bool hit = (dec.hit >> i) & 1;
                if constexpr (full) {
                    // hit_when, as the scalar query answers from the enclosure (a miss is
                    // Hit<float>{}); t is the one float both ends round to.
                    out[j] = hit_when(hit, dec.t[i], dec.t[i]);
                } else {
                    out[j] = Verdict(int(hit));
                }
            }
            return ~dec.decided & ((1u << W) - 1u);
        }
    });
}

// The batch_of hook (intersect.hpp): rays against a plane, certified, where a native
// register holds two doubles or more (SSE2, AVX2; kLanesPay). Measured in pairs within
// one program on the bench's batch workload (uniform rays, half of them misses),
// 1,000,000 rays in calls of 10,000 (fresh rays in every call), -O2, the lanes take of
// the scalar loop's time: in the default x86-64 build (SSE2) 0.64× (float rays) and
// 0.71× (double: the hits' pinned t dominates) for the full query, 0.60× and 0.75× for
// the verdict; in an AVX2 build 0.59× and 0.68× for the full query, 0.42× and 0.56× for
// the verdict.
template <class R, class T, CertifiedOut<T> Out>
    requires kLanesPay
RAYPROOF_ALWAYS_INLINE void lane_batch(std::span<const R> rays, const PreparedPlane<T>& p, std::span<Out> out,
                                       certified_t) {
    certified_lanes<simd::native>(rays, p, out);
}

}  // namespace rayproof::detail::batch
