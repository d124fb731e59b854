// bench/bvh_bench.cpp — rayproof_bvh_bench: closest-hit rays per second on the sphere set
// of bvh_scenes.hpp (100,000 balls by default), rayproof's Bvh<float> in each mode
// against Embree 3's rtcIntersect1 with and without RTC_SCENE_FLAG_ROBUST, on the same
// rays; the wrong closest hits of each, judged against the brute-force certified loop
// (closest.hpp, closest_hit) on the first --judge rays of each set; build time and memory
// per primitive. Writes "KEY VALUE" lines (the trade report's --bvh input):
//
//   bvh-spheres N                 the set's size; bvh-rays-SET, bvh-judged-SET likewise
//   bvh-rate-SET-METHOD R         rays per second, one thread: the median over the
//                                 repetitions of rays / (CPU time of a pass over the set)
//   bvh-build-s-METHOD S          the build, wall seconds, one thread (METHOD here:
//                                 rayproof, rayproof_double, embree, embree_robust)
//   bvh-bytes-METHOD B            what the structure holds after the build (rayproof:
//                                 BvhStats::bytes; Embree: its device's memory monitor)
//   bvh-bytes-items-METHOD B      of those, the copies of the balls themselves (rayproof:
//                                 one Primitive<float> each; Embree: one float4 each)
//   bvh-hits-SET H                judged rays the reference says hit
//   bvh-wrong-SET-METHOD W        judged rays whose answer differs from the reference:
//                                 another verdict, or another ball (rayproof certified:
//                                 any bit of the answer, index and Hit)
//   bvh-falsemiss-SET-METHOD M    of those, a miss where the reference hits
//   bvh-falsehit-SET-METHOD F     of those, a hit where the reference misses
//   bvh-brute-rate-SET R          the brute-force certified loop's rays per second
//
//   bvh-double-width W            the double tree's node width (the tracer's)
//
// METHOD: fast, conservative, certified (rayproof::Bvh<float, 8>), fast_double,
// conservative_double, certified_double (rayproof::Bvh<double, W> over the same balls,
// widened exactly, W the tracer's width; judged by verdict and ball), embree, embree_robust; SET: camera, grazing (bvh_scenes.hpp). The repetitions run the methods
// in turn within each repetition, so that a change of load on a shared machine spreads
// over all of them. Exit status 3 when the certified BVH differs from the brute-force
// loop on some judged ray (each such ray is named on stderr with the seed).
//
// Built a second time with -mavx2 (rayproof_bvh_bench_avx2, RAYPROOF_BENCH_BVH_SUFFIX
// "_avx2"): rayproof's methods only, each name and the build keys suffixed (fast_avx2,
// rayproof_avx2, ...), and none of the keys the default build already writes (the set,
// the judgement's reference), so that both outputs can be read side by side.
#include "bvh_scenes.hpp"

#include <rayproof/rayproof.hpp>
#include <rayproof/cli.hpp>

