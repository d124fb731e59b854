// kernel_measure — evidence that a change to the kernel changed no answer and no cost.
// Not a test (it asserts nothing): run it before and after a change and compare.
//   kernel_measure hash [cases]          FNV-1a of every answer (verdict, t_enter and
//       t_exit bits, face; and verdict() alone) over `cases` (default 200000) cases per
//       shape × scalar type × mode, drawn round-robin from every generator of the
//       shared registry with a fixed seed: equal hashes mean equal answers.
//   kernel_measure count [cases] [Shape] the uniform (`general`) cases through
//       intersect() and verdict() per shape × type × mode, each combination between
//       callgrind's zero and dump client requests (a no-op outside valgrind):
//         valgrind --tool=callgrind --callgrind-out-file=cg.%p kernel_measure count 4000
//       then each dump's "totals:" divided by the case count is instructions per query.
//   kernel_measure_counters rates [cases]  the exact-stage rate of the certified mode
//       per shape × type × generator (built with RAYPROOF_COUNTERS=1).
#include <rayproof/generators.hpp>
#include <rayproof/rayproof.hpp>
#include <valgrind/callgrind.h>

#include <rayproof/cli.hpp>

#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

using namespace rayproof;

struct Fnv {
    std::uint64_t h = 0xcbf29ce484222325ull;
    void add(const void* p, std::size_t n) {
        const auto* b = static_cast<const unsigned char*>(p);
        for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
    }
    template <class X> void put(X x) { add(&x, sizeof x); }
};

template <class T> const char* tname() { return std::is_same_v<T, float> ? "float" : "double"; }
template <class S> const char* sname();
template <> const char* sname<Aabb<float>>() { return "Aabb"; }
template <> const char* sname<Aabb<double>>() { return "Aabb"; }
template <> const char* sname<Obb<float>>() { return "Obb"; }
template <> const char* sname<Obb<double>>() { return "Obb"; }
template <> const char* sname<Plane<float>>() { return "Plane"; }
template <> const char* sname<Plane<double>>() { return "Plane"; }
template <> const char* sname<Sphere<float>>() { return "Sphere"; }
template <> const char* sname<Sphere<double>>() { return "Sphere"; }

template <class T, class Shape> std::vector<gen::Case<T, Shape>> mixed_cases(std::size_t n) {
    const auto gens = gen::generators<T, Shape>();
    std::vector<gen::Case<T, Shape>> out;
    out.reserve(n);
    gen::Rng rng(20261202);
    for (std::size_t i = 0; i < n; ++i) out.push_back(gens[i % gens.size()].make(rng));
    return out;
}
template <class T, class Shape> std::vector<gen::Case<T, Shape>> uniform_cases(std::size_t n) {
    const auto gens = gen::generators<T, Shape>();
    std::vector<gen::Case<T, Shape>> out;
    gen::Rng rng(20240611);
    for (std::size_t i = 0; i < n; ++i) out.push_back(gens[0].make(rng));
    return out;
}

template <class T, class Shape, class Mode> void hash_one(const std::vector<gen::Case<T, Shape>>& cs, Mode m) {
    Fnv full, ver;
    for (const auto& c : cs) {
        const Hit<T> h = intersect(c.ray, c.shape, m);
        full.put(int(h.verdict));
        full.put(std::bit_cast<std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>>(h.t_enter));
        full.put(std::bit_cast<std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>>(h.t_exit));
        full.put(h.face);
        ver.put(int(verdict(c.ray, c.shape, m)));
    }
    std::printf("%-6s %-6s %-12s intersect %016llx verdict %016llx\n", sname<Shape>(), tname<T>(), mode_name(m),
                (unsigned long long)full.h, (unsigned long long)ver.h);
}
template <class T, class Shape> void hash_shape(std::size_t n) {
    const auto cs = mixed_cases<T, Shape>(n);
    hash_one(cs, fast);
    hash_one(cs, conservative);
    hash_one(cs, certified);
}

