// rayproof-audit — what each mode costs in accuracy, measured against the exact oracle.
//
// Runs N cases from every generator (tests/generators) of every shape, for float and
// double, through every mode the kernel provides, judges each answer against the exact
// oracle and prints one row per shape × scalar type × generator × mode, and the number of
// cases each generator ran:
//
//   rayproof-audit [--cases N] [--seed S] [--shape aabb|obb|plane|sphere|polyhedron|all]
//                  [--type float|double|all] [--generator NAME] [--format md|csv]
//                  [--jobs J] [--examples K] [--check] [--list] [--progress]
//                  [--shard K/N] [--save FILE]
//   rayproof-audit --merge FILE... [--format md|csv] [--check]
//
// Every case is reproducible on its own: case i of a row is generator `g` run on a fresh
// std::mt19937_64 seeded with case_seed(S, shape, type, g, i); --examples prints the first
// K wrong answers of each row with that seed and the inputs in hexfloat, so that
// rayproof::gen::make_case<T, Shape>(g, seed) rebuilds the case.
//
// Rows are computed in parallel (--jobs, default: the hardware threads); the output does
// not depend on the number of jobs.
//
// A long run scales out over machines: --shard K/N runs, of every row, the cases i with
// i mod N == K - 1 (so each shard does about 1/N of every row, whatever the rows cost),
// and --save FILE writes what it found (per-row tallies, the first K wrong answers with
// their case indices) as a small tab-separated file. --merge adds up the files of shards
// 1..N of one run (same options, each shard once) and prints the report a single run
// prints: the same counts, the same examples, the same text but for the timing.
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
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
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
    std::string shard;                 // "K/N" as given
    std::uint64_t shard_k = 1, shard_n = 1;  // this run: cases i with i mod N == K - 1
    std::string save;                  // --save FILE
    std::vector<std::string> merge;    // --merge FILE...
};

// "K/N" with 1 <= K <= N into k, n; an error message otherwise.
std::string parse_shard(const std::string& s, std::uint64_t& k, std::uint64_t& n) {
    const std::string expected = "expects K/N, shard K of N with 1 <= K <= N (e.g. 3/8), got '" + s + "'";
    const auto slash = s.find('/');
    const auto number = [](const std::string& t, std::uint64_t& v) {
        if (t.empty() || t.size() > 9 || t.find_first_not_of("0123456789") != std::string::npos) return false;
        v = std::stoull(t);
        return true;
    };
    if (slash == std::string::npos || !number(s.substr(0, slash), k) || !number(s.substr(slash + 1), n))
        return expected;
    if (n == 0) return "expects K/N with N >= 1 shards, got '" + s + "'";
    if (k == 0 || k > n) return "expects K/N with 1 <= K <= N (shards are numbered from 1), got '" + s + "'";
    return {};
}

