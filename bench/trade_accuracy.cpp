// bench/trade_accuracy.cpp — the accuracy half of the trade: every method of
// rayproof_bench answers the same workload cases (same generators, same seed, the timed
// cases being the first of them), and the oracle's judge scores each answer against the
// exact one.
//
//   rayproof_trade_accuracy [--cases N] [--cgal-cases N] [--seed S] [--shape aabb,obb,...,polyhedron]
//                           [--methods fast,certified,...] [--timeout SECONDS]
//                           [--show-method METHOD --show N]   (the wrong cases, on stderr)
//
// Prints one CSV row per (shape, type, workload, method):
//   cases            cases judged (the CGAL baselines: the first --cgal-cases of them)
//   wrong            wrong verdicts: false hits + false misses + invalid mismatches
//   false_hit, false_miss, invalid_mismatch
//   face_mismatch    both hit, different entry face (methods that report a face)
//   t_judged         both hit and t comparable (see below)
//   t_off            of those, t_enter or t_exit not a faithful rounding of the exact value
//   max_ulps         the largest distance, in representable values, from a faithful
//                    rounding ("inf" for NaN)
//   not_enclosing    of t_judged, [t_enter, t_exit] does not contain the exact interval
//   exact_hits       cases whose exact verdict is hit
//   refused          valid cases the method declines to answer (Embree: rays beyond its
//                    coordinate limit); not counted as wrong, not judged further
//   status           ok; or "timeout at case I" / "signal S at case I" when the method
//                    hung or crashed on a case (each method runs in a child process with
//                    a deadline, --timeout seconds, so that one bad case cannot stop the run)
// CGAL answers only a verdict (no t, no face). Embree answers the first surface crossing:
// its t_enter is judged where the ray starts outside the ball (t_min >= 0 and the exact
// entry after t_min), its t_exit never.
#include "baselines.hpp"
#include "watchdog.hpp"
#include "workloads.hpp"

#ifdef RAYPROOF_BENCH_HAVE_CGAL
#include "cgal_baselines.hpp"
#endif
#ifdef RAYPROOF_BENCH_HAVE_EMBREE
#include "embree_sphere.hpp"
#endif

#include <rayproof/oracle/contract.hpp>
#include <rayproof/oracle/oracle.hpp>

#include <rayproof/cli.hpp>

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <memory>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

