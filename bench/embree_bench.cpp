// bench/embree_bench.cpp — Embree's rtcIntersect1 on one-sphere scenes, timed on the
// same Sphere<float> cases as the kernel (see embree_sphere.hpp for the adapter).
#include "bench_common.hpp"
#include "embree_sphere.hpp"

namespace rayproof::bench {
namespace {
// The scenes of a workload's timed cases, built on first use and kept.
const EmbreeSpheres& scenes(const std::string& workload_name, bool robust) {
    static std::map<std::pair<std::string, bool>, std::unique_ptr<EmbreeSpheres>> cache;
    auto& slot = cache[{workload_name, robust}];
    if (!slot) {
        const auto& cases = timed_cases<float, Sphere<float>>(workload_name);
        std::vector<Sphere<float>> spheres;
        spheres.reserve(cases.size());
        for (const auto& c : cases) spheres.push_back(c.shape);
        slot = std::make_unique<EmbreeSpheres>(spheres, robust);
    }
    return *slot;
}

void time_embree(benchmark::State& st, const std::string& w, bool robust) {
    const auto& cases = timed_cases<float, Sphere<float>>(w);
    // The check pass builds its own scenes in the child (Embree's threads do not fork).
    const std::string key = bench_name<float, Sphere<float>>("scalar", w, robust ? "embree_robust" : "embree");
    if (!passes_watchdog(st, key, 1, [&](std::size_t) {
            const EmbreeSpheres& es = scenes(w, robust);
            for (std::size_t i = 0; i < cases.size(); ++i) benchmark::DoNotOptimize(es.intersect(i, cases[i].ray));
        }))
        return;
    const EmbreeSpheres& es = scenes(w, robust);
    std::vector<Hit<float>> out(cases.size());
    // Each pass in a new order, as time_scalar's (bench_common.hpp); case i's scene is
    // scene i, so what is shuffled is the indices.
    std::vector<std::uint32_t> indices(cases.size());
    for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = std::uint32_t(i);
    ShuffledCases<std::uint32_t> order(indices, indices.size(), key);
    const std::uint32_t* k = order.data();
    for (auto _ : st) {
        st.PauseTiming();
        order.shuffle();
        st.ResumeTiming();
        for (std::size_t i = 0; i < order.size(); ++i) out[i] = es.intersect(k[i], cases[k[i]].ray);
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    std::int64_t hits = 0;
    for (const auto& h : out) hits += h.verdict == Verdict::hit;
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(cases.size()));
    st.counters["cases"] = double(cases.size());
    st.counters["hit_rate"] = double(hits) / double(cases.size());
}
}  // namespace

void register_embree() {
    for (const std::string_view wv : kWorkloads) {
        const std::string w(wv);
        benchmark::RegisterBenchmark(bench_name<float, Sphere<float>>("scalar", w, "embree").c_str(),
                                     [w](benchmark::State& st) { time_embree(st, w, false); });
        benchmark::RegisterBenchmark(bench_name<float, Sphere<float>>("scalar", w, "embree_robust").c_str(),
                                     [w](benchmark::State& st) { time_embree(st, w, true); });
    }
}
}  // namespace rayproof::bench
