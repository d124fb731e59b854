// bench/fp_env_bench.cpp — what the floating-point environment guard costs
// (detail/fp_env.hpp): per query, certified and conservative, every shape, float and
// double, on the uniform workload's timed cases, measured in pairs as time_pair does
// (bench_common.hpp: one pass of each method back to back, each after an untimed pass of
// its own, many times; the medians over the pairs), each pass timed by the thread's CPU
// clock.
//
//   fpenv/<shape>/<type>/<mode>/guard        a: the query with the guard compiled out
//                                            (detail::query on the prepared shape, which
//                                            is what intersect() compiles to with
//                                            RAYPROOF_NO_FP_ENV_GUARD), b: intersect(), in
//                                            the default environment
//   fpenv/<shape>/<type>/<mode>/scope        a: intersect() in the default environment,
//                                            b: intersect(..., scope), the form that takes
//                                            an FpEnvScope (fp_env_scope.hpp), the scope
//                                            made once around every pass
//   fpenv/<shape>/<type>/<mode>/foreign      a: intersect() in the default environment,
//                                            b: intersect() with the caller in a foreign
//                                            environment (x86: MXCSR FTZ+DAZ, as Embree's
//                                            users set it; elsewhere FE_UPWARD), so that
//                                            every query switches and restores
// Counters: a_ns and b_ns (the median over the pairs of each pass's time per query),
// delta_ns (the median of the per-query difference b - a within a pair), ratio (the
// median of b / a).
#include "bench_common.hpp"

#include <cfenv>
#include <ctime>

#if defined(__SSE2__) || defined(_M_X64)
#include <xmmintrin.h>
#endif

namespace rayproof::bench {

namespace {

// The foreign environment of the second pass, set and cleared out of line around it.
[[gnu::noinline]] void enter_foreign() {
#if defined(__SSE2__) || defined(_M_X64)
    _mm_setcsr(_mm_getcsr() | 0x8040u);  // FTZ (bit 15) and DAZ (bit 6)
#else
    std::fesetround(FE_UPWARD);
#endif
}
[[gnu::noinline]] void leave_foreign() {
#if defined(__SSE2__) || defined(_M_X64)
    _mm_setcsr(_mm_getcsr() & ~0x8040u);
#else
    std::fesetround(FE_TONEAREST);
#endif
}

// The calling thread's CPU time in seconds where POSIX has it (the machine may be
// shared: a pass that loses the processor is not charged for it), else wall time.
double pass_clock() {
#if defined(CLOCK_THREAD_CPUTIME_ID)
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + double(ts.tv_nsec) * 1e-9;
#else
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
#endif
}

template <class T> double median(std::vector<T>& v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return double(v[v.size() / 2]);
}

// a and b in pairs over the first n uniform cases; b runs in the foreign environment
// when `foreign` is set.
// b_check stands for b in the watchdog's check pass, which runs on another thread (b
// itself may hold the timing thread's FpEnvScope).
template <class T, class Shape, class A, class B, class C>
void time_env_pair(benchmark::State& st, const std::string& key, A a, B b, bool foreign, C b_check) {
    const auto& all = timed_cases<T, Shape>("uniform");
    const std::size_t n = std::min(options().cases, all.size());
    if (!passes_watchdog(st, key + "#a", n, [&](std::size_t i) { benchmark::DoNotOptimize(a(all[i].ray, all[i].shape)); }))
        return;
    if (!passes_watchdog(st, key + "#b", n, [&](std::size_t i) {
            if (foreign) enter_foreign();
            benchmark::DoNotOptimize(b_check(all[i].ray, all[i].shape));
            if (foreign) leave_foreign();
        }))
        return;
    ShuffledCases<Case<T, Shape>> order(all, n, key);  // each pass in a new order, as time_pair's
    std::vector<Hit<T>> out(n);
    auto pass = [&](auto query, bool in_foreign) {
        order.shuffle();
        if (in_foreign) enter_foreign();
        const double start = pass_clock();
        fill_pass(order.data(), out.data(), n, query);  // its own loop, as time_pair's passes
        const double t = pass_clock() - start;
        if (in_foreign) leave_foreign();
        return t * 1e9 / double(n);
    };
    std::vector<double> ta, tb, delta, ratio;
    for (auto _ : st) {
        pass(a, false);  // warm-up, untimed
        const double x = pass(a, false);
        pass(b, foreign);
        const double y = pass(b, foreign);
        ta.push_back(x);
        tb.push_back(y);
        delta.push_back(y - x);
        ratio.push_back(y / x);
    }
    st.counters["a_ns"] = median(ta);
    st.counters["b_ns"] = median(tb);
    st.counters["delta_ns"] = median(delta);
    st.counters["ratio"] = median(ratio);
    st.counters["cases"] = double(n);
}

template <class T, class Shape, class Mode> void register_mode() {
    const std::string mode = mode_name(Mode{});
    const auto per_call = [](const Ray<T>& r, const Shape& s) RAYPROOF_BENCH_INLINE { return intersect(r, s, Mode{}); };
    const std::string guard = bench_name<T, Shape>("fpenv", mode, "guard");
    benchmark::RegisterBenchmark(guard.c_str(), [guard, per_call](benchmark::State& st) {
        time_env_pair<T, Shape>(
            st, guard,
            [](const Ray<T>& r, const Shape& s) RAYPROOF_BENCH_INLINE { return rayproof::detail::query(r, rayproof::detail::prepare(s), Mode{}); },
            per_call, false, per_call);
    });
    const std::string foreign = bench_name<T, Shape>("fpenv", mode, "foreign");
    benchmark::RegisterBenchmark(foreign.c_str(), [foreign, per_call](benchmark::State& st) {
        time_env_pair<T, Shape>(st, foreign, per_call, per_call, true, per_call);
    });
    const std::string scope = bench_name<T, Shape>("fpenv", mode, "scope");
    benchmark::RegisterBenchmark(scope.c_str(), [scope, per_call](benchmark::State& st) {
        const FpEnvScope env;  // on the timing thread, around every pass, as a caller's loop would hold it
        const FpEnvScope* e = &env;
        time_env_pair<T, Shape>(
            st, scope, per_call,
            [e](const Ray<T>& r, const Shape& s) RAYPROOF_BENCH_INLINE { return intersect(r, s, Mode{}, *e); }, false,
            per_call);
    });
}

template <template <class> class S> void register_fp_env_shape() {
    register_mode<double, S<double>, certified_t>();
    register_mode<double, S<double>, conservative_t>();
    register_mode<float, S<float>, certified_t>();
    register_mode<float, S<float>, conservative_t>();
}

}  // namespace

void register_fp_env() {
#if defined(__SSE2__) || defined(_M_X64)
    benchmark::AddCustomContext("fp_env_x86", "1");  // the report names the probe and the foreign environment
#else
    benchmark::AddCustomContext("fp_env_x86", "0");
#endif
    register_fp_env_shape<Aabb>();
    register_fp_env_shape<Obb>();
    register_fp_env_shape<Plane>();
    register_fp_env_shape<Sphere>();
}

}  // namespace rayproof::bench
