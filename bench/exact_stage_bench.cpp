// bench/exact_stage_bench.cpp — how often the certified mode needs its exact stage, per
// shape × scalar type × generator (this program alone is built with RAYPROOF_COUNTERS=1;
// its timings include the counting and are not the reference ones, rayproof_bench is).
//
// For each generator of the shared registry, the first `count_cases` cases of its seeded
// sequence (`count_cases_uniform` for `general`, the uniform workload: the same sequence
// whose first cases rayproof_bench times) are answered once in certified mode with the
// counters reset; the benchmark then reports
//   exact_rate   certified queries that needed the exact stage / certified queries
//   exact        that number of queries,  queries  the certified queries counted
// (invalid input is answered before the certified code and is not counted), and times
// the first `cases` cases.
//   rayproof_bench_counters [benchmark flags] [--cases=N] [--count_cases=N]
//                           [--count_cases_uniform=N] [--seed=S] [--watchdog=SECONDS]
#include "bench_cli.hpp"
#include "watchdog.hpp"
#include "workloads.hpp"

#include <benchmark/benchmark.h>

#include <map>
#include <string>
#include <vector>

#ifndef RAYPROOF_COUNTERS
#error "rayproof_bench_counters is built with RAYPROOF_COUNTERS=1"
#endif

namespace rayproof::bench {
namespace {

struct CountOptions {
    std::size_t cases = 4096;
    std::size_t count_cases = 1 << 16;
    std::size_t count_cases_uniform = 1 << 20;
    std::uint64_t seed = kDefaultSeed;
    double watchdog = 120;  // seconds for the counting pass of one generator
} opts;

struct Counts {
    unsigned long long queries = 0, exact = 0;
    std::string error;  // the counting pass hung or crashed
};

// The counting pass runs in a child process with a deadline (see watchdog.hpp), so that
// a case on which the certified mode hangs is named instead of stopping the run.
template <class T, class Shape> Counts count(std::string_view generator) {
    static std::map<std::string, Counts> cache;
    const auto it = cache.find(std::string(generator));
    if (it != cache.end()) return it->second;
    const std::size_t n = generator == "general" ? opts.count_cases_uniform : opts.count_cases;
    const auto* g = gen::find_generator<T, Shape>(generator);
    Watchdog w;
    Counts r;
    const bool ok = w.run(
        opts.watchdog,
        [&](Watchdog::Shared& s) {
            gen::Rng rng = seeded_rng<T, Shape>(generator, opts.seed);
            auto& c = rayproof::detail::exact_stage_counters;
            c = {};
            for (std::size_t i = 0; i < n; ++i) {
                s.progress = i;
                const auto k = g->make(rng);
                benchmark::DoNotOptimize(intersect(k.ray, k.shape, rayproof::certified));
            }
            s.value[0] = c.queries;
            s.value[1] = c.exact;
        },
        r.error);
    if (ok) {
        r.queries = w.shared().value[0];
        r.exact = w.shared().value[1];
    }
    cache[std::string(generator)] = r;
    return r;
}

template <class T, class Shape> void run(benchmark::State& st, std::string_view generator) {
    const Counts c = count<T, Shape>(generator);
    if (!c.error.empty()) {
        st.SkipWithError(c.error.c_str());
        return;
    }
    const auto cases = generator_cases<T, Shape>(generator, opts.cases, opts.seed);
    std::vector<Hit<T>> out(cases.size());
    for (auto _ : st) {
        for (std::size_t i = 0; i < cases.size(); ++i) out[i] = intersect(cases[i].ray, cases[i].shape, rayproof::certified);
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(cases.size()));
    st.counters["queries"] = double(c.queries);
    st.counters["exact"] = double(c.exact);
    st.counters["exact_rate"] = c.queries ? double(c.exact) / double(c.queries) : 0.0;
}

template <class T, class Shape> void register_all() {
    for (const auto& g : gen::generators<T, Shape>()) {
        const std::string name = "exact_stage/" + std::string(gen::shape_name<Shape>()) + "/" +
                                 std::string(gen::scalar_name<T>()) + "/" + std::string(g.name);
        const std::string_view generator = g.name;
        benchmark::RegisterBenchmark(name.c_str(), [generator](benchmark::State& st) { run<T, Shape>(st, generator); });
    }
}

}  // namespace
}  // namespace rayproof::bench

int main(int argc, char** argv) {
    using namespace rayproof;
    using namespace rayproof::bench;
    CLI::App app{"How often the certified mode needs its exact stage, per shape, scalar type and generator.",
                 "rayproof_bench_counters"};
    app.option_defaults()->always_capture_default();
    app.add_option("--cases", opts.cases, "cases timed per generator")->check(cli::positive);
    app.add_option("--count_cases", opts.count_cases, "cases counted per generator")->check(cli::non_negative);
    app.add_option("--count_cases_uniform", opts.count_cases_uniform, "cases counted for `general` (uniform)")
        ->check(cli::non_negative);
    app.add_option("--seed", opts.seed, "the generators' seed (decimal or 0x hex)")->check(cli::non_negative);
    app.add_option("--watchdog", opts.watchdog, "the deadline of each generator's counting pass, seconds")
        ->check(cli::non_negative);
    if (const auto stop = parse_command_line(app, argc, argv)) return *stop;
    benchmark::AddCustomContext("seed", std::to_string(opts.seed));
    register_all<double, Aabb<double>>();
    register_all<float, Aabb<float>>();
    register_all<double, Obb<double>>();
    register_all<float, Obb<float>>();
    register_all<double, Plane<double>>();
    register_all<float, Plane<float>>();
    register_all<double, Sphere<double>>();
    register_all<float, Sphere<float>>();
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