// The command line into o; the exit status when the program is to stop.
std::optional<int> parse(int argc, char** argv, Options& o) {
    CLI::App app{"What each mode costs in accuracy, measured against the exact oracle.", "rayproof-audit"};
    app.option_defaults()->always_capture_default();
    app.add_option("--cases", o.cases, "cases per generator, shape and scalar type")->check(cli::positive);
    app.add_option("--seed", o.seed, "master seed (decimal or 0x hex)")->check(cli::non_negative);
    app.add_option("--shape", o.shape, "restrict to one shape")
        ->check(CLI::IsMember({"aabb", "obb", "plane", "sphere", "polyhedron", "all"}));
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
    auto* shard = app.add_option("--shard", o.shard,
                                 "run shard K of N: of every row, the cases i with i mod N == K - 1 (K in 1..N)")
                      ->check(CLI::Validator(
                          [](std::string& s) {
                              std::uint64_t k, n;
                              return parse_shard(s, k, n);
                          },
                          "K/N"));
    app.add_option("--save", o.save, "also write the results in mergeable form (tab-separated) to FILE");
    auto* merge = app.add_option("--merge", o.merge,
                                 "add up the --save files of shards 1..N of one run and print its report")
                      ->expected(1, -1)
                      ->check(CLI::ExistingFile);
    for (const char* other : {"--cases", "--seed", "--shape", "--type", "--generator", "--jobs", "--examples", "--list",
                              "--progress", "--save"})
        merge->excludes(app.get_option(other));
    merge->excludes(shard);
    if (const auto stop = cli::parse(app, argc, argv)) return stop;
    if (!o.shard.empty()) parse_shard(o.shard, o.shard_k, o.shard_n);
    return std::nullopt;
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

// A wrong answer kept for --examples: the case index in its row and the text printed.
struct Example {
    std::uint64_t index;
    std::string text;
};

// One row's counts (t_off: answers whose t is not faithful) and its first wrong answers.
struct Stats {
    oracle::Tally tally;
    std::vector<Example> examples;
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

// The kernel's shape of a case's shape: itself, or the ConvexPolyhedron over the planes
// a polyhedron case owns (gen::OwnedPolyhedron).
template <class S> const S& kernel_shape(const S& s) { return s; }
template <class T> ConvexPolyhedron<T> kernel_shape(const gen::OwnedPolyhedron<T>& p) { return p.view(); }
template <class S> using KernelShape = std::remove_cvref_t<decltype(kernel_shape(std::declval<const S&>()))>;

// The case's C++ type as make_case spells it, for the slow-case message.
std::string shape_type(const std::string& shape, const std::string& type) {
    if (shape == "polyhedron") return "rayproof::gen::OwnedPolyhedron<" + type + ">";
    return "rayproof::" + std::string(1, char(std::toupper(shape[0]))) + shape.substr(1) + '<' + type + '>';
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
void judge_into(Stats& s, const gen::Case<T, Shape>& c, const oracle::Exact<T>& e, Mode mode, std::uint64_t index,
                std::uint64_t seed, unsigned max_examples) {
    const ModeId id = oracle::mode_id(mode);
    const auto shape = kernel_shape(c.shape);
    const Hit<T> h = intersect(c.ray, shape, mode);
    const oracle::ContractCheck check = oracle::check_contract(c.ray, shape, h, e, mode);
    const oracle::Judgement& j = check.judgement;
    oracle::Tally& t = s.tally;
    ++t.cases;
    t.count_outcome(j);
    if (h.verdict == Verdict::hit && e.verdict == Verdict::hit) t.count_interval(j);
    const std::uint64_t incoherent_before = t.incoherent;
    t.count_coherence(h);
    const bool bad_coherence = t.incoherent != incoherent_before;
    // verdict() promises the full answer's verdict in every mode.
    const Verdict alone = verdict(c.ray, shape, mode);
    const bool v = check.promise_broken() || alone != h.verdict;
    if (v) ++t.violations;
    if (s.examples.size() < max_examples && (j.verdict_wrong() || v || bad_coherence)) {
        std::ostringstream os;
        os << "seed 0x" << std::hex << seed << std::dec << ": " << c << "\n    " << mode_label(id) << ": " << h
           << (alone != h.verdict ? " (verdict() alone: " + std::string(to_string(alone)) + ")" : std::string())
           << "\n    " << e << "\n    " << j;
        s.examples.push_back(Example{index, os.str()});
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
            using K = KernelShape<Shape>;
            const bool available = m == ModeId::fast           ? Answerable<T, K, fast_t>
                                   : m == ModeId::conservative ? Answerable<T, K, conservative_t>
                                                               : Answerable<T, K, certified_t>;
            job.rows.push_back(Row{shape, type, name, m, available, {}});
        }
        job.run = [&o, shape, type, name, make](std::vector<Row>& rows, Slot& slot) {
            for (std::uint64_t i = o.shard_k - 1; i < o.cases; i += o.shard_n) {  // this shard's cases
                const std::uint64_t seed = case_seed(o.seed, shape, type, name, i);
                slot.seed = seed;
                slot.since_ms = now_ms();
                gen::Rng rng(seed);
                const gen::Case<T, Shape> c = make(rng);
                const oracle::Exact<T> e = oracle::exact(c.ray, kernel_shape(c.shape));
                judge_into(rows[0].stats, c, e, fast, i, seed, o.examples);
                if constexpr (Answerable<T, KernelShape<Shape>, conservative_t>)
                    judge_into(rows[1].stats, c, e, conservative, i, seed, o.examples);
                if constexpr (Answerable<T, KernelShape<Shape>, certified_t>)
                    judge_into(rows[2].stats, c, e, certified, i, seed, o.examples);
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

// What a run found, or the shards of one run added up: what the report prints and what
// --save writes.
struct Report {
    std::uint64_t cases = 0, seed = 0;
    std::string shape, type, generator;
    unsigned examples = 0;
    std::uint64_t shard_n = 1;
    std::vector<std::uint64_t> shards;  // the shards (1..N) it holds
    double seconds = 0;                 // wall time (a merge: the shards' times added up)
    unsigned threads = 0;               // 0: merged
    std::vector<Row> rows;
};

// The run's options as the header line of a saved file: shards of one run share it.
std::string run_line(const Report& r) {
    std::ostringstream os;
    os << "run\tcases\t" << r.cases << "\tseed\t" << r.seed << "\tshape\t" << r.shape << "\ttype\t" << r.type
       << "\tgenerator\t" << (r.generator.empty() ? "*" : r.generator) << "\texamples\t" << r.examples
       << "\tshards\t" << r.shard_n;
    return os.str();
}

// The tally's fields, in the order a saved file lists them; merged by adding them up,
// max_ulps by taking the larger.
constexpr std::uint64_t oracle::Tally::* tally_fields[] = {
    &oracle::Tally::cases,          &oracle::Tally::exact_hits,   &oracle::Tally::refused,
    &oracle::Tally::false_hit,      &oracle::Tally::false_miss,   &oracle::Tally::invalid_mismatch,
    &oracle::Tally::face_mismatch,  &oracle::Tally::t_judged,     &oracle::Tally::t_off,
    &oracle::Tally::max_ulps,       &oracle::Tally::not_enclosing, &oracle::Tally::incoherent,
    &oracle::Tally::violations};
static_assert(sizeof(oracle::Tally) == sizeof(tally_fields) / sizeof(tally_fields[0]) * sizeof(std::uint64_t),
              "oracle::Tally has a field that tally_fields does not save and merge");

// Example texts hold newlines and tabs: escaped as \n, \t and \\ in a saved file.
std::string escaped(const std::string& s) {
    std::string out;
    for (const char c : s) out += c == '\n' ? "\\n" : c == '\t' ? "\\t" : c == '\\' ? "\\\\" : std::string(1, c);
    return out;
}
std::string unescaped(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '\\' && i + 1 < s.size()) {
            const char c = s[++i];
            out += c == 'n' ? '\n' : c == 't' ? '\t' : c;
        } else {
            out += s[i];
        }
    }
    return out;
}
std::vector<std::string> fields(const std::string& line) {
    std::vector<std::string> f;
    std::size_t at = 0;
    for (std::size_t tab; (tab = line.find('\t', at)) != std::string::npos; at = tab + 1)
        f.push_back(line.substr(at, tab - at));
    f.push_back(line.substr(at));
    return f;
}

// The saved form: a comment, the run line, "shard K" lines, "time SECONDS", then one
// "row" line per row (shape, type, generator, mode, available, the tally fields) and one
// "example" line per kept wrong answer (row number, case index, text).
void save(const Report& r, std::ostream& out) {
    out << "# rayproof-audit results; add up the shards of a run with rayproof-audit --merge FILE...\n"
        << run_line(r) << '\n';
    for (const std::uint64_t k : r.shards) out << "shard\t" << k << '\n';
    out << "time\t" << r.seconds << '\n';
    for (const Row& row : r.rows) {
        out << "row\t" << row.shape << '\t' << row.type << '\t' << row.generator << '\t' << mode_label(row.mode) << '\t'
            << row.available;
        for (const auto field : tally_fields) out << '\t' << row.stats.tally.*field;
        out << '\n';
    }
    for (std::size_t i = 0; i < r.rows.size(); ++i)
        for (const Example& e : r.rows[i].stats.examples)
            out << "example\t" << i << '\t' << e.index << '\t' << escaped(e.text) << '\n';
}

// A saved file back into a report; an error message when it is not one.
std::optional<std::string> load(const std::string& path, Report& r) {
    std::ifstream in(path);
    if (!in) return path + ": cannot be read";
    std::string line;
    int n = 0;
    const auto bad = [&](const std::string& why) { return path + ":" + std::to_string(n) + ": " + why; };
    const auto number = [](const std::string& t, std::uint64_t& v) {
        if (t.empty() || t.find_first_not_of("0123456789") != std::string::npos) return false;
        v = std::stoull(t);
        return true;
    };
    bool have_run = false;
    while (std::getline(in, line)) {
        ++n;
        if (line.empty() || line[0] == '#') continue;
        const std::vector<std::string> f = fields(line);
        if (f[0] == "run") {
            std::uint64_t examples = 0;
            if (f.size() != 15 || f[1] != "cases" || !number(f[2], r.cases) || f[3] != "seed" ||
                !number(f[4], r.seed) || f[5] != "shape" || f[7] != "type" || f[9] != "generator" ||
                f[11] != "examples" || !number(f[12], examples) || f[13] != "shards" || !number(f[14], r.shard_n) ||
                r.shard_n == 0)
                return bad("not a run line of rayproof-audit --save");
            r.shape = f[6], r.type = f[8], r.generator = f[10] == "*" ? "" : f[10], r.examples = unsigned(examples);
            have_run = true;
        } else if (!have_run) {
            return bad("not a file written by rayproof-audit --save (no run line first)");
        } else if (f[0] == "shard") {
            std::uint64_t k = 0;
            if (f.size() != 2 || !number(f[1], k) || k == 0 || k > r.shard_n) return bad("bad shard line");
            r.shards.push_back(k);
        } else if (f[0] == "time") {
            if (f.size() != 2) return bad("bad time line");
            r.seconds = std::strtod(f[1].c_str(), nullptr);
        } else if (f[0] == "row") {
            constexpr std::size_t n_fields = sizeof(tally_fields) / sizeof(tally_fields[0]);
            std::uint64_t available = 0;
            const bool mode_ok = f.size() == 6 + n_fields &&
                                 (f[4] == "fast" || f[4] == "conservative" || f[4] == "certified") &&
                                 number(f[5], available) && available <= 1;
            if (!mode_ok) return bad("bad row line");
            Row row{f[1], f[2], f[3], ModeId::certified, false, {}};
            if (f[4] == "fast") row.mode = ModeId::fast;
            if (f[4] == "conservative") row.mode = ModeId::conservative;
            row.available = available == 1;
            for (std::size_t i = 0; i < n_fields; ++i)
                if (!number(f[6 + i], row.stats.tally.*tally_fields[i])) return bad("bad count in a row line");
            r.rows.push_back(std::move(row));
        } else if (f[0] == "example") {
            std::uint64_t row = 0, index = 0;
            if (f.size() != 4 || !number(f[1], row) || row >= r.rows.size() || !number(f[2], index))
                return bad("bad example line");
            r.rows[row].stats.examples.push_back(Example{index, unescaped(f[3])});
        } else {
            return bad("unknown line '" + f[0] + "'");
        }
    }
    if (!have_run) return path + ": not a file written by rayproof-audit --save (empty)";
    return std::nullopt;
}

// The reports of shards 1..N of one run added up, each shard once; an error message when
// they are not that.
std::optional<std::string> merge(const std::vector<std::string>& paths, Report& out) {
    std::vector<Report> parts(paths.size());
    for (std::size_t i = 0; i < paths.size(); ++i)
        if (auto error = load(paths[i], parts[i])) return error;
    out = parts[0];
    out.shards.clear();
    out.seconds = 0;
    out.threads = 0;
    for (Row& row : out.rows) row.stats = {};
    std::vector<std::string> holder(out.shard_n + 1);
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const Report& p = parts[i];
        if (run_line(p) != run_line(out))
            return paths[i] + " is from another run than " + paths[0] + " (" + run_line(p) + " vs " + run_line(out) +
                   ")";
        if (p.rows.size() != out.rows.size()) return paths[i] + " has other rows than " + paths[0];
        for (const std::uint64_t k : p.shards) {
            if (!holder[k].empty())
                return "shard " + std::to_string(k) + "/" + std::to_string(out.shard_n) + " is in both " + holder[k] +
                       " and " + paths[i];
            holder[k] = paths[i];
            out.shards.push_back(k);
        }
        out.seconds += p.seconds;
        for (std::size_t j = 0; j < p.rows.size(); ++j) {
            const Row& a = p.rows[j];
            Row& b = out.rows[j];
            if (a.shape != b.shape || a.type != b.type || a.generator != b.generator || a.mode != b.mode)
                return paths[i] + " has other rows than " + paths[0];
            for (const auto field : tally_fields)
                b.stats.tally.*field = field == &oracle::Tally::max_ulps
                                           ? std::max(b.stats.tally.*field, a.stats.tally.*field)
                                           : b.stats.tally.*field + a.stats.tally.*field;
            b.stats.examples.insert(b.stats.examples.end(), a.stats.examples.begin(), a.stats.examples.end());
        }
    }
    std::string missing;
    for (std::uint64_t k = 1; k <= out.shard_n; ++k)
        if (holder[k].empty()) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
    if (!missing.empty())
        return "shard(s) " + missing + " of " + std::to_string(out.shard_n) + " missing: give the files of all shards";
    std::sort(out.shards.begin(), out.shards.end());
    // Each shard kept its first K wrong answers, so the first K of the union by case index
    // are the first K of the whole run.
    for (Row& row : out.rows) {
        std::stable_sort(row.stats.examples.begin(), row.stats.examples.end(),
                         [](const Example& x, const Example& y) { return x.index < y.index; });
        if (row.stats.examples.size() > out.examples) row.stats.examples.resize(out.examples);
    }
    return std::nullopt;
}

// The report on stdout (Markdown or CSV); the exit status: 1 under --check when a
// contract was broken.
int print_report(const Report& report, const Options& o) {
    std::vector<const Row*> rows;
    std::vector<std::string> skipped;
    for (const auto& r : report.rows) {
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
                      << s.cases << ',' << std::setprecision(6) << (s.cases ? double(wrong) / double(s.cases) : 0.0)
                      << ',' << s.false_hit << ',' << s.false_miss << ',' << s.invalid_mismatch << ','
                      << s.face_mismatch << ',' << s.t_off << ',' << s.not_enclosing << ',' << s.incoherent << ','
                      << ulps_text(s.max_ulps) << ',' << s.violations << '\n';
        }
    } else {
        std::cout << "# rayproof-audit\n\n"
                  << report.cases << " cases per generator, shape and scalar type; seed 0x" << std::hex << report.seed
                  << std::dec << "; " << std::fixed << std::setprecision(1);
        if (report.threads == 0)
            std::cout << "merged from " << report.shard_n << " shards, " << report.seconds << " s of work in all.\n";
        else if (report.shard_n > 1)
            std::cout << "shard " << report.shards.front() << '/' << report.shard_n << " (the cases i with i mod "
                      << report.shard_n << " == " << report.shards.front() - 1 << "), " << report.seconds << " s on "
                      << report.threads << " thread(s).\n";
        else
            std::cout << report.seconds << " s on " << report.threads << " thread(s).\n";
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
        // The cases each generator ran (every mode judges each case once: the fast row's count).
        std::cout << "\nCases per generator:\n";
        std::string group;
        for (const auto& r : report.rows) {
            if (r.mode != ModeId::fast) continue;
            const std::string g = r.shape + ' ' + r.type;
            std::cout << (g == group ? ", " : group.empty() ? "- " + g + ": " : "\n- " + g + ": ") << r.generator << ' '
                      << r.stats.tally.cases;
            group = g;
        }
        std::cout << '\n';
        std::uint64_t incoherent = 0;
        for (const Row* r : rows) incoherent += r->stats.tally.incoherent;
        if (incoherent)
            std::cout << "\n" << incoherent
                      << " answers were `hit` with t_enter > t_exit or a NaN t (see --examples).\n";
    }
    if (report.examples) {
        for (const Row* r : rows)
            for (const auto& ex : r->stats.examples)
                std::cout << "\n[" << r->shape << ' ' << r->type << ' ' << r->generator << ' ' << mode_label(r->mode)
                          << "] " << ex.text << '\n';
    }
    if (o.check && total_violations) {
        std::cerr << "rayproof-audit: " << total_violations << " contract violations\n";
        return 1;
    }
    return 0;
}

// Runs the jobs on o.jobs threads (with the stall watchdog); returns the wall time.
double run_jobs(const Options& o, std::vector<Job>& jobs, unsigned n_threads) {
    const auto start = std::chrono::steady_clock::now();
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
                          << " (rayproof::gen::make_case<" << r.type << ", " << shape_type(r.shape, r.type)
                          << ">(\"" << r.generator << "\", 0x" << std::hex
                          << seed << std::dec << "))\n";
            }
        }
    });
    for (auto& th : pool) th.join();
    finished = true;
    watchdog.join();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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
        list_generators<double, gen::OwnedPolyhedron<double>>();
        return 0;
    }
    if (!o.merge.empty()) {
        Report merged;
        if (const auto error = merge(o.merge, merged)) {
            std::cerr << "rayproof-audit: --merge: " << *error << '\n';
            return 1;
        }
        return print_report(merged, o);
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
    add_jobs<float, gen::OwnedPolyhedron<float>>(o, jobs);
    add_jobs<double, gen::OwnedPolyhedron<double>>(o, jobs);
    if (jobs.empty()) {
        std::cerr << "rayproof-audit: --generator: no generator of the shapes chosen is named '" << o.generator
                  << "' (see --list)\n";
        return cli::usage_error;
    }

    // The --save file is opened before the run, so that a bad path costs no run.
    std::ofstream saved;
    if (!o.save.empty()) {
        saved.open(o.save);
        if (!saved) {
            std::cerr << "rayproof-audit: --save: cannot write " << o.save << '\n';
            return 1;
        }
    }
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    Report report;
    report.cases = o.cases, report.seed = o.seed, report.shape = o.shape, report.type = o.type;
    report.generator = o.generator, report.examples = o.examples, report.shard_n = o.shard_n;
    report.shards = {o.shard_k};
    report.threads = std::min<unsigned>(o.jobs ? o.jobs : hw, unsigned(jobs.size()));
    report.seconds = run_jobs(o, jobs, report.threads);
    for (auto& j : jobs)
        for (auto& r : j.rows) report.rows.push_back(std::move(r));
    if (!o.save.empty()) {
        save(report, saved);
        saved.close();
        if (!saved) {
            std::cerr << "rayproof-audit: --save: cannot write " << o.save << '\n';
            return 1;
        }
    }
    return print_report(report, o);
}
