// bench/bench_main.cpp — the speed half of the trade: every shape × scalar type ×
// workload × method (scalar) and the batch sweep, as Google Benchmark runs. Built with
// RAYPROOF_BENCH_BATCH_SUFFIX (rayproof_batch_bench_avx2), the lane batches alone.
//   rayproof_bench [benchmark flags] [--cases=N] [--cgal_cases=N] [--batch_max=N] [--seed=S]
//                  [--watchdog=SECONDS] [--fixed_order]
#include "bench_common.hpp"
#include "bench_cli.hpp"

#include <string>

namespace rayproof::bench {

Options& options() {
    static Options o;
    return o;
}

}  // namespace rayproof::bench

int main(int argc, char** argv) {
    using namespace rayproof;
    using namespace rayproof::bench;
    Options& o = options();
    CLI::App app{"Times every shape, scalar type, workload and method, scalar and in batches.", "rayproof_bench"};
    app.option_defaults()->always_capture_default();
    app.add_option("--cases", o.cases, "cases per workload (the timed pass)")->check(cli::positive);
    app.add_option("--cgal_cases", o.cgal_cases, "cases timed for the CGAL baselines (at most --cases)")
        ->check(cli::non_negative);
    app.add_option("--batch_max", o.batch_max, "the largest batch of the batch sweep")->check(cli::positive);
    app.add_option("--seed", o.seed, "the workloads' seed (decimal or 0x hex)")->check(cli::non_negative);
    app.add_flag("--fixed_order", o.fixed_order,
                 "time every pass over the cases in one order (default: a new random order per pass)");
    app.add_option("--watchdog", o.watchdog, "the deadline of each method's untimed check pass, seconds (0: none)")
        ->check(cli::non_negative);
    if (const auto stop = parse_command_line(app, argc, argv)) return *stop;
    o.cgal_cases = std::min(o.cgal_cases, o.cases);
    benchmark::AddCustomContext("cases", std::to_string(options().cases));
    benchmark::AddCustomContext("cgal_cases", std::to_string(options().cgal_cases));
    benchmark::AddCustomContext("seed", std::to_string(options().seed));
    benchmark::AddCustomContext("order", options().fixed_order ? "fixed" : "shuffled per pass");
#ifdef RAYPROOF_BENCH_BATCH_SUFFIX
    // Built for another instruction set (bench/CMakeLists.txt): the lane batches alone
    // (the certified Aabb's and plane's), their mode named with the suffix.
    register_batch<double, Aabb<double>>(RAYPROOF_BENCH_BATCH_SUFFIX, true);
    register_batch<float, Aabb<float>>(RAYPROOF_BENCH_BATCH_SUFFIX, true);
    register_batch<double, Plane<double>>(RAYPROOF_BENCH_BATCH_SUFFIX, true);
    register_batch<float, Plane<float>>(RAYPROOF_BENCH_BATCH_SUFFIX, true);
#else
    register_aabb();
    register_obb();
    register_plane();
    register_sphere();
    register_polyhedron();
    register_fp_env();
#ifdef RAYPROOF_BENCH_HAVE_CGAL
    register_cgal();
#endif
#ifdef RAYPROOF_BENCH_HAVE_EMBREE
    register_embree();
#endif
#endif
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
