// rayproof/detail/batch_block.hpp — what the SIMD batch paths (ray_aabb_batch.hpp,
// ray_plane_batch.hpp) share: a block of W rays of a batch gathered into
// structure-of-arrays lanes (RayBlock, gather: every value widened to double, which is
// exact for float and double input alike, so the lanes compute from the very values the
// scalar queries do), the loop over the blocks (for_each_block) and the scalar certified
// query that answers what a block leaves undecided and the rays of a last, partial block
// (scalar_certified).
#pragma once

#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/simd.hpp>
#include <rayproof/prepared_ray.hpp>
#include <rayproof/types.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>

namespace rayproof::detail::batch {

// Rays per block: one native register of doubles (2 with SSE2, 4 with AVX2; 2 for the
// portable backend alone): wider blocks spill the block's many live vectors (measured for
// the box: four rays to a block in two SSE2 registers took 1.03-1.15× the time of two).
inline constexpr int kBatchLanes = simd::native_lanes<double, 4>() < 2 ? 2 : simd::native_lanes<double, 4>();

// Origin, direction, reciprocal (prepared rays only: PreparedRay::rinv), t_min, t_max.
template <int W> struct RayBlock {
    alignas(32) double o[3][std::size_t(W)];
    alignas(32) double d[3][std::size_t(W)];
    alignas(32) double inv[3][std::size_t(W)];
    alignas(32) double t_min[std::size_t(W)];
    alignas(32) double t_max[std::size_t(W)];
};

template <class R, class T, int W> RAYPROOF_ALWAYS_INLINE void gather(const R* rays, RayBlock<W>& g) {
    RAYPROOF_UNROLL_LANES
    for (int i = 0; i < W; ++i) {
        const Ray<T>& r = ray_of(rays[i]);
        RAYPROOF_UNROLL3
        for (int a = 0; a < 3; ++a) {
            g.o[a][i] = double(r.origin[a]);
            g.d[a][i] = double(r.direction[a]);
            if constexpr (is_prepared_ray_v<R>) g.inv[a][i] = rays[i].rinv(a);
        }
        g.t_min[i] = double(r.t_min);
        g.t_max[i] = double(r.t_max);
    }
}

// A batch streams its rays from memory once, and a loop whose branches depend on each
// ray's outcome (a hit or a miss, a fallback) keeps few of the next rays' loads in flight:
// so every batch loop asks for the cache lines of the rays kPrefetchBytes ahead of those
// it answers. Measured on fresh rays from a pool of 1M (bench/ batch sweep's workload,
// -O2, ns a ray, double Aabb): the fast scalar loop 39 without, 28 at 256 bytes ahead,
// 10 at 1 KiB, 8.6 at 2 KiB, 8.1 at 4 KiB, 8.6 at 8 KiB; a copy of the rays alone takes 4.
inline constexpr std::size_t kPrefetchBytes = 2048;
template <class R> RAYPROOF_ALWAYS_INLINE void prefetch_ahead(std::span<const R> rays, std::size_t first, std::size_t count) {
    constexpr std::size_t ahead = (kPrefetchBytes + sizeof(R) - 1) / sizeof(R);
    if (rays.size() - first > ahead + count) prefetch(rays.data() + first + ahead, count * sizeof(R));
}

// Whether batch_of takes the lane paths: where a native register holds two doubles or
// more (SSE2, AVX2); with the portable backend alone it keeps the scalar loop.
inline constexpr bool kLanesPay = simd::native_lanes<double, 4>() >= 2;

// What a lane path answers: the certified query (Hit<T>) or the verdict alone.
template <class Out, class T>
concept CertifiedOut = std::is_same_v<Out, Hit<T>> || std::is_same_v<Out, Verdict>;

// out = the scalar certified answer (Out = Hit<T>) or verdict (Out = Verdict) of ray r
// against the prepared shape p: what a lane path gives every ray it does not decide.
template <class R, class P, class Out> void scalar_certified(const R& r, const P& p, Out& out) {
    if constexpr (std::is_same_v<Out, Verdict>)
        out = verdict_query(r, p, certified_t{});
    else
        out = query(r, p, certified_t{});
}

// The loop of a lane path: every whole block of W rays (when shape_ok) gathered and
// handed to block(k, g), which answers out[k], ..., out[k + W - 1] and returns the mask
// of the lanes it leaves undecided (bit i: out[k + i]); those, the rays of a last,
// partial block, and every ray when !shape_ok are answered by scalar_certified.
// Defer: where many lanes are left undecided at random (the plane's double hits, about
// half the rays), a branch on each block's mask is mispredicted about as often; then the
// undecided rays of each chunk of kFallbackChunk rays are listed without a branch and
// answered after the chunk's blocks. Where few are (every other lane path), the branch is
// predicted and the list would only add its stores (measured in pairs on fresh rays, -O2:
// the float plane 6.9 ns a ray with the list against 6.2 without; the double plane's full
// query 22-24 against 30-31).
inline constexpr std::size_t kFallbackChunk = 256;  // a multiple of every W
template <class T, bool Defer, class R, class P, class Out, class Block>
RAYPROOF_ALWAYS_INLINE void for_each_block(std::span<const R> rays, const P& p, std::span<Out> out, bool shape_ok,
                                           Block&& block) {
    constexpr int W = kBatchLanes;
    const std::size_t n = rays.size(), blocks = shape_ok ? n / W * W : 0;
    RayBlock<W> g;
    if constexpr (Defer) {
        static_assert(kFallbackChunk % std::size_t(W) == 0);
        std::uint32_t left[kFallbackChunk];
        for (std::size_t c = 0; c < blocks; c += kFallbackChunk) {
            const std::size_t end = blocks - c < kFallbackChunk ? blocks : c + kFallbackChunk;
            std::size_t m = 0;
            for (std::size_t k = c; k < end; k += W) {
                prefetch_ahead(rays, k, W);
                gather<R, T, W>(rays.data() + k, g);
                const std::uint32_t undecided = block(k, g);
                RAYPROOF_UNROLL_LANES
                for (int i = 0; i < W; ++i) {
                    left[m] = std::uint32_t(k - c) + std::uint32_t(i);
                    m += (undecided >> i) & 1u;
                }
            }
            for (std::size_t q = 0; q < m; ++q) scalar_certified(rays[c + left[q]], p, out[c + left[q]]);
        }
    } else {
        for (std::size_t k = 0; k < blocks; k += W) {
            prefetch_ahead(rays, k, W);
            gather<R, T, W>(rays.data() + k, g);
            const std::uint32_t undecided = block(k, g);
            if (undecided != 0) [[unlikely]]
                for (int i = 0; i < W; ++i)
                    if ((undecided >> i) & 1u) scalar_certified(rays[k + std::size_t(i)], p, out[k + std::size_t(i)]);
        }
    }
    for (std::size_t j = blocks; j < n; ++j) scalar_certified(rays[j], p, out[j]);
}

}  // namespace rayproof::detail::batch
