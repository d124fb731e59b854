// bench/ray_aabb_packet_bench.cpp — the box packets (ray_aabb_packet.hpp) against the
// branch-free structure-of-arrays slab loop (baselines.hpp, soa_slab) over the same
// boxes: ns per box test of verdict() in fast and certified mode, float W = 8, double
// W = 4 and 8, plus the certified intersect().
//
// Workload ("uniform"): 1024 packets of boxes with lower corners uniform in [-2, 2]^3
// and extents uniform in [0, 1.5] per axis, and 1024 prepared rays with origins uniform
// in [-4, 4]^3, ray k aimed at a point uniform in one of packet k's boxes (box k mod W),
// so that each packet has a hit and its neighbours are hit at random (the counter
// hit_rate says how many box tests hit), seeded; ray k is tested against packet k. The reciprocals are computed outside
// the timed loop for every method (PreparedRay for the packets, 1/d for the baseline).
// The counter ns_per_box is the time per call divided by W. The machine may be shared:
// run with --benchmark_repetitions and --benchmark_enable_random_interleaving so that
// each method's repetitions alternate with the others' and compare the medians.
//
// Embree (float, W = 8, where Embree 3 is found): its node test is not public, so each
// packet is an Embree scene of W user-geometry boxes (one box per primitive, the box as
// its bounds) and the ray goes through rtcIntersect1, or rtcIntersect8 with rays k..k+7
// against scene k; the primitive callback only counts its calls (a box whose bounds
// Embree's traversal hit), so the time is Embree's BVH node tests plus its call and
// dispatch, per box test. Embree's node test is not exact (no rounding direction, its own
// robust flag aside), and it is asked with t_near = 0 (every ray here has t_min = 0).
#include "baselines.hpp"

#include <rayproof/ray_aabb_packet.hpp>

#include <benchmark/benchmark.h>

#if RAYPROOF_BENCH_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

#include <cstdint>
#include <stdexcept>
#include <random>
#include <vector>