namespace rayproof::bench {
namespace {

using oracle::Exact;

struct Options {
    std::size_t cases = 1 << 17;
    std::size_t cgal_cases = 1 << 14;
    std::uint64_t seed = kDefaultSeed;
    std::string shapes = "aabb,obb,plane,sphere,polyhedron";
    std::string methods;      // only these methods (empty: all)
    double timeout = 120;     // seconds per (shape, type, workload, method)
    std::string show_method;  // print the cases this method gets wrong (stderr)
    std::size_t show = 0;     // at most this many per (shape, type, workload)
} opts;

using oracle::Tally;

enum Judge : unsigned { verdict_only = 0, face = 1, t_both = 2, t_enter_outside = 4, may_refuse = 8 };

template <class T> void tally(Tally& t, const Ray<T>& r, const Hit<T>& h, const Exact<T>& ex, unsigned what) {
    ++t.cases;
    t.exact_hits += ex.verdict == Verdict::hit;
    if ((what & may_refuse) && h.verdict == Verdict::invalid && ex.verdict != Verdict::invalid) {
        ++t.refused;
        return;
    }
    const oracle::Judgement j = oracle::judge(h, ex, (what & face) != 0);
    t.count_outcome(j);
    if (h.verdict != Verdict::hit || ex.verdict != Verdict::hit) return;
    if (what & t_both) {
        t.count_interval(j);
    } else if (what & t_enter_outside) {
        if (r.t_min >= 0 && ex.enter_vs(r.t_min) == oracle::Order::below) t.count_t(j.enter_ulps);
    }
}

void print_header() {
    std::printf(
        "shape,type,workload,method,cases,wrong,false_hit,false_miss,invalid_mismatch,face_mismatch,t_judged,t_off,"
        "max_ulps,not_enclosing,exact_hits,refused,status\n");
}

// faces / times: whether the method answers a face / a t (else those columns read n/a).
template <class T, class Shape>
void print_row(std::string_view w, const char* method, const Tally& t, bool faces, bool times) {
    char ulps[32];
    if (!times || t.t_judged == 0)
        std::snprintf(ulps, sizeof ulps, "n/a");
    else if (t.max_ulps == std::numeric_limits<std::uint64_t>::max())
        std::snprintf(ulps, sizeof ulps, "inf");
    else
        std::snprintf(ulps, sizeof ulps, "%llu", static_cast<unsigned long long>(t.max_ulps));
    const std::string face = faces ? std::to_string(t.face_mismatch) : "n/a";
    const std::string t_judged = times ? std::to_string(t.t_judged) : "n/a";
    const std::string t_off = times ? std::to_string(t.t_off) : "n/a";
    const std::string encl = times ? std::to_string(t.not_enclosing) : "n/a";
    std::printf("%s,%s,%.*s,%s,%" PRIu64 ",%" PRIu64 ",%" PRIu64 ",%" PRIu64 ",%" PRIu64 ",%s,%s,%s,%s,%s,%" PRIu64
                ",%" PRIu64 ",ok\n",
                std::string(gen::shape_name<Shape>()).c_str(), std::string(gen::scalar_name<T>()).c_str(),
                int(w.size()), w.data(), method, t.cases, t.wrong(),
                t.false_hit, t.false_miss, t.invalid_mismatch, face.c_str(), t_judged.c_str(), t_off.c_str(), ulps,
                encl.c_str(), t.exact_hits, t.refused);
    std::fflush(stdout);
}

template <class T, class Shape> void print_failure(std::string_view w, const char* method, const std::string& status) {
    std::printf("%s,%s,%.*s,%s,,,,,,,,,,,,,%s\n", std::string(gen::shape_name<Shape>()).c_str(),
                std::string(gen::scalar_name<T>()).c_str(), int(w.size()), w.data(), method, status.c_str());
    std::fflush(stdout);
}

bool method_wanted(const char* method) {
    if (opts.methods.empty()) return true;
    return ("," + opts.methods + ",").find("," + std::string(method) + ",") != std::string::npos;
}

// Runs f on the first n cases and prints the judged row. The loop runs in a child
// process (the cases and the exact answers are shared copy-on-write) with a deadline:
// a method that hangs or crashes on some case gets a status row naming the case, and
// the run goes on with the next method.
template <class T, class Shape, class F>
void judge_method(std::string_view w, const char* method, const std::vector<Case<T, Shape>>& cases,
                  const std::vector<Exact<T>>& exact, std::size_t n, unsigned what, F f) {
    if (!method_wanted(method)) return;
    n = std::min(n, cases.size());
    Watchdog dog;
    std::string why;
    const bool ok = dog.run(
        opts.timeout,
        [&](Watchdog::Shared& s) {
            Tally t;
            const bool show = opts.show > 0 && opts.show_method == method;
            std::size_t shown = 0;
            for (std::size_t i = 0; i < n; ++i) {
                s.progress = i;
                const Hit<T> h = f(i, cases[i].ray, cases[i].shape);
                const Tally before = t;
                tally(t, cases[i].ray, h, exact[i], what);
                const bool bad =
                    t.wrong() != before.wrong() || t.face_mismatch != before.face_mismatch || t.t_off != before.t_off;
                if (show && bad && shown < opts.show) {
                    ++shown;
                    std::cerr << w << " case " << i << ": " << cases[i] << "\n  answer " << h.verdict << " ["
                              << std::hexfloat << h.t_enter << ", " << h.t_exit << std::defaultfloat << "] face "
                              << h.face << "\n  exact  " << exact[i] << '\n';
                }
            }
            print_row<T, Shape>(w, method, t, (what & face) != 0, (what & (t_both | t_enter_outside)) != 0);
        },
        why);
    if (!ok) print_failure<T, Shape>(w, method, why);
}

template <class T> Hit<T> verdict_hit(bool hit) {
    Hit<T> h;
    h.verdict = hit ? Verdict::hit : Verdict::miss;
    return h;
}

template <class T, class Shape> void run_workload(std::string_view w) {
    const auto cases = workload<T, Shape>(w, opts.cases, opts.seed);
    std::vector<Exact<T>> exact;
    exact.reserve(cases.size());
    for (const auto& c : cases) exact.push_back(oracle::exact(c.ray, kernel_shape(c.shape)));
    const std::size_t n = cases.size();
    const unsigned all = face | t_both;
    judge_method(w, "fast", cases, exact, n, all,
                 [](std::size_t, const Ray<T>& r, const Shape& s) { return intersect(r, kernel_shape(s), rayproof::fast); });
    judge_method(w, "conservative", cases, exact, n, all,
                 [](std::size_t, const Ray<T>& r, const Shape& s) { return intersect(r, kernel_shape(s), rayproof::conservative); });
    judge_method(w, "certified", cases, exact, n, all,
                 [](std::size_t, const Ray<T>& r, const Shape& s) { return intersect(r, kernel_shape(s), rayproof::certified); });
    judge_method(w, "certified_verdict", cases, exact, n, verdict_only, [](std::size_t, const Ray<T>& r, const Shape& s) {
        Hit<T> h;
        h.verdict = verdict(r, kernel_shape(s), rayproof::certified);
        return h;
    });
    judge_method(w, "textbook", cases, exact, n, all,
                 [](std::size_t, const Ray<T>& r, const Shape& s) { return baseline::textbook(r, kernel_shape(s)); });
    if constexpr (baseline::has_branchless<Shape>)
        judge_method(w, "branchless", cases, exact, n, t_both,
                     [](std::size_t, const Ray<T>& r, const Shape& s) { return baseline::branchless(r, s); });
#ifdef RAYPROOF_BENCH_HAVE_CGAL
    if constexpr (cgal::supported<Shape>) {
        judge_method(w, "cgal_epeck", cases, exact, opts.cgal_cases, verdict_only,
                     [](std::size_t, const Ray<T>& r, const Shape& s) { return verdict_hit<T>(cgal::epeck(r, kernel_shape(s))); });
        judge_method(w, "cgal_rational", cases, exact, opts.cgal_cases, verdict_only,
                     [](std::size_t, const Ray<T>& r, const Shape& s) { return verdict_hit<T>(cgal::rational(r, kernel_shape(s))); });
    }
#endif
#ifdef RAYPROOF_BENCH_HAVE_EMBREE
    if constexpr (std::is_same_v<Shape, Sphere<float>>) {
        for (const bool robust : {false, true}) {
            // The scenes are built in the child, a chunk at a time (memory stays small).
            constexpr std::size_t chunk = 4096;
            std::shared_ptr<EmbreeSpheres> scenes;
            judge_method(w, robust ? "embree_robust" : "embree", cases, exact, n, t_enter_outside | may_refuse,
                         [&, scenes, robust](std::size_t i, const Ray<T>& r, const Shape&) mutable {
                             if (i % chunk == 0) {
                                 const std::size_t m = std::min(chunk, cases.size() - i);
                                 std::vector<Sphere<float>> spheres(m);
                                 for (std::size_t k = 0; k < m; ++k) spheres[k] = cases[i + k].shape;
                                 scenes.reset();
                                 scenes = std::make_shared<EmbreeSpheres>(spheres, robust);
                             }
                             return scenes->intersect(i % chunk, r);
                         });
        }
    }
#endif
}

template <template <class> class S> void run_shape() {
    for (const std::string_view w : kWorkloads) {
        if (!has_workload<S<float>>(w)) continue;
        run_workload<double, S<double>>(w);
        run_workload<float, S<float>>(w);
    }
}

bool wanted(const char* shape) {
    const std::string list = "," + opts.shapes + ",";
    return list.find("," + std::string(shape) + ",") != std::string::npos;
}

}  // namespace
}  // namespace rayproof::bench

