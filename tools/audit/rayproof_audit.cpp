// rayproof-audit — what each mode costs in accuracy, measured against the exact oracle.
//
// Runs N cases from every generator (tests/generators) of every shape, for float and
// double, through every mode the kernel provides, judges each answer against the exact
// oracle and prints one row per shape × scalar type × generator × mode:
//
//   rayproof-audit [--cases N] [--seed S] [--shape aabb|obb|plane|sphere|all]
//                  [--type float|double|all] [--generator NAME] [--format md|csv]
//                  [--jobs J] [--examples K] [--check] [--list] [--progress]
//
// Every case is reproducible on its own: case i of a row is generator `g` run on a fresh
// std::mt19937_64 seeded with case_seed(S, shape, type, g, i); --examples prints the first
// K wrong answers of each row with that seed and the inputs in hexfloat, so that
// rayproof::gen::make_case<T, Shape>(g, seed) rebuilds the case.
//
// Rows are computed in parallel (--jobs, default: the hardware threads); the output does
// not depend on the number of jobs.
#include <rayproof/generators.hpp>
#include <rayproof/oracle/contract.hpp>
#include <rayproof/oracle/oracle.hpp>
#include <rayproof/rayproof.hpp>

#include <rayproof/cli.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cctype>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace rayproof;

struct Options {
    std::uint64_t cases = 10000;
    std::uint64_t seed = 0x5eed;
    std::string shape = "all", type = "all", generator, format = "md";
    unsigned jobs = 0;
    unsigned examples = 0;
    bool check = false, list = false, progress = false;
};

// The command line into o; the exit status when the program is to stop.
std::optional<int> parse(int argc, char** argv, Options& o) {
    CLI::App app{"What each mode costs in accuracy, measured against the exact oracle.", "rayproof-audit"};
    app.option_defaults()->always_capture_default();
    app.add_option("--cases", o.cases, "cases per generator, shape and scalar type")->check(cli::positive);
    app.add_option("--seed", o.seed, "master seed (decimal or 0x hex)")->check(cli::non_negative);
    app.add_option("--shape", o.shape, "restrict to one shape")
        ->check(CLI::IsMember({"aabb", "obb", "plane", "sphere", "all"}));
    app.add_option("--type", o.type, "restrict to one scalar type")->check(CLI::IsMember({"float", "double", "all"}));
    app.add_option("--generator", o.generator, "restrict to one generator name (see --list)");
    app.add_option("--format", o.format, "md (a Markdown table with a legend) or csv")
        ->check(CLI::IsMember({"md", "csv"}));
    app.add_option("--jobs", o.jobs, "rows computed in parallel (default: hardware threads)")->check(cli::non_negative);
    app.add_option("--examples", o.examples, "print the first K wrong answers of each row (hexfloat, with seeds)")
        ->check(cli::non_negative);
    app.add_flag("--check", o.check, "exit 1 when any mode breaks its contract (see the legend)");
    app.add_flag("--list", o.list, "list the generators of each shape and exit");
    app.add_flag("--progress", o.progress, "report each finished generator (and its time) on stderr");
    return cli::parse(app, argc, argv);
}

// SplitMix64 (Steele, Lea, Flood 2014): a portable mix of the row identity and index.
std::uint64_t splitmix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}
std::uint64_t case_seed(std::uint64_t master, std::string_view shape, std::string_view type, std::string_view g,
                        std::uint64_t i) {
    std::uint64_t h = splitmix(master);
    h = splitmix(h ^ gen::name_hash(shape));
    h = splitmix(h ^ gen::name_hash(type));
    h = splitmix(h ^ gen::name_hash(g));
    return splitmix(h + i);
}

using oracle::ModeId;
const char* mode_label(ModeId m) { return oracle::to_string(m); }

// One row's counts (t_off: answers whose t is not faithful) and its first wrong answers.
struct Stats {
    oracle::Tally tally;
    std::vector<std::string> examples;
};

struct Row {
    std::string shape, type, generator;
    ModeId mode;
    bool available;
    Stats stats;
};