volatile int sink_i;
volatile double sink_d;
template <class T, class Shape, class Mode, bool VerdictOnly>
__attribute__((noinline)) void run(const std::vector<gen::Case<T, Shape>>& cs, Mode m) {
    char name[96];
    std::snprintf(name, sizeof name, "%s-%s-%s-%s", sname<Shape>(), tname<T>(), mode_name(m),
                  VerdictOnly ? "verdict" : "intersect");
    int acc = 0;
    double accd = 0;
    CALLGRIND_ZERO_STATS;
    for (const auto& c : cs) {
        if constexpr (VerdictOnly) {
            acc += int(verdict(c.ray, c.shape, m));
        } else {
            const Hit<T> h = intersect(c.ray, c.shape, m);
            acc += int(h.verdict) + h.face;
            accd += double(h.t_enter) + double(h.t_exit);
        }
    }
    CALLGRIND_DUMP_STATS_AT(name);
    sink_i = acc;
    sink_d = accd;
}
const char* only_shape = nullptr;
template <class T, class Shape> void count_shape(std::size_t n) {
    if (only_shape && std::strcmp(only_shape, sname<Shape>()) != 0) return;
    const auto cs = uniform_cases<T, Shape>(n);
    run<T, Shape, fast_t, false>(cs, fast);
    run<T, Shape, conservative_t, false>(cs, conservative);
    run<T, Shape, certified_t, false>(cs, certified);
    run<T, Shape, fast_t, true>(cs, fast);
    run<T, Shape, conservative_t, true>(cs, conservative);
    run<T, Shape, certified_t, true>(cs, certified);
}

#ifdef RAYPROOF_COUNTERS
template <class T, class Shape> void rates_shape(std::size_t n) {
    for (const auto& g : gen::generators<T, Shape>()) {
        gen::Rng rng(gen::name_hash(g.name) ^ 20240611);
        detail::exact_stage_counters = {};
        for (std::size_t i = 0; i < n; ++i) {
            const auto c = g.make(rng);
            sink_i = int(intersect(c.ray, c.shape, certified).verdict);
        }
        const auto q = detail::exact_stage_counters;
        std::printf("%-6s %-6s %-16s queries %8llu exact %7llu rate %.6f\n", sname<Shape>(), tname<T>(),
                    std::string(g.name).c_str(), q.queries, q.exact, q.queries ? double(q.exact) / q.queries : 0.0);
    }
}
#endif

template <class F> void each(F&& f) {
    f.template operator()<float, Aabb<float>>();
    f.template operator()<double, Aabb<double>>();
    f.template operator()<float, Obb<float>>();
    f.template operator()<double, Obb<double>>();
    f.template operator()<float, Plane<float>>();
    f.template operator()<double, Plane<double>>();
    f.template operator()<float, Sphere<float>>();
    f.template operator()<double, Sphere<double>>();
}

int main(int argc, char** argv) {
    CLI::App app{"Evidence that a change to the kernel changed no answer and no cost.", "kernel_measure"};
    std::string what = "hash", shape;
    std::size_t n = 200000;
    app.add_option("what", what, "hash (default), count, rates (kernel_measure_counters)")
        ->check(CLI::IsMember({"hash", "count", "rates"}));
    app.add_option("cases", n, "cases per combination")->capture_default_str();
    app.add_option("Shape", shape, "count: this shape alone")->check(CLI::IsMember({"Aabb", "Obb", "Plane", "Sphere"}));
    if (const auto stop = rayproof::cli::parse(app, argc, argv)) return *stop;
    if (!shape.empty()) only_shape = shape.c_str();
    if (what == "hash") each([&]<class T, class S>() { hash_shape<T, S>(n); });
    if (what == "count") each([&]<class T, class S>() { count_shape<T, S>(n); });
#ifdef RAYPROOF_COUNTERS
    if (what == "rates") each([&]<class T, class S>() { rates_shape<T, S>(n); });
#else
    if (what == "rates") return rayproof::cli::report(app, CLI::ValidationError("what", "rates: run kernel_measure_counters"));
#endif
    return 0;
}