#if RAYPROOF_BENCH_HAVE_EMBREE
#include "embree_bvh.hpp"
#endif

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace {

using namespace rayproof;
using bench::RaySet;

#ifdef RAYPROOF_BENCH_BVH_SUFFIX
const std::string kSuffix = RAYPROOF_BENCH_BVH_SUFFIX;
#else
const std::string kSuffix;
#endif
// The keys of the set and of the reference: written by the default build alone.
const bool kWritesShared = kSuffix.empty();
// The tracer's width for its Bvh<double, W> (render/tracer.hpp, scene_bvh_width): the
// kernel's bvh_native_width (bvh.hpp), 8 where the build targets AVX2, else 4.
constexpr int kDoubleWidth = bvh_native_width<double>;

double thread_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

// One method's answer to a closest-hit query, reduced to what is compared.
struct Answer {
    bool hit = false;
    std::int64_t index = -1;
    ClosestHit<float> full;  // rayproof's own answer (unused for Embree)
};

bool same_bits(const ClosestHit<float>& a, const ClosestHit<float>& b) {
    const auto bits = [](float x) {
        std::uint32_t u;
        std::memcpy(&u, &x, sizeof u);
        return u;
    };
    return a.verdict == b.verdict && a.index == b.index && a.hit.verdict == b.hit.verdict &&
           bits(a.hit.t_enter) == bits(b.hit.t_enter) && bits(a.hit.t_exit) == bits(b.hit.t_exit) &&
           a.hit.face == b.hit.face;
}

struct Method {
    std::string name;
    bool exact_bits = false;                       // judged bit for bit (rayproof certified)
    std::function<Answer(const Ray<float>&)> ask;  // one query (judging)
    std::function<std::int64_t(const std::vector<Ray<float>>&)> pass;  // one timed pass: sum of indices
};

struct Options {
    std::size_t spheres = 100000, rays = 100000, judge = 2000;
    std::uint64_t seed = 1;
    int repetitions = 5;
    int leaf_size = rayproof::BvhOptions{}.leaf_size;
    std::string output;
};

}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{"Closest-hit rays per second on generated balls: rayproof's BVH against Embree 3.", "rayproof_bvh_bench"};
    app.add_option("--spheres", o.spheres, "balls in the set")->check(CLI::Range(std::size_t(1), std::size_t(10000000)));
    app.add_option("--rays", o.rays, "rays per set (camera, grazing), timed")->check(CLI::Range(std::size_t(1), std::size_t(100000000)));
    app.add_option("--judge", o.judge, "the first rays of each set judged against the brute-force certified loop")
        ->check(rayproof::cli::non_negative);
    app.add_option("--seed", o.seed, "the scene's and the rays' seed")->check(rayproof::cli::non_negative);
    app.add_option("--repetitions", o.repetitions, "timed passes per method and set (the median is reported)")
        ->check(CLI::Range(1, 1000));
    app.add_option("--leaf-size", o.leaf_size, "the most balls in one leaf of both trees (BvhOptions::leaf_size)")
        ->check(CLI::Range(1, 255));
    app.add_option("-o,--output", o.output, "write the KEY VALUE lines here (default: stdout)");
    if (const auto stop = rayproof::cli::parse(app, argc, argv)) return *stop;
    o.judge = std::min(o.judge, o.rays);

    std::ofstream file;
    if (!o.output.empty()) {
        file.open(o.output);
        if (!file) {
            std::fprintf(stderr, "rayproof_bvh_bench: cannot write '%s'\n", o.output.c_str());
            return 1;
        }
    }
    std::ostream& out = o.output.empty() ? std::cout : file;
    const auto put = [&](const std::string& key, double value) {
        out << key << ' ' << value << '\n';
        out.flush();
    };
    const auto note = [&](const std::string& what) { std::fprintf(stderr, "rayproof_bvh_bench: %s\n", what.c_str()); };

    const std::vector<Sphere<float>> balls = bench::sphere_set(o.spheres, o.seed);
    std::vector<Primitive<float>> prims(balls.begin(), balls.end());
    if (kWritesShared) put("bvh-spheres", double(balls.size()));
    const RaySet sets[] = {RaySet::camera, RaySet::grazing};
    std::vector<std::vector<Ray<float>>> rays;
    for (std::size_t k = 0; k < 2; ++k) {
        rays.push_back(bench::ray_set(sets[k], balls, o.rays, o.seed + 1 + k));
        if (kWritesShared) put(std::string("bvh-rays-") + bench::ray_set_name(sets[k]), double(o.rays));
    }

    // ---- the structures and their builds
    std::vector<Method> methods;
    const auto built = [&](const std::string& base, double seconds, std::size_t bytes, std::size_t item_bytes) {
        const std::string name = base.rfind("embree", 0) == 0 ? base : base + kSuffix;
        put("bvh-build-s-" + name, seconds);
        put("bvh-bytes-" + name, double(bytes));
        put("bvh-bytes-items-" + name, double(item_bytes * balls.size()));
        note(name + ": built in " + std::to_string(seconds) + " s, " + std::to_string(double(bytes) / double(balls.size())) +
             " bytes per ball");
    };

    const auto t0 = std::chrono::steady_clock::now();
    const Bvh<float, 8> bvh{std::span<const Primitive<float>>(prims), BvhOptions{o.leaf_size, BvhOptions{}.bins}};
    built("rayproof", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), bvh.stats().bytes,
          sizeof(Primitive<float>));
    const auto add_mode = [&](const std::string& name, auto mode, bool exact) {
        methods.push_back(Method{
            name + kSuffix, exact,
            [&bvh, mode](const Ray<float>& r) {
                const ClosestHit<float> c = bvh.closest_hit(PreparedRay<float>(r), mode);
                return Answer{bool(c), c.index, c};
            },
            [&bvh, mode](const std::vector<Ray<float>>& rs) {
                std::int64_t sum = 0;
                for (const Ray<float>& r : rs) sum += bvh.closest_hit(PreparedRay<float>(r), mode).index;
                return sum;
            }});
    };
    add_mode("fast", fast, false);
    add_mode("conservative", conservative, false);
    add_mode("certified", certified, true);

    // The same balls and rays in a double tree (the tracer's Bvh<double, kDoubleWidth>):
    // float widens to double exactly, so the exact answers are the float tree's; judged
    // by verdict and ball.
    std::vector<Primitive<double>> dprims;
    dprims.reserve(balls.size());
    for (const Sphere<float>& b : balls) dprims.push_back(Sphere<double>{b.center.cast<double>(), double(b.radius)});
    const auto td = std::chrono::steady_clock::now();
    const Bvh<double, kDoubleWidth> dbvh{std::span<const Primitive<double>>(dprims),
                                        BvhOptions{o.leaf_size, BvhOptions{}.bins}};
    if (kWritesShared) put("bvh-double-width", double(kDoubleWidth));
    built("rayproof_double", std::chrono::duration<double>(std::chrono::steady_clock::now() - td).count(),
          dbvh.stats().bytes, sizeof(Primitive<double>));
    const auto widen = [](const Ray<float>& r) {
        return Ray<double>{r.origin.cast<double>(), r.direction.cast<double>(), double(r.t_min), double(r.t_max)};
    };
    const auto add_double_mode = [&](const std::string& name, auto mode) {
        methods.push_back(Method{
            name + "_double" + kSuffix, false,
            [&dbvh, mode, widen](const Ray<float>& r) {
                const ClosestHit<double> c = dbvh.closest_hit(PreparedRay<double>(widen(r)), mode);
                return Answer{bool(c), c.index, {}};
            },
            [&dbvh, mode, widen](const std::vector<Ray<float>>& rs) {
                std::int64_t sum = 0;
                for (const Ray<float>& r : rs) sum += dbvh.closest_hit(PreparedRay<double>(widen(r)), mode).index;
                return sum;
            }});
    };
    add_double_mode("fast", fast);
    add_double_mode("conservative", conservative);
    add_double_mode("certified", certified);

