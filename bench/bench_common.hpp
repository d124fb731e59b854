// bench/bench_common.hpp — the timing harness shared by the per-shape benchmark files.
//
// Names (parsed by the report):
//   scalar/<shape>/<float|double>/<workload>/<method>   one query per case, each case its
//                                                       own shape; items = queries
//   batch/<shape>/<float|double>/<mode>/<rays>          intersect(span, shape, mode, out)
//                                                       on one shape; items = rays
//   paired/<shape>/<float|double>/uniform/certified_over_fast
//                                                       the ratio certified / fast measured
//                                                       in pairs (counter "ratio")
//   paired/<shape>/<float|double>/uniform/fast_over_textbook
//   paired/<shape>/<float|double>/uniform/conservative_over_fast
//   paired/<shape>/<float|double>/grazing/certified_over_fast
//                                                       the ladder of issue #17's targets,
//                                                       each ratio in pairs likewise
//                                                       (counters a_ns and b_ns: each half's
//                                                       ns per query, medians over the pairs)
//   paired/<shape>/<float|double>/uniform/epeck_over_certified_verdict
//                                                       CGAL Epeck's do_intersect over the
//                                                       certified verdict query, in pairs
//   fpenv/<shape>/<float|double>/<mode>/{guard,foreign}  the floating-point environment
//                                                       guard's cost, in pairs (fp_env_bench.cpp)
//   prepared/aabb/<float|double>/<method>/{ray,prepared} one ray against many boxes, as a
//                                                       Ray or prepared once (ray_aabb_bench.cpp)
// Methods: the kernel's modes fast, conservative, certified, and certified_verdict (the
// verdict query alone, rayproof::verdict in certified mode); the baselines textbook,
// branchless (boxes), cgal_epeck, cgal_rational (Aabb, Plane, Sphere, polyhedron), embree
// and embree_robust (Sphere<float>). A polyhedron's shape name is "polyhedron"; its cases
// own their planes and every method is handed kernel_shape() of them (workloads.hpp).
//
// The scalar loop answers the first `cases` cases of a workload (same seed, same cases
// for every method: the accuracy tool judges these very rays) into an output array, as
// an application would; ns per query = time per pass / cases.
// Every pass, timed or not, runs over the cases in a fresh random order (shuffled
// outside the timed region; --fixed_order keeps one order for every pass). Over the same
// 4096 cases in the same order pass after pass, the processor's branch predictor
// learns each case's outcomes, and branchy code is timed as if random rays were
// predictable: the textbook plane took 2.5 ns per query so, 11 ns shuffled, and the
// textbook box 25 against 40 ns, while branch-free code kept its time. Random rays do not
// repeat in an application; a shuffled order keeps the cases in the cache (4096 cases
// are under half a megabyte) and takes the learned outcomes away.
#pragma once

#include "baselines.hpp"
#include "watchdog.hpp"
#include "workloads.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace rayproof::bench {

struct Options {
    std::size_t cases = 4096;          // cases per scalar benchmark (the timed set)
    std::size_t cgal_cases = 4096;     // the prefix of it timed for the CGAL baselines
    std::size_t batch_max = 1000000;   // the largest batch (sizes 1, 10, ..., batch_max)
    std::uint64_t seed = kDefaultSeed;
    double watchdog = 60;  // seconds for the untimed check pass of each method (0: none)
    bool fixed_order = false;  // every pass over the cases in one order (see above)
};
Options& options();  // set from the command line by main (bench_main.cpp)

template <class T, class Shape> std::string bench_name(const char* kind, std::string_view a, std::string_view b) {
    return std::string(kind) + "/" + std::string(gen::shape_name<Shape>()) + "/" + std::string(gen::scalar_name<T>()) +
           "/" + std::string(a) + "/" + std::string(b);
}

// The workload's timed cases, built on first use and kept.
template <class T, class Shape> const std::vector<Case<T, Shape>>& timed_cases(const std::string& workload_name) {
    static std::map<std::string, std::unique_ptr<std::vector<Case<T, Shape>>>> cache;
    auto& slot = cache[workload_name];
    if (!slot)
        slot = std::make_unique<std::vector<Case<T, Shape>>>(
            workload<T, Shape>(workload_name, options().cases, options().seed));
    return *slot;
}

// Before a method is timed, one untimed pass over its cases runs in a child process
// with a deadline (once per benchmark): a method that hangs or crashes on some case is
// reported as the benchmark's error, naming the case, and is not timed.
template <class F> bool passes_watchdog(benchmark::State& st, const std::string& key, std::size_t n, F pass) {
    if (options().watchdog <= 0) return true;
    static std::map<std::string, std::string> verdicts;  // key -> "" (fine) or what happened
    auto it = verdicts.find(key);
    if (it == verdicts.end()) {
        Watchdog w;
        std::string why;
        const bool ok = w.run(
            options().watchdog,
            [&](Watchdog::Shared& s) {
                for (std::size_t i = 0; i < n; ++i) {
                    s.progress = i;
                    pass(i);
                }
            },
            why);
        it = verdicts.emplace(key, ok ? std::string() : why).first;
    }
    if (it->second.empty()) return true;
    st.SkipWithError(it->second.c_str());
    return false;
}

