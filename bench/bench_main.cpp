// bench/bench_main.cpp — the speed half of the trade: every shape × scalar type ×
// workload × method (scalar) and the batch sweep, as Google Benchmark runs.
//   rayproof_bench [benchmark flags] [--cases=N] [--cgal_cases=N] [--batch_max=N] [--seed=S]
//                  [--watchdog=SECONDS]
#include "bench_common.hpp"
#include "flags.hpp"

#include <string>

namespace rayproof::bench {

Options& options() {
    static Options o;
    return o;
}

bool parse_options(int& argc, char** argv) {
    Options& o = options();
    take_flags(argc, argv,
               {count_flag("--cases", o.cases), count_flag("--cgal_cases", o.cgal_cases),
                count_flag("--batch_max", o.batch_max), seconds_flag("--watchdog", o.watchdog),
                seed_flag("--seed", o.seed)});
    if (o.cases == 0 || o.batch_max == 0) return false;
    o.cgal_cases = std::min(o.cgal_cases, o.cases);
    return true;
}

}  // namespace rayproof::bench

int main(int argc, char** argv) {
    using namespace rayproof::bench;
    benchmark::Initialize(&argc, argv);
    if (!parse_options(argc, argv) || benchmark::ReportUnrecognizedArguments(argc, argv))
        return usage_error(argv[0],
                           "[--cases=N] [--cgal_cases=N] [--batch_max=N] [--seed=S]\n"
                           "       [--watchdog=SECONDS]  (the deadline of each method's untimed check pass; 0: none)\n");
    benchmark::AddCustomContext("cases", std::to_string(options().cases));
    benchmark::AddCustomContext("cgal_cases", std::to_string(options().cgal_cases));
    benchmark::AddCustomContext("seed", std::to_string(options().seed));
    register_aabb();
    register_obb();
    register_plane();
    register_sphere();
#ifdef RAYPROOF_BENCH_HAVE_CGAL
    register_cgal();
#endif
#ifdef RAYPROOF_BENCH_HAVE_EMBREE
    register_embree();
#endif
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