#if RAYPROOF_BENCH_HAVE_EMBREE
    std::vector<std::unique_ptr<bench::EmbreeBallScene>> embree;
    for (const bool robust : {false, true}) {
        embree.push_back(std::make_unique<bench::EmbreeBallScene>(balls, robust));
        const bench::EmbreeBallScene* e = embree.back().get();
        const std::string name = robust ? "embree_robust" : "embree";
        built(name, e->build_seconds(), e->bytes(), 4 * sizeof(float));
        methods.push_back(Method{
            name, false,
            [e](const Ray<float>& r) {
                const auto a = e->closest(r);
                return Answer{a.hit, a.index, {}};
            },
            [e](const std::vector<Ray<float>>& rs) {
                std::int64_t sum = 0;
                for (const Ray<float>& r : rs) sum += e->closest(r).index;
                return sum;
            }});
    }
#endif

    // ---- the judgement: the first o.judge rays of each set against the brute-force loop
    std::size_t certified_differs = 0;
    for (std::size_t k = 0; k < 2; ++k) {
        const std::string set = bench::ray_set_name(sets[k]);
        if (kWritesShared) put("bvh-judged-" + set, double(o.judge));
        std::vector<ClosestHit<float>> ref(o.judge);
        const double c0 = thread_cpu_seconds();
        for (std::size_t i = 0; i < o.judge; ++i)
            ref[i] = closest_hit(PreparedRay<float>(rays[k][i]), std::span<const Primitive<float>>(prims), certified);
        const double brute = thread_cpu_seconds() - c0;
        if (o.judge > 0 && kWritesShared) put("bvh-brute-rate-" + set, double(o.judge) / brute);
        std::size_t hits = 0;
        for (const auto& c : ref) hits += bool(c);
        if (kWritesShared) put("bvh-hits-" + set, double(hits));
        for (const Method& m : methods) {
            std::size_t wrong = 0, false_miss = 0, false_hit = 0;
            for (std::size_t i = 0; i < o.judge; ++i) {
                const Answer a = m.ask(rays[k][i]);
                const bool differs = m.exact_bits ? !same_bits(a.full, ref[i])
                                                  : a.hit != bool(ref[i]) || (a.hit && a.index != ref[i].index);
                if (!differs) continue;
                ++wrong;
                false_miss += !a.hit && bool(ref[i]);
                false_hit += a.hit && !bool(ref[i]);
                certified_differs += m.exact_bits;
                if (m.exact_bits)
                    note("certified BVH differs from brute force on " + set + " ray " + std::to_string(i) +
                         " (--seed " + std::to_string(o.seed) + ")");
            }
            put("bvh-wrong-" + set + "-" + m.name, double(wrong));
            put("bvh-falsemiss-" + set + "-" + m.name, double(false_miss));
            put("bvh-falsehit-" + set + "-" + m.name, double(false_hit));
        }
    }

    // ---- the timings: every method in turn within each repetition
    for (std::size_t k = 0; k < 2; ++k) {
        const std::string set = bench::ray_set_name(sets[k]);
        std::vector<std::vector<double>> rate(methods.size());
        std::int64_t sink = 0;
        for (const Method& m : methods) sink += m.pass(rays[k]);  // warm
        for (int rep = 0; rep < o.repetitions; ++rep)
            for (std::size_t j = 0; j < methods.size(); ++j) {
                const double c0 = thread_cpu_seconds();
                sink += methods[j].pass(rays[k]);
                rate[j].push_back(double(rays[k].size()) / (thread_cpu_seconds() - c0));
            }
        for (std::size_t j = 0; j < methods.size(); ++j) put("bvh-rate-" + set + "-" + methods[j].name, median(rate[j]));
        if (sink == 42) note("");  // keeps the passes from being optimized away
    }
    // The certified BVH promises the brute-force answer bit for bit: a difference fails.
    return certified_differs == 0 ? 0 : 3;
}
