// bench/cgal_bench.cpp — CGAL's exact do_intersect (Epeck, plain rationals) timed on the
// same cases as the kernel (the first `cgal_cases` of each workload); the CGAL code
// itself is compiled apart (cgal_baselines.cpp), this file includes no CGAL.
#include "bench_common.hpp"
#include "cgal_baselines.hpp"

namespace rayproof::bench {
namespace {
template <class T> Hit<T> verdict_only(bool hit) {
    Hit<T> h;
    h.verdict = hit ? Verdict::hit : Verdict::miss;
    return h;
}

template <class T, class Shape> void register_one(std::string_view workload_name) {
    const std::string w(workload_name);
    const std::string epeck = bench_name<T, Shape>("scalar", w, "cgal_epeck");
    benchmark::RegisterBenchmark(epeck.c_str(), [epeck, w](benchmark::State& st) {
        time_scalar<T, Shape>(st, epeck, w, options().cgal_cases,
                              [](const Ray<T>& r, const Shape& s) { return verdict_only<T>(cgal::epeck(r, kernel_shape(s))); });
    });
    const std::string rational = bench_name<T, Shape>("scalar", w, "cgal_rational");
    benchmark::RegisterBenchmark(rational.c_str(), [rational, w](benchmark::State& st) {
        time_scalar<T, Shape>(st, rational, w, options().cgal_cases,
                              [](const Ray<T>& r, const Shape& s) { return verdict_only<T>(cgal::rational(r, kernel_shape(s))); });
    });
}

// Epeck over the certified verdict query in pairs, on the cases both are timed on.
template <class T, class Shape> void register_paired() {
    benchmark::RegisterBenchmark(
        bench_name<T, Shape>("paired", "uniform", "epeck_over_certified_verdict").c_str(), [](benchmark::State& st) {
            time_pair<T, Shape>(
                st, options().cgal_cases, bench_name<T, Shape>("scalar", "uniform", "certified_verdict"),
                [](const Ray<T>& r, const Shape& s) RAYPROOF_BENCH_INLINE { return certified_verdict_hit<T>(r, s); },
                bench_name<T, Shape>("scalar", "uniform", "cgal_epeck"),
                [](const Ray<T>& r, const Shape& s) { return verdict_only<T>(cgal::epeck(r, kernel_shape(s))); });
        });
}

template <template <class> class S> void register_shape_cgal() {
    register_paired<double, S<double>>();
    register_paired<float, S<float>>();
    for (const std::string_view w : kWorkloads) {
        if (!has_workload<S<float>>(w)) continue;
        register_one<double, S<double>>(w);
        register_one<float, S<float>>(w);
    }
}
}  // namespace

void register_cgal() {
    register_shape_cgal<Aabb>();
    register_shape_cgal<Plane>();
    register_shape_cgal<Sphere>();
    register_shape_cgal<gen::OwnedPolyhedron>();
}
}  // namespace rayproof::bench