// What a worker thread is doing, for the stall watchdog: the case seed and since when.
struct Slot {
    std::atomic<std::uint64_t> seed{0};
    std::atomic<std::int64_t> since_ms{-1};  // -1: idle
    std::atomic<std::size_t> job{0};
};
std::int64_t now_ms() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

// One row group: one generator of one shape and scalar type, all modes.
struct Job {
    std::function<void(std::vector<Row>&, Slot&)> run;
    std::vector<Row> rows;
    double seconds = 0;
};

// A contract violation: the answer breaks what its mode promises against the exact answer
// (oracle::check_contract, after docs/semantics.md's table; the fast mode promises only
// that invalid inputs are answered invalid), or verdict() differs from the full answer.
template <class T, class Shape, class Mode>
void judge_into(Stats& s, const gen::Case<T, Shape>& c, const oracle::Exact<T>& e, Mode mode, std::uint64_t seed,
                unsigned max_examples) {
    const ModeId id = oracle::mode_id(mode);
    const Hit<T> h = intersect(c.ray, c.shape, mode);
    const oracle::ContractCheck check = oracle::check_contract(c.ray, c.shape, h, e, mode);
    const oracle::Judgement& j = check.judgement;
    oracle::Tally& t = s.tally;
    ++t.cases;
    t.count_outcome(j);
    if (h.verdict == Verdict::hit && e.verdict == Verdict::hit) t.count_interval(j);
    const std::uint64_t incoherent_before = t.incoherent;
    t.count_coherence(h);
    const bool bad_coherence = t.incoherent != incoherent_before;
    // verdict() promises the full answer's verdict in every mode.
    const Verdict alone = verdict(c.ray, c.shape, mode);
    const bool v = check.promise_broken() || alone != h.verdict;
    if (v) ++t.violations;
    if (s.examples.size() < max_examples && (j.verdict_wrong() || v || bad_coherence)) {
        std::ostringstream os;
        os << "seed 0x" << std::hex << seed << std::dec << ": " << c << "\n    " << mode_label(id) << ": " << h
           << (alone != h.verdict ? " (verdict() alone: " + std::string(to_string(alone)) + ")" : std::string())
           << "\n    " << e << "\n    " << j;
        s.examples.push_back(os.str());
    }
}

template <class T, class Shape>
void add_jobs(const Options& o, std::vector<Job>& jobs) {
    const std::string shape(gen::shape_name<Shape>()), type(gen::scalar_name<T>());
    if ((o.shape != "all" && o.shape != shape) || (o.type != "all" && o.type != type)) return;
    for (const auto& g : gen::generators<T, Shape>()) {
        if (!o.generator.empty() && o.generator != g.name) continue;
        Job job;
        const std::string name(g.name);
        const auto make = g.make;
        for (ModeId m : {ModeId::fast, ModeId::conservative, ModeId::certified}) {
            const bool available = m == ModeId::fast                 ? Answerable<T, Shape, fast_t>
                                   : m == ModeId::conservative ? Answerable<T, Shape, conservative_t>
                                                                     : Answerable<T, Shape, certified_t>;
            job.rows.push_back(Row{shape, type, name, m, available, {}});
        }
        job.run = [&o, shape, type, name, make](std::vector<Row>& rows, Slot& slot) {
            for (std::uint64_t i = 0; i < o.cases; ++i) {
                const std::uint64_t seed = case_seed(o.seed, shape, type, name, i);
                slot.seed = seed;
                slot.since_ms = now_ms();
                gen::Rng rng(seed);
                const gen::Case<T, Shape> c = make(rng);
                const oracle::Exact<T> e = oracle::exact(c.ray, c.shape);
                judge_into(rows[0].stats, c, e, fast, seed, o.examples);
                if constexpr (Answerable<T, Shape, conservative_t>)
                    judge_into(rows[1].stats, c, e, conservative, seed, o.examples);
                if constexpr (Answerable<T, Shape, certified_t>)
                    judge_into(rows[2].stats, c, e, certified, seed, o.examples);
            }
            slot.since_ms = -1;
        };
        jobs.push_back(std::move(job));
    }
}