// A copy of the first n timed cases (or of their indices), put in a new random order by
// shuffle() before each pass (a no-op under --fixed_order). Seeded by the workloads' seed and the benchmark's
// name: a run is reproducible, and each benchmark draws its own orders.
template <class Case> class ShuffledCases {
public:
    ShuffledCases(const std::vector<Case>& all, std::size_t n, const std::string& key)
        : cases_(all.begin(), all.begin() + std::ptrdiff_t(std::min(n, all.size()))), rng_(seed_for(key)) {}
    void shuffle() {
        if (!options().fixed_order) std::shuffle(cases_.begin(), cases_.end(), rng_);
    }
    const Case* data() const { return cases_.data(); }
    std::size_t size() const { return cases_.size(); }

private:
    static std::uint64_t seed_for(const std::string& key) {
        std::uint64_t h = options().seed;
        for (const char c : key) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ull;  // FNV-1a steps
        return h;
    }
    std::vector<Case> cases_;
    std::mt19937_64 rng_;
};

// Times f(ray, shape) -> Hit<T> over the first n timed cases of the workload, each pass
// in a new order (the shuffle outside the timed region).
template <class T, class Shape, class F>
void time_scalar(benchmark::State& st, const std::string& key, const std::string& workload_name, std::size_t n, F f) {
    const auto& all = timed_cases<T, Shape>(workload_name);
    n = std::min(n, all.size());
    if (!passes_watchdog(st, key, n, [&](std::size_t i) { benchmark::DoNotOptimize(f(all[i].ray, all[i].shape)); }))
        return;
    ShuffledCases<Case<T, Shape>> order(all, n, key);
    const Case<T, Shape>* cases = order.data();
    std::vector<Hit<T>> out(n);
    for (auto _ : st) {
        st.PauseTiming();
        order.shuffle();
        st.ResumeTiming();
        for (std::size_t i = 0; i < n; ++i) out[i] = f(cases[i].ray, cases[i].shape);
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    std::int64_t hits = 0;
    for (const auto& h : out) hits += h.verdict == Verdict::hit;
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(n));
    st.counters["cases"] = double(n);
    st.counters["hit_rate"] = double(hits) / double(n);
}

// Every method is inlined into the timing loop the same way (in a translation unit this
// large the compiler's own choice differs from method to method, and a Hit returned
// through memory and copied whole adds a store-forwarding stall to the methods it
// leaves out of line).
#if defined(__GNUC__) || defined(__clang__)
#define RAYPROOF_BENCH_INLINE __attribute__((always_inline))
#else
#define RAYPROOF_BENCH_INLINE
#endif