int main(int argc, char** argv) {
    using namespace rayproof;
    using namespace rayproof::bench;
    CLI::App app{"Judges every method's answers on the timed workloads against the exact oracle (CSV).",
                 "rayproof_trade_accuracy"};
    app.option_defaults()->always_capture_default();
    app.add_option("--cases", opts.cases, "cases judged per workload")->check(cli::positive);
    app.add_option("--cgal-cases", opts.cgal_cases, "cases judged for the CGAL baselines (at most --cases)")
        ->check(cli::non_negative);
    app.add_option("--seed", opts.seed, "the workloads' seed (decimal or 0x hex)")->check(cli::non_negative);
    app.add_option("--shape", opts.shapes, "the shapes, comma-separated");
    app.add_option("--methods", opts.methods, "only these methods, comma-separated (default: all)");
    app.add_option("--timeout", opts.timeout, "seconds per method and workload")->check(cli::non_negative);
    app.add_option("--show-method", opts.show_method, "print the cases this method gets wrong, on stderr");
    app.add_option("--show", opts.show, "with --show-method: at most N cases per workload")->check(cli::non_negative);
    if (const auto stop = cli::parse(app, argc, argv)) return *stop;
    opts.cgal_cases = std::min(opts.cgal_cases, opts.cases);
    print_header();
    if (wanted("aabb")) run_shape<Aabb>();
    if (wanted("obb")) run_shape<Obb>();
    if (wanted("plane")) run_shape<Plane>();
    if (wanted("sphere")) run_shape<Sphere>();
    if (wanted("polyhedron")) run_shape<gen::OwnedPolyhedron>();
    return 0;
}
