// bench/ray_aabb_bench.cpp — ray against Aabb: the kernel's three modes and the plain
// baselines on every workload (scalar), and the batch sweep (see bench_common.hpp); and
// one ray against many boxes, the Ray form against the PreparedRay form:
//   prepared/aabb/<float|double>/<method>/{ray,prepared}
// each of the first kRays uniform rays asked against the first kBoxes uniform boxes (the
// same pairs for both forms), in the form named last: `ray` passes the Ray to every
// query, `prepared` makes a PreparedRay once per ray (its cost is timed) and passes that.
// Methods: fast, certified (intersect) and certified_verdict (verdict). items = queries.
//   prepared/aabb/<float|double>/<method>/prepared_over_ray
// the two measured in pairs: counters ratio (prepared time over ray time, median over
// the pairs), ray_ns and prepared_ns (ns per query, medians).
#include "bench_common.hpp"

#include <chrono>
#include <type_traits>

namespace rayproof::bench {
namespace {

constexpr std::size_t kRays = 64, kBoxes = 256;

template <class T> struct ManyBoxes {
    std::vector<Ray<T>> rays;
    std::vector<Aabb<T>> boxes;
};
template <class T> const ManyBoxes<T>& many_boxes() {
    static const ManyBoxes<T> m = [] {
        const auto& all = timed_cases<T, Aabb<T>>("uniform");
        ManyBoxes<T> out;
        for (std::size_t i = 0; i < std::min(kRays, all.size()); ++i) out.rays.push_back(all[i].ray);
        for (std::size_t i = 0; i < std::min(kBoxes, all.size()); ++i) out.boxes.push_back(all[i].shape);
        return out;
    }();
    return m;
}

// One ray (a Ray or a PreparedRay) against every box, into out.
template <class T, class R, class Q>
RAYPROOF_BENCH_INLINE inline void against_boxes(const R& ray, const std::vector<Aabb<T>>& boxes, Hit<T>* out, Q query) {
    for (std::size_t j = 0; j < boxes.size(); ++j) out[j] = query(ray, boxes[j]);
}

template <class T, bool Prepared, class Q> void time_many_boxes(benchmark::State& st, Q query) {
    const ManyBoxes<T>& m = many_boxes<T>();
    std::vector<Hit<T>> out(m.boxes.size());
    std::int64_t hits = 0;
    for (auto _ : st) {
        for (const Ray<T>& r : m.rays) {
            if constexpr (Prepared) {
                const PreparedRay<T> p(r);
                against_boxes<T>(p, m.boxes, out.data(), query);
            } else {
                against_boxes<T>(r, m.boxes, out.data(), query);
            }
            benchmark::DoNotOptimize(out.data());
            benchmark::ClobberMemory();
        }
    }
    for (const Hit<T>& h : out) hits += h.verdict == Verdict::hit;
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(m.rays.size() * m.boxes.size()));
    st.counters["rays"] = double(m.rays.size());
    st.counters["boxes"] = double(m.boxes.size());
    st.counters["last_ray_hit_rate"] = double(hits) / double(out.size());
}

// The prepared form's time over the Ray form's, in pairs (as time_pair in
// bench_common.hpp: each iteration times one warm pass of each, back to back, and keeps
// the ratio; the counter "ratio" is the median), robust to a machine whose speed changes
// between repetitions.
template <class T, class Q> void time_many_boxes_paired(benchmark::State& st, Q query) {
    const ManyBoxes<T>& m = many_boxes<T>();
    std::vector<Hit<T>> out(m.boxes.size());
    const auto pass = [&](auto prepared) {
        const auto start = std::chrono::steady_clock::now();
        for (const Ray<T>& r : m.rays) {
            if constexpr (decltype(prepared)::value) {
                const PreparedRay<T> p(r);
                against_boxes<T>(p, m.boxes, out.data(), query);
            } else {
                against_boxes<T>(r, m.boxes, out.data(), query);
            }
            benchmark::DoNotOptimize(out.data());
            benchmark::ClobberMemory();
        }
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    std::vector<double> ratios, ray_ns, prepared_ns;
    const double queries = double(m.rays.size() * m.boxes.size());
    for (auto _ : st) {
        pass(std::false_type{});
        const double a = pass(std::false_type{});
        pass(std::true_type{});
        const double b = pass(std::true_type{});
        ratios.push_back(b / a);
        ray_ns.push_back(a / queries * 1e9);
        prepared_ns.push_back(b / queries * 1e9);
    }
    const auto median = [](std::vector<double> v) {
        if (v.empty()) return 0.0;
        std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
        return v[v.size() / 2];
    };
    st.counters["ratio"] = median(ratios);
    st.counters["ray_ns"] = median(ray_ns);
    st.counters["prepared_ns"] = median(prepared_ns);
}

template <class T, class Mode> void register_many_boxes(const char* method) {
    const auto q = [](const auto& r, const Aabb<T>& b) RAYPROOF_BENCH_INLINE { return intersect(r, b, Mode{}); };
    benchmark::RegisterBenchmark(bench_name<T, Aabb<T>>("prepared", method, "ray").c_str(),
                                 [q](benchmark::State& st) { time_many_boxes<T, false>(st, q); });
    benchmark::RegisterBenchmark(bench_name<T, Aabb<T>>("prepared", method, "prepared").c_str(),
                                 [q](benchmark::State& st) { time_many_boxes<T, true>(st, q); });
    benchmark::RegisterBenchmark(bench_name<T, Aabb<T>>("prepared", method, "prepared_over_ray").c_str(),
                                 [q](benchmark::State& st) { time_many_boxes_paired<T>(st, q); });
}
template <class T> void register_many_boxes_verdict() {
    const auto q = [](const auto& r, const Aabb<T>& b) RAYPROOF_BENCH_INLINE {
        Hit<T> h;
        h.verdict = verdict(r, b, rayproof::certified);
        return h;
    };
    benchmark::RegisterBenchmark(bench_name<T, Aabb<T>>("prepared", "certified_verdict", "ray").c_str(),
                                 [q](benchmark::State& st) { time_many_boxes<T, false>(st, q); });
    benchmark::RegisterBenchmark(bench_name<T, Aabb<T>>("prepared", "certified_verdict", "prepared").c_str(),
                                 [q](benchmark::State& st) { time_many_boxes<T, true>(st, q); });
    benchmark::RegisterBenchmark(bench_name<T, Aabb<T>>("prepared", "certified_verdict", "prepared_over_ray").c_str(),
                                 [q](benchmark::State& st) { time_many_boxes_paired<T>(st, q); });
}
template <class T> void register_prepared() {
    register_many_boxes<T, fast_t>("fast");
    register_many_boxes<T, certified_t>("certified");
    register_many_boxes_verdict<T>();
}

}  // namespace

void register_aabb() {
    register_shape<Aabb>();
    register_prepared<double>();
    register_prepared<float>();
}
}  // namespace rayproof::bench