namespace {

using namespace rayproof;

constexpr int kN = 1024;

template <class T, int W> struct Workload {
    std::vector<PreparedRay<T>> rays;
    std::vector<Ray<T>> raw;
    std::vector<std::array<T, 3>> inv;
    std::vector<AabbPacket<T, W>> packets;

    Workload() {
        std::mt19937_64 rng(20261203);
        std::uniform_real_distribution<double> o(-4, 4), c(-2, 2), e(0, 1.5), f(0, 1);
        for (int k = 0; k < kN; ++k) {
            AabbPacket<T, W> p;
            for (int i = 0; i < W; ++i)
                for (int a = 0; a < 3; ++a) {
                    p.lo[a][i] = T(c(rng));
                    p.hi[a][i] = p.lo[a][i] + T(e(rng));
                }
            packets.push_back(p);
            Vec3<T> from, to;
            for (int a = 0; a < 3; ++a) {
                const int j = k % W;
                from[a] = T(o(rng));
                to[a] = p.lo[a][j] + T(f(rng)) * (p.hi[a][j] - p.lo[a][j]);
            }
            Ray<T> r{from, to - from};
            raw.push_back(r);
            rays.emplace_back(r);
            inv.push_back({T(1) / r.direction[0], T(1) / r.direction[1], T(1) / r.direction[2]});
        }
    }
    static const Workload& get() {
        static const Workload w;
        return w;
    }
};

template <int W> void set_counters(benchmark::State& state, std::uint64_t hits) {
    state.counters["ns_per_box"] = benchmark::Counter(double(state.iterations()) * kN * W,
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["hit_rate"] = double(hits) / (double(state.iterations()) * kN * W);
}

template <class T, int W> void BM_soa_slab(benchmark::State& state) {
    const auto& w = Workload<T, W>::get();
    std::uint64_t hits = 0;
    for (auto _ : state)
        for (int k = 0; k < kN; ++k) {
            const Ray<T>& r = w.raw[std::size_t(k)];
            const std::uint32_t m = bench::baseline::soa_slab<T, W>(r.origin.data(), w.inv[std::size_t(k)].data(),
                                                                    w.packets[std::size_t(k)].lo,
                                                                    w.packets[std::size_t(k)].hi, r.t_min, r.t_max);
            benchmark::DoNotOptimize(m);
            hits += std::uint64_t(std::popcount(m));
        }
    set_counters<W>(state, hits);
}

template <class T, int W, class Mode> void BM_packet_verdict(benchmark::State& state) {
    const auto& w = Workload<T, W>::get();
    std::uint64_t hits = 0;
    for (auto _ : state)
        for (int k = 0; k < kN; ++k) {
            const std::uint32_t m = verdict(w.rays[std::size_t(k)], w.packets[std::size_t(k)], Mode{});
            benchmark::DoNotOptimize(m);
            hits += std::uint64_t(std::popcount(m));
        }
    set_counters<W>(state, hits);
}

// The certified verdict's own work without the entry point's floating-point environment
// check (detail::packet::certified_verdict: the same lanes and fallback; the default
// environment holds here): the share of the MXCSR read in the public form's time.
template <class T, int W> void BM_packet_verdict_certified_unguarded(benchmark::State& state) {
    const auto& w = Workload<T, W>::get();
    std::uint64_t hits = 0;
    for (auto _ : state)
        for (int k = 0; k < kN; ++k) {
            const std::uint32_t m =
                detail::packet::certified_verdict<detail::simd::native>(w.rays[std::size_t(k)], w.packets[std::size_t(k)]);
            benchmark::DoNotOptimize(m);
            hits += std::uint64_t(std::popcount(m));
        }
    set_counters<W>(state, hits);
}

// The certified verdict in an FpEnvScope (fp_env_scope.hpp): the scope made once, outside
// the loop, as an embedder's BVH traversal would; each packet query then reads no control
// state.
template <class T, int W> void BM_packet_verdict_certified_scoped(benchmark::State& state) {
    const auto& w = Workload<T, W>::get();
    std::uint64_t hits = 0;
    const FpEnvScope env;
    for (auto _ : state)
        for (int k = 0; k < kN; ++k) {
            const std::uint32_t m = verdict(w.rays[std::size_t(k)], w.packets[std::size_t(k)], certified, env);
            benchmark::DoNotOptimize(m);
            hits += std::uint64_t(std::popcount(m));
        }
    set_counters<W>(state, hits);
}

template <class T, int W> void BM_packet_intersect_certified(benchmark::State& state) {
    const auto& w = Workload<T, W>::get();
    std::uint64_t hits = 0;
    for (auto _ : state)
        for (int k = 0; k < kN; ++k) {
            const PacketHit<T, W> h = intersect(w.rays[std::size_t(k)], w.packets[std::size_t(k)], certified);
            benchmark::DoNotOptimize(h);
            hits += std::uint64_t(std::popcount(h.mask));
        }
    set_counters<W>(state, hits);
}

#if RAYPROOF_BENCH_HAVE_EMBREE
// One Embree scene per packet of the float, W = 8 workload (see the head of the file).
class EmbreeBoxes {
public:
    static constexpr int W = 8;
    EmbreeBoxes() : device_(rtcNewDevice("threads=1")) {
        if (!device_) throw std::runtime_error("embree: rtcNewDevice failed");
        const auto& w = Workload<float, W>::get();
        for (const AabbPacket<float, W>& p : w.packets) {
            RTCScene scene = rtcNewScene(device_);
            RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
            rtcSetGeometryUserPrimitiveCount(g, W);
            rtcSetGeometryUserData(g, const_cast<AabbPacket<float, W>*>(&p));
            rtcSetGeometryBoundsFunction(g, &bounds, nullptr);
            rtcSetGeometryIntersectFunction(g, &count_calls);
            rtcCommitGeometry(g);
            rtcAttachGeometry(scene, g);
            rtcReleaseGeometry(g);
            rtcCommitScene(scene);
            scenes_.push_back(scene);
        }
    }
    ~EmbreeBoxes() {
        for (RTCScene s : scenes_) rtcReleaseScene(s);
        rtcReleaseDevice(device_);
    }
    EmbreeBoxes(const EmbreeBoxes&) = delete;
    EmbreeBoxes& operator=(const EmbreeBoxes&) = delete;
    static const EmbreeBoxes& get() {
        static const EmbreeBoxes e;
        return e;
    }
    RTCScene scene(int k) const { return scenes_[std::size_t(k)]; }
    // Calls of the primitive callback (boxes Embree's traversal hit) since the last read.
    static std::uint64_t take_calls() {
        const std::uint64_t c = calls_;
        calls_ = 0;
        return c;
    }

private:
    static void bounds(const RTCBoundsFunctionArguments* a) {
        const auto* p = static_cast<const AabbPacket<float, W>*>(a->geometryUserPtr);
        const unsigned i = a->primID;
        *a->bounds_o = RTCBounds{p->lo[0][i], p->lo[1][i], p->lo[2][i], 0, p->hi[0][i], p->hi[1][i], p->hi[2][i], 0};
    }
    static void count_calls(const RTCIntersectFunctionNArguments* a) {
        for (unsigned i = 0; i < a->N; ++i) calls_ += a->valid[i] == -1;
    }
    static inline std::uint64_t calls_ = 0;
    RTCDevice device_;
    std::vector<RTCScene> scenes_;
};

void BM_embree_intersect1(benchmark::State& state) {
    const auto& w = Workload<float, 8>::get();
    const EmbreeBoxes& e = EmbreeBoxes::get();
    EmbreeBoxes::take_calls();
    for (auto _ : state)
        for (int k = 0; k < kN; ++k) {
            const Ray<float>& r = w.raw[std::size_t(k)];
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            RTCRayHit rh{};
            rh.ray.org_x = r.origin[0];
            rh.ray.org_y = r.origin[1];
            rh.ray.org_z = r.origin[2];
            rh.ray.dir_x = r.direction[0];
            rh.ray.dir_y = r.direction[1];
            rh.ray.dir_z = r.direction[2];
            rh.ray.tnear = 0;
            rh.ray.tfar = r.t_max;
            rh.ray.mask = ~0u;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(e.scene(k), &context, &rh);
            benchmark::DoNotOptimize(rh);
        }
    set_counters<8>(state, EmbreeBoxes::take_calls());
}

void BM_embree_intersect8(benchmark::State& state) {
    const auto& w = Workload<float, 8>::get();
    const EmbreeBoxes& e = EmbreeBoxes::get();
    alignas(32) int valid[8];
    for (int& v : valid) v = -1;
    EmbreeBoxes::take_calls();
    for (auto _ : state)
        for (int k = 0; k < kN; k += 8) {
            // Rays k..k+7 against the scene of packet k: 8 rays · W boxes per call, so the
            // time per call is divided as for 8 calls of one ray each.
            alignas(32) RTCRayHit8 rh{};
            for (int j = 0; j < 8; ++j) {
                const Ray<float>& r = w.raw[std::size_t(k + j)];
                rh.ray.org_x[j] = r.origin[0];
                rh.ray.org_y[j] = r.origin[1];
                rh.ray.org_z[j] = r.origin[2];
                rh.ray.dir_x[j] = r.direction[0];
                rh.ray.dir_y[j] = r.direction[1];
                rh.ray.dir_z[j] = r.direction[2];
                rh.ray.tnear[j] = 0;
                rh.ray.tfar[j] = r.t_max;
                rh.ray.mask[j] = ~0u;
                rh.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
            }
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            rtcIntersect8(valid, e.scene(k), &context, &rh);
            benchmark::DoNotOptimize(rh);
        }
    set_counters<8>(state, EmbreeBoxes::take_calls());
}
BENCHMARK(BM_embree_intersect1);
BENCHMARK(BM_embree_intersect8);
#endif

#define RAYPROOF_PACKET_BENCH(T, W)                                          \
    BENCHMARK(BM_soa_slab<T, W>);                                            \
    BENCHMARK(BM_packet_verdict<T, W, fast_t>);                              \
    BENCHMARK(BM_packet_verdict<T, W, certified_t>);                         \
    BENCHMARK(BM_packet_verdict_certified_unguarded<T, W>);                  \
    BENCHMARK(BM_packet_verdict_certified_scoped<T, W>);                     \
    BENCHMARK(BM_packet_intersect_certified<T, W>);
RAYPROOF_PACKET_BENCH(float, 8)
RAYPROOF_PACKET_BENCH(double, 4)
RAYPROOF_PACKET_BENCH(double, 8)

}  // namespace

BENCHMARK_MAIN();
