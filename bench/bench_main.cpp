// bench/bench_main.cpp — the speed half of the trade: every shape × scalar type ×
// workload × method (scalar) and the batch sweep, as Google Benchmark runs.
//   rayproof_bench [benchmark flags] [--cases=N] [--cgal_cases=N] [--batch_max=N] [--seed=S]
//                  [--watchdog=SECONDS]
#include "bench_common.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace rayproof::bench {

Options& options() {
    static Options o;
    return o;
}

bool parse_options(int& argc, char** argv) {
    int kept = 1;
    for (int i = 1; i < argc; ++i) {
        const char* a = argv[i];
        auto value = [&](const char* flag) -> const char* {
            const std::size_t n = std::strlen(flag);
            return std::strncmp(a, flag, n) == 0 && a[n] == '=' ? a + n + 1 : nullptr;
        };
        if (const char* v = value("--cases")) {
            options().cases = std::strtoull(v, nullptr, 10);
        } else if (const char* v = value("--cgal_cases")) {
            options().cgal_cases = std::strtoull(v, nullptr, 10);
        } else if (const char* v = value("--batch_max")) {
            options().batch_max = std::strtoull(v, nullptr, 10);
        } else if (const char* v = value("--watchdog")) {
            options().watchdog = std::strtod(v, nullptr);
        } else if (const char* v = value("--seed")) {
            options().seed = std::strtoull(v, nullptr, 0);
        } else {
            argv[kept++] = argv[i];
        }
    }
    argc = kept;
    if (options().cases == 0 || options().batch_max == 0) return false;
    options().cgal_cases = std::min(options().cgal_cases, options().cases);
    return true;
}

}  // namespace rayproof::bench

int main(int argc, char** argv) {
    using namespace rayproof::bench;
    benchmark::Initialize(&argc, argv);
    if (!parse_options(argc, argv) || benchmark::ReportUnrecognizedArguments(argc, argv)) {
        std::fprintf(stderr, "usage: %s [benchmark flags] [--cases=N] [--cgal_cases=N] [--batch_max=N] [--seed=S]\n"
                     "       [--watchdog=SECONDS]  (the deadline of each method's untimed check pass; 0: none)\n",
                     argv[0]);
        return 2;
    }
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