template <class T, class Shape> void list_generators() {
    std::cout << gen::shape_name<Shape>() << ":";
    for (const auto& g : gen::generators<T, Shape>()) std::cout << ' ' << g.name;
    std::cout << '\n';
}

std::string percent(std::uint64_t num, std::uint64_t den) {
    std::ostringstream os;
    if (num == 0) return "0";
    os << std::setprecision(3) << 100.0 * double(num) / double(den) << '%';
    return os.str();
}
std::string ulps_text(std::uint64_t u) {
    return u == std::numeric_limits<std::uint64_t>::max() ? std::string("NaN") : std::to_string(u);
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (const auto stop = parse(argc, argv, o)) return *stop;
    if (o.list) {
        list_generators<double, Aabb<double>>();
        list_generators<double, Obb<double>>();
        list_generators<double, Plane<double>>();
        list_generators<double, Sphere<double>>();
        return 0;
    }
    std::vector<Job> jobs;
    add_jobs<float, Aabb<float>>(o, jobs);
    add_jobs<double, Aabb<double>>(o, jobs);
    add_jobs<float, Obb<float>>(o, jobs);
    add_jobs<double, Obb<double>>(o, jobs);
    add_jobs<float, Plane<float>>(o, jobs);
    add_jobs<double, Plane<double>>(o, jobs);
    add_jobs<float, Sphere<float>>(o, jobs);
    add_jobs<double, Sphere<double>>(o, jobs);
    if (jobs.empty()) {
        std::cerr << "rayproof-audit: --generator: no generator of the shapes chosen is named '" << o.generator
                  << "' (see --list)\n";
        return cli::usage_error;
    }

    const auto start = std::chrono::steady_clock::now();
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    const unsigned n_threads = std::min<unsigned>(o.jobs ? o.jobs : hw, unsigned(jobs.size()));
    std::atomic<std::size_t> next{0};
    std::mutex progress_mutex;
    std::vector<Slot> slots(n_threads);
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < n_threads; ++t)
        pool.emplace_back([&, t]() {
            for (std::size_t k; (k = next++) < jobs.size();) {
                slots[t].job = k;
                const auto t0 = std::chrono::steady_clock::now();
                jobs[k].run(jobs[k].rows, slots[t]);
                jobs[k].seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                if (o.progress) {
                    const std::lock_guard<std::mutex> lock(progress_mutex);
                    const Row& r = jobs[k].rows.front();
                    std::cerr << "done: " << r.shape << ' ' << r.type << ' ' << r.generator << " in " << jobs[k].seconds
                              << " s\n";
                }
            }
        });
    // Watchdog: a single case running for more than 10 s is reported once on stderr with
    // its seed, so that a stall (a bug in some mode) can be reproduced.
    std::atomic<bool> finished{false};
    std::thread watchdog([&]() {
        std::vector<std::uint64_t> reported(n_threads, 0);
        while (!finished) {
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
            for (unsigned t = 0; t < n_threads; ++t) {
                const std::int64_t since = slots[t].since_ms;
                const std::uint64_t seed = slots[t].seed;
                if (since < 0 || now_ms() - since < 10000 || reported[t] == seed + 1) continue;
                reported[t] = seed + 1;
                const Row& r = jobs[slots[t].job].rows.front();
                const std::lock_guard<std::mutex> lock(progress_mutex);
                std::cerr << "rayproof-audit: one case has been running for over 10 s: " << r.shape << ' ' << r.type
                          << ' ' << r.generator << ", seed 0x" << std::hex << seed << std::dec
                          << " (rayproof::gen::make_case<" << r.type << ", rayproof::" << char(std::toupper(r.shape[0]))
                          << r.shape.substr(1) << '<' << r.type << ">>(\"" << r.generator << "\", 0x" << std::hex
                          << seed << std::dec << "))\n";
            }
        }
    });
    for (auto& th : pool) th.join();
    finished = true;
    watchdog.join();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::vector<const Row*> rows;
    std::vector<std::string> skipped;
    for (const auto& j : jobs)
        for (const auto& r : j.rows) {
            if (r.available) {
                rows.push_back(&r);
            } else {
                const std::string s = std::string(mode_label(r.mode)) + " (" + r.shape + ", " + r.type + ")";
                if (std::find(skipped.begin(), skipped.end(), s) == skipped.end()) skipped.push_back(s);
            }
        }

    std::uint64_t total_violations = 0;
    for (const Row* r : rows) total_violations += r->stats.tally.violations;

    if (o.format == "csv") {
        std::cout << "shape,type,generator,mode,cases,wrong_verdict_rate,false_hits,false_misses,invalid_mismatches,"
                     "face_mismatches,t_not_faithful,t_not_enclosing,incoherent_hits,max_t_error_ulps,contract_violations\n";
        for (const Row* r : rows) {
            const oracle::Tally& s = r->stats.tally;
            const std::uint64_t wrong = s.wrong();
            std::cout << r->shape << ',' << r->type << ',' << r->generator << ',' << mode_label(r->mode) << ','
                      << s.cases << ',' << std::setprecision(6) << double(wrong) / double(s.cases) << ','
                      << s.false_hit << ',' << s.false_miss << ',' << s.invalid_mismatch << ',' << s.face_mismatch
                      << ',' << s.t_off << ',' << s.not_enclosing << ',' << s.incoherent << ','
                      << ulps_text(s.max_ulps) << ',' << s.violations << '\n';
        }
    } else {
        std::cout << "# rayproof-audit\n\n"
                  << o.cases << " cases per generator, shape and scalar type; seed 0x" << std::hex << o.seed
                  << std::dec << "; " << std::fixed << std::setprecision(1) << seconds << " s on " << n_threads
                  << " thread(s).\n";
        std::cout.unsetf(std::ios::floatfield);
        if (!skipped.empty()) {
            std::cout << "\nNot in this build (rayproof::Answerable is false), so not audited:";
            for (const auto& s : skipped) std::cout << ' ' << s << ';';
            std::cout << '\n';
        }
        std::cout << "\n| shape | type | generator | mode | wrong verdict | false hits | false misses | invalid "
                     "mismatches | face mismatches | t not faithful | max t error (ulps) | contract violations |\n"
                     "|---|---|---|---|--:|--:|--:|--:|--:|--:|--:|--:|\n";
        for (const Row* r : rows) {
            const oracle::Tally& s = r->stats.tally;
            const std::uint64_t wrong = s.wrong();
            std::cout << "| " << r->shape << " | " << r->type << " | " << r->generator << " | " << mode_label(r->mode)
                      << " | " << percent(wrong, s.cases) << " | " << s.false_hit << " | " << s.false_miss << " | "
                      << s.invalid_mismatch << " | " << s.face_mismatch << " | " << percent(s.t_off, s.cases)
                      << " | " << ulps_text(s.max_ulps) << " | " << s.violations << " |\n";
        }
        std::cout << "\nLegend: *wrong verdict* is the share of cases whose verdict differs from the exact one "
                     "(false hits + false misses + invalid mismatches). *t not faithful*: cases answered hit with "
                     "t_enter or t_exit not one of the two floats enclosing the exact value; *max t error* counts "
                     "representable values between the answer and the nearest faithful rounding (0: faithful; NaN: "
                     "a hit with a NaN t). *Contract violations*: fast, an invalid input not answered invalid (or "
                     "the reverse); conservative, a false miss, an invalid mismatch or an interval not enclosing "
                     "the exact one; certified, any answer other than the exact verdict and face with faithful "
                     "t; every mode, verdict() (the verdict alone) differing from the full answer's verdict.\n";
        std::uint64_t incoherent = 0;
        for (const Row* r : rows) incoherent += r->stats.tally.incoherent;
        if (incoherent)
            std::cout << "\n" << incoherent
                      << " answers were `hit` with t_enter > t_exit or a NaN t (see --examples).\n";
    }
    if (o.examples) {
        for (const Row* r : rows)
            for (const auto& ex : r->stats.examples)
                std::cout << "\n[" << r->shape << ' ' << r->type << ' ' << r->generator << ' ' << mode_label(r->mode)
                          << "] " << ex << '\n';
    }
    if (o.check && total_violations) {
        std::cerr << "rayproof-audit: " << total_violations << " contract violations\n";
        return 1;
    }
    return 0;
}