// One method's time over another's, measured in pairs: each iteration times one pass of
// `a` and then one pass of `b` over the same first n uniform cases, back to back, and
// keeps the ratio b / a; the counter "ratio" is the median over the iterations. On a
// machine whose speed changes between repetitions (a shared host, frequency steps) two
// independent medians can each land in a different state; both halves of a pair see
// the same one. A timed pass is a function of its own per method (fill_pass), its loop
// over plain pointers and a count, as a scalar benchmark's loop is. The loop used to sit
// in a lambda reaching the cases, the output and the count through captured
// references, and the textbook Aabb half of its pair then ran three times slower than
// the same method timed alone (40 against 12.8 ns); out of line, 12.0 against 12.3 ns.
// Why the lambda's loop was slower was not established. Each timed pass follows an
// untimed one of the same method, so both are timed warm, as the scalar benchmarks time
// every method: a short pass right after a long one of another method (CGAL's, which
// allocates) would otherwise start with the cases and its code evicted, and pay for
// that alone. The benchmark's own time is that of all four passes and is not reported.
// a_key and b_key name the scalar benchmarks whose check passes (run once per key)
// must have passed; the cases are the workload's timed ones (uniform unless named).
template <class Case, class T, class F> [[gnu::noinline]] void fill_pass(const Case* cases, Hit<T>* out, std::size_t n, F f) {
    for (std::size_t i = 0; i < n; ++i) out[i] = f(cases[i].ray, cases[i].shape);
    benchmark::DoNotOptimize(out);
    benchmark::ClobberMemory();
}
template <class Case, class T, class F> double timed_pass(const Case* cases, Hit<T>* out, std::size_t n, F f) {
    const auto start = std::chrono::steady_clock::now();
    fill_pass(cases, out, n, f);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
template <class T, class Shape, class A, class B>
void time_pair(benchmark::State& st, std::size_t n, const std::string& a_key, A a, const std::string& b_key, B b,
               const std::string& workload_name = "uniform") {
    const auto& all = timed_cases<T, Shape>(workload_name);
    n = std::min(n, all.size());
    const auto checked = [&](const std::string& key, auto query) {
        return passes_watchdog(st, key, n, [&](std::size_t i) { benchmark::DoNotOptimize(query(all[i].ray, all[i].shape)); });
    };
    if (!checked(a_key, a) || !checked(b_key, b)) return;
    ShuffledCases<Case<T, Shape>> order(all, n, a_key + " " + b_key);
    std::vector<Hit<T>> out(n);
    // Each pass, the untimed ones too, in a new order (the shuffle is outside the timing).
    const auto pass = [&](auto query) {
        order.shuffle();
        return timed_pass(order.data(), out.data(), n, query);
    };
    std::vector<double> ratios, a_ns, b_ns;
    for (auto _ : st) {
        pass(a);  // warm-up, untimed
        const double ta = pass(a);
        pass(b);
        const double tb = pass(b);
        ratios.push_back(tb / ta);
        a_ns.push_back(ta / double(n) * 1e9);
        b_ns.push_back(tb / double(n) * 1e9);
    }
    const auto median = [](std::vector<double>& v) {
        if (v.empty()) return 0.0;
        std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
        return v[v.size() / 2];
    };
    st.counters["ratio"] = median(ratios);
    st.counters["a_ns"] = median(a_ns);  // ns per query of each half, medians over the pairs
    st.counters["b_ns"] = median(b_ns);
    st.counters["cases"] = double(n);
}

// The verdict query timed as the CGAL baselines are: the verdict stored in a Hit.
template <class T, class Shape> RAYPROOF_BENCH_INLINE inline Hit<T> certified_verdict_hit(const Ray<T>& r, const Shape& s) {
    Hit<T> h;
    h.verdict = verdict(r, kernel_shape(s), rayproof::certified);
    return h;
}

// The ladder's ratios in pairs (a pass takes well under a millisecond): `num` over
// `den` on workload w, both scalar methods of register_scalar_kernel below.
template <class T, class Shape, class Num, class Den>
void time_ladder_pair(benchmark::State& st, const std::string& w, const char* num, Num nq, const char* den, Den dq) {
    time_pair<T, Shape>(st, options().cases, bench_name<T, Shape>("scalar", w, den), dq,
                        bench_name<T, Shape>("scalar", w, num), nq, w);
}
template <class T, class Shape> void register_ladder() {
    const auto reg = [](const std::string& w, const char* pair, auto f) {
        benchmark::RegisterBenchmark(bench_name<T, Shape>("paired", w, pair).c_str(), f);
    };
    // The same lambdas as the scalar benchmarks time alone, so that a pair times what the
    // table's columns time.
    const auto fast = [](const Ray<T>& r, const Shape& s) RAYPROOF_BENCH_INLINE {
        return intersect(r, kernel_shape(s), rayproof::fast);
    };
    const auto conservative = [](const Ray<T>& r, const Shape& s) RAYPROOF_BENCH_INLINE {
        return intersect(r, kernel_shape(s), rayproof::conservative);
    };
    const auto certified = [](const Ray<T>& r, const Shape& s) RAYPROOF_BENCH_INLINE {
        return intersect(r, kernel_shape(s), rayproof::certified);
    };
    const auto textbook = [](const Ray<T>& r, const Shape& s) RAYPROOF_BENCH_INLINE {
        return baseline::textbook(r, kernel_shape(s));
    };
    reg("uniform", "certified_over_fast", [=](benchmark::State& st) {
        time_ladder_pair<T, Shape>(st, "uniform", "certified", certified, "fast", fast);
    });
    reg("uniform", "fast_over_textbook", [=](benchmark::State& st) {
        time_ladder_pair<T, Shape>(st, "uniform", "fast", fast, "textbook", textbook);
    });
    reg("uniform", "conservative_over_fast", [=](benchmark::State& st) {
        time_ladder_pair<T, Shape>(st, "uniform", "conservative", conservative, "fast", fast);
    });
    if constexpr (has_workload<Shape>("grazing"))
        reg("grazing", "certified_over_fast", [=](benchmark::State& st) {
            time_ladder_pair<T, Shape>(st, "grazing", "certified", certified, "fast", fast);
        });
}

// Registers the kernel's three modes and the plain baselines for one shape and type.
template <class T, class Shape> void register_scalar_kernel(std::string_view workload_name) {
    const std::string w(workload_name);
    auto reg = [&](const char* method, auto f) {
        const std::string name = bench_name<T, Shape>("scalar", w, method);
        benchmark::RegisterBenchmark(name.c_str(), [name, w, f](benchmark::State& st) {
            time_scalar<T, Shape>(st, name, w, options().cases, f);
        });
    };
    reg("fast", [](const Ray<T>& r, const Shape& s) RAYPROOF_BENCH_INLINE { return intersect(r, kernel_shape(s), rayproof::fast); });
    reg("conservative", [](const Ray<T>& r, const Shape& s) RAYPROOF_BENCH_INLINE { return intersect(r, kernel_shape(s), rayproof::conservative); });
    reg("certified", [](const Ray<T>& r, const Shape& s) RAYPROOF_BENCH_INLINE { return intersect(r, kernel_shape(s), rayproof::certified); });
    // The verdict alone (rayproof::verdict), stored as the CGAL baselines store theirs:
    // the question do_intersect answers, on the same cases.
    reg("certified_verdict", [](const Ray<T>& r, const Shape& s) RAYPROOF_BENCH_INLINE {
        return certified_verdict_hit<T>(r, s);
    });
    reg("textbook", [](const Ray<T>& r, const Shape& s) RAYPROOF_BENCH_INLINE { return baseline::textbook(r, kernel_shape(s)); });
    if constexpr (baseline::has_branchless<Shape>)
        reg("branchless", [](const Ray<T>& r, const Shape& s) RAYPROOF_BENCH_INLINE { return baseline::branchless(r, s); });
}

// The batch sweep: sizes 1, 10, ..., batch_max rays against one shape, in each mode.
template <class T, class Shape> const Batch<T, Shape>& batch_data() {
    static const Batch<T, Shape> b = batch_workload<T, Shape>(options().batch_max, options().seed);
    return b;
}
template <class T, class Shape, class Mode> void time_batch(benchmark::State& st, std::size_t n) {
    const Batch<T, Shape>& b = batch_data<T, Shape>();
    n = std::min(n, b.rays.size());
    // The check pass runs on the whole batch once (the smaller batches are its prefixes).
    const std::string key = bench_name<T, Shape>("batch", mode_name(Mode{}), "all");
    if (!passes_watchdog(st, key, b.rays.size(),
                         [&](std::size_t i) { benchmark::DoNotOptimize(intersect(b.rays[i], b.shape, Mode{})); }))
        return;
    // Each call takes the next n rays of the pool (from its start again when fewer are
    // left): over the same n rays call after call, the processor's branch predictor
    // learns their outcomes up to some thousands of rays, and code with a branch on hit or
    // miss then runs faster than on fresh rays (measured: a branch the certified float
    // box's lane batch once had, 10 ns a ray on the same 10,000 rays again and again
    // against 18 on fresh ones). Fresh rays are what an application gives a batch.
    std::vector<Hit<T>> out(n);
    const std::size_t pool = b.rays.size();
    std::size_t first = 0;
    for (auto _ : st) {
        intersect(std::span<const Ray<T>>(b.rays.data() + first, n), b.shape, Mode{}, std::span<Hit<T>>(out));
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
        first = pool - (first + n) >= n ? first + n : 0;
    }
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(n));
    st.counters["rays"] = double(n);
}
// Each row's mode named with `suffix` appended (the AVX2 build's lane batches: "_avx2",
// certified only).
template <class T, class Shape> void register_batch(std::string_view suffix = {}, bool certified_only = false) {
    const auto reg = [suffix](std::size_t n, auto mode) {
        using Mode = decltype(mode);
        const std::string name = bench_name<T, Shape>("batch", std::string(mode_name(mode)) + std::string(suffix),
                                                      std::to_string(n));
        benchmark::RegisterBenchmark(name.c_str(), [n](benchmark::State& st) { time_batch<T, Shape, Mode>(st, n); });
    };
    for (std::size_t n = 1; n <= options().batch_max; n *= 10) {
        if (!certified_only) {
            reg(n, fast_t{});
            reg(n, conservative_t{});
        }
        reg(n, certified_t{});
    }
}

// Every workload of the shape, scalar and batch, in float and double.
template <template <class> class S> void register_shape() {
    register_ladder<double, S<double>>();
    register_ladder<float, S<float>>();
    for (const std::string_view w : kWorkloads) {
        if (!has_workload<S<float>>(w)) continue;
        register_scalar_kernel<double, S<double>>(w);
        register_scalar_kernel<float, S<float>>(w);
    }
    if constexpr (!is_polyhedron_v<S<float>>) {  // no batch sweep for polyhedra (workloads.hpp)
        register_batch<double, S<double>>();
        register_batch<float, S<float>>();
    }
}

// Defined by the per-shape files and the baseline files.
void register_aabb();
void register_obb();
void register_plane();
void register_sphere();
void register_polyhedron();
void register_fp_env();  // fp_env_bench.cpp
void register_cgal();    // cgal_bench.cpp
void register_embree();  // embree_bench.cpp

}  // namespace rayproof::bench
