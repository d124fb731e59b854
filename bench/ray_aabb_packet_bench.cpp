// bench/ray_aabb_packet_bench.cpp — the box packets (ray_aabb_packet.hpp) against the
// branch-free structure-of-arrays slab loop (baselines.hpp, soa_slab) over the same
// boxes: ns per box test of verdict() in fast and certified mode, float W = 8, double
// W = 4 and 8, plus the certified intersect().
//
// Workload ("uniform"): 1024 packets of boxes with lower corners uniform in [-2, 2]^3
// and extents uniform in [0, 1.5] per axis, and 1024 prepared rays with origins uniform
// in [-4, 4]^3, ray k aimed at a point uniform in one of packet k's boxes (box k mod W),
// so that each packet has a hit and its neighbours are hit at random (the counter
// hit_rate says how many box tests hit), seeded; ray k is tested against packet k. The
// reciprocals are computed outside the timed loop for every method (PreparedRay for the
// packets, 1/d for the baseline).
// Each benchmark iteration makes kPasses passes over the 1024 pairs, each pass in its own
// random order, the orders drawn anew outside the timed region before every iteration
// (every method draws the same orders). Over the same pairs in the same order call after
// call, the branch predictor learns each pair's outcomes (which lanes the filter leaves
// undecided, which the fast lanes hit) and branchy code is timed as if random rays were
// predictable, as the scalar tables found (bench_common.hpp); a random order keeps the
// pairs in the cache (float W = 8: 1024 packets of 192 bytes) and takes the learned
// outcomes away. The orders are read through one index per call, in every method.
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

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <stdexcept>
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

constexpr int kPasses = 16;

// kPasses random orders of the indices 0..n-1, one after another; shuffle() draws new
// ones. Seeded: every method, in every run, sees the same sequence of orders.
class Orders {
public:
    explicit Orders(int n) : n_(n), index_(std::size_t(n) * kPasses), rng_(20261206) {
        for (int p = 0; p < kPasses; ++p) std::iota(begin(p), begin(p) + n_, 0);
    }
    void shuffle() {
        for (int p = 0; p < kPasses; ++p) std::shuffle(begin(p), begin(p) + n_, rng_);
    }
    const std::vector<int>& all() const { return index_; }

private:
    std::vector<int>::iterator begin(int p) { return index_.begin() + std::ptrdiff_t(p) * n_; }
    int n_;
    std::vector<int> index_;
    std::mt19937_64 rng_;
};

// Times call(k), which returns how many of its box tests hit, over kPasses shuffled
// passes per iteration (the shuffle untimed); calls counts the calls one pass makes.
template <int W, class F> void time_calls(benchmark::State& state, int calls, F call) {
    Orders order(calls);
    std::uint64_t hits = 0;
    for (auto _ : state) {
        state.PauseTiming();
        order.shuffle();
        state.ResumeTiming();
        for (const int k : order.all()) hits += call(k);
    }
    const double boxes = double(state.iterations()) * kPasses * kN * W;
    state.counters["ns_per_box"] = benchmark::Counter(boxes, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["hit_rate"] = double(hits) / boxes;
}

template <class T, int W> void BM_soa_slab(benchmark::State& state) {
    const auto& w = Workload<T, W>::get();
    time_calls<W>(state, kN, [&](int k) {
        const Ray<T>& r = w.raw[std::size_t(k)];
        const std::uint32_t m = bench::baseline::soa_slab<T, W>(r.origin.data(), w.inv[std::size_t(k)].data(),
                                                                w.packets[std::size_t(k)].lo,
                                                                w.packets[std::size_t(k)].hi, r.t_min, r.t_max);
        benchmark::DoNotOptimize(m);
        return std::popcount(m);
    });
}

template <class T, int W, class Mode> void BM_packet_verdict(benchmark::State& state) {
    const auto& w = Workload<T, W>::get();
    time_calls<W>(state, kN, [&](int k) {
        const std::uint32_t m = verdict(w.rays[std::size_t(k)], w.packets[std::size_t(k)], Mode{});
        benchmark::DoNotOptimize(m);
        return std::popcount(m);
    });
}

// The certified verdict's own work without the entry point's floating-point environment
// check (detail::packet::certified_verdict: the same lanes and fallback; the default
// environment holds here): the share of the MXCSR read in the public form's time.
template <class T, int W> void BM_packet_verdict_certified_unguarded(benchmark::State& state) {
    const auto& w = Workload<T, W>::get();
    time_calls<W>(state, kN, [&](int k) {
        const std::uint32_t m =
            detail::packet::certified_verdict<detail::simd::native>(w.rays[std::size_t(k)], w.packets[std::size_t(k)]);
        benchmark::DoNotOptimize(m);
        return std::popcount(m);
    });
}

// The certified verdict in an FpEnvScope (fp_env_scope.hpp): the scope made once, outside
// the loop, as an embedder's BVH traversal would; each packet query then reads no control
// state.
template <class T, int W> void BM_packet_verdict_certified_scoped(benchmark::State& state) {
    const auto& w = Workload<T, W>::get();
    const FpEnvScope env;
    time_calls<W>(state, kN, [&](int k) {
        const std::uint32_t m = verdict(w.rays[std::size_t(k)], w.packets[std::size_t(k)], certified, env);
        benchmark::DoNotOptimize(m);
        return std::popcount(m);
    });
}

template <class T, int W> void BM_packet_intersect_certified(benchmark::State& state) {
    const auto& w = Workload<T, W>::get();
    time_calls<W>(state, kN, [&](int k) {
        const PacketHit<T, W> h = intersect(w.rays[std::size_t(k)], w.packets[std::size_t(k)], certified);
        benchmark::DoNotOptimize(h);
        return std::popcount(h.mask);
    });
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

// Embree's hits are its callback's calls, not a mask: the counter is set from them.
void set_embree_hit_rate(benchmark::State& state) {
    state.counters["hit_rate"] =
        double(EmbreeBoxes::take_calls()) / (double(state.iterations()) * kPasses * kN * EmbreeBoxes::W);
}

void BM_embree_intersect1(benchmark::State& state) {
    const auto& w = Workload<float, 8>::get();
    const EmbreeBoxes& e = EmbreeBoxes::get();
    EmbreeBoxes::take_calls();
    time_calls<8>(state, kN, [&](int k) {
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
        return 0;
    });
    set_embree_hit_rate(state);
}

void BM_embree_intersect8(benchmark::State& state) {
    const auto& w = Workload<float, 8>::get();
    const EmbreeBoxes& e = EmbreeBoxes::get();
    alignas(32) int valid[8];
    for (int& v : valid) v = -1;
    EmbreeBoxes::take_calls();
    // Call g: rays 8g..8g+7 against the scene of packet 8g, 8 rays · W boxes per call (so
    // a pass's kN / 8 calls make as many box tests as the one-ray passes).
    time_calls<8>(state, kN / 8, [&](int g) {
        const int k = 8 * g;
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
        return 0;
    });
    set_embree_hit_rate(state);
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
