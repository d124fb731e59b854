// bench/trade_report.cpp — turns one run of the trade into its report: reads the
// benchmark JSON (rayproof_bench, rayproof_bench_counters), the accuracy CSV
// (rayproof_trade_accuracy) and the tracer timings, and writes
//   - the Markdown report (--md FILE): the summary, the acceptance checks, the full
//     speed/accuracy table per shape, the batch sweep, the exact-stage rates, the tracer
//     comparison, with the date, compiler and flags given as --meta KEY=VALUE;
//   - the summary and the checks on stdout;
//   - the plot's data and gnuplot script (--plot-dir DIR: trade.dat, trade.gp, drawing
//     --plot-png FILE): time per query against wrong-verdict rate, one point per
//     (method, shape, type), one panel per workload.
//
//   rayproof_trade_report --bench B.json [--counters C.json] [--accuracy A.csv ...]
//       [--tracer T.txt] [--tracer-facts F.txt] [--meta KEY=VALUE ...] [--md OUT.md] [--plot-dir DIR --plot-png PNG]
//       [--plot-ref NAME] [--tracer-png NAME] [--audit AUDIT.md] [--summary-md OUT.md] [--render-md OUT.md]
//       [--bvh BVH.txt ...]
//
// Times are the median over repetitions of the CPU time of one pass over the cases,
// divided by the number of cases (CPU time, not wall time: the machine may be shared);
// every pass takes the cases in a new random order (bench_common.hpp: a fixed order lets
// the branch predictor learn each case's outcome); the spread is the coefficient of
// variation over repetitions. certified / fast and
// Epeck / certified verdict are also measured in pairs (bench_common.hpp, time_pair:
// the median over back-to-back pairs of passes of the ratio), which the checks use.
//
// The acceptance targets are the table kTargets below; the report's sentences are the
// sections of trade_report.md.in, built into the program (trade_report_template.hpp).
#include "trade_report_template.hpp"

#include <rayproof/cli.hpp>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace {

using json = nlohmann::json;

const std::vector<std::string> kShapes = {"aabb", "obb", "plane", "sphere", "polyhedron"};
const std::vector<std::string> kTypes = {"double", "float"};
const std::vector<std::string> kWorkloads = {"uniform", "grazing", "parallel", "extreme", "far_small"};
const std::vector<std::string> kMethods = {"fast",          "conservative", "certified",  "certified_verdict",
                                           "textbook",      "branchless",   "cgal_epeck", "cgal_rational",
                                           "embree",        "embree_robust"};
const std::map<std::string, std::string> kMethodLabel = {
    {"fast", "fast"},
    {"conservative", "conservative"},
    {"certified", "certified"},
    {"certified_verdict", "certified, verdict alone"},
    {"textbook", "textbook"},
    {"branchless", "branch-free slab"},
    {"cgal_epeck", "CGAL Epeck"},
    {"cgal_rational", "CGAL rationals"},
    {"embree", "Embree"},
    {"embree_robust", "Embree (robust)"},
};
const std::map<std::string, std::string> kWorkloadLabel = {
    {"uniform", "uniform random"},    {"grazing", "grazing-heavy"}, {"parallel", "parallel-heavy"},
    {"extreme", "extreme magnitudes"}, {"far_small", "far small shapes"},
};
const std::map<std::string, std::string> kShapeLabel = {
    {"aabb", "Aabb"}, {"obb", "Obb"}, {"plane", "Plane"}, {"sphere", "Sphere"}, {"polyhedron", "ConvexPolyhedron"}};

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::string cur;
    std::istringstream in(s);
    while (std::getline(in, cur, sep)) out.push_back(cur);
    if (!s.empty() && s.back() == sep) out.emplace_back();
    return out;
}

// ---- the prose ----------------------------------------------------------------------
// trade_report.md.in: sections "%% NAME" whose lines are joined with newlines, with
// {{name}} placeholders; see the head of that file.
using Vars = std::map<std::string, std::string, std::less<>>;

class Template {
public:
    explicit Template(std::string_view text) {
        std::istringstream in{std::string(text)};
        std::string line, name;
        std::optional<std::string> body;
        while (std::getline(in, line)) {
            if (line.rfind("%% ", 0) == 0) {
                if (body) sections_[name] = *body;
                name = line.substr(3);
                body.reset();
            } else if (!name.empty()) {
                body = body ? *body + '\n' + line : line;
            }
        }
        if (!name.empty()) sections_[name] = body.value_or("");
    }

    // Section `name` with every {{key}} replaced by vars[key].
    std::string operator()(std::string_view name, const Vars& vars = {}) const {
        const auto it = sections_.find(name);
        if (it == sections_.end()) throw std::logic_error("trade_report: no section " + std::string(name));
        const std::string& s = it->second;
        std::string out;
        std::size_t at = 0;
        for (std::size_t open; (open = s.find("{{", at)) != std::string::npos;) {
            const std::size_t close = s.find("}}", open);
            const auto v = vars.find(std::string_view(s).substr(open + 2, close - open - 2));
            if (close == std::string::npos || v == vars.end())
                throw std::logic_error("trade_report: section " + std::string(name) + " has an unfilled placeholder");
            out += s.substr(at, open - at) + v->second;
            at = close + 2;
        }
        return out + s.substr(at);
    }

private:
    std::map<std::string, std::string, std::less<>> sections_;
};

const Template& prose() {
    static const Template t(rayproof::bench::trade_report_template);
    return t;
}

// ---- timings ----------------------------------------------------------------------
struct Timing {
    double ns = NAN;     // per query / per ray
    double cv = NAN;     // relative spread over repetitions
    double hit_rate = NAN;
    double cases = NAN;
    double ratio = NAN;  // paired/ benchmarks: the second method over the first, median over pairs
                         // (over the processes too, where the pairs ran in more than one)
    std::vector<double> process_ratios;  // paired/ benchmarks: each process's ratio, where more than one
    double a_ns = NAN, b_ns = NAN, delta_ns = NAN;  // fpenv/ pairs: each pass per query, their difference
};

double to_ns(double t, const std::string& unit) {
    if (unit == "us") return t * 1e3;
    if (unit == "ms") return t * 1e6;
    if (unit == "s") return t * 1e9;
    return t;
}

std::optional<json> read_json(const std::string& path) {
    std::ifstream in(path);
    if (!in) {
        std::cerr << "trade_report: cannot read " << path << '\n';
        return std::nullopt;
    }
    json j;
    try {
        in >> j;
    } catch (const std::exception& e) {
        std::cerr << "trade_report: " << path << ": " << e.what() << '\n';
        return std::nullopt;
    }
    return j;
}

// One benchmark's entry (its median, or its only run); cv: its spread entry, if any.
Timing timing_of(const json& b, const json* cv) {
    Timing t;
    t.cases = b.contains("cases") ? b["cases"].get<double>() : b.contains("rays") ? b["rays"].get<double>() : 1.0;
    t.ns = to_ns(b["cpu_time"].get<double>(), b.value("time_unit", "ns")) / t.cases;
    if (b.contains("hit_rate")) t.hit_rate = b["hit_rate"].get<double>();
    if (b.contains("ratio")) t.ratio = b["ratio"].get<double>();
    if (b.contains("a_ns")) t.a_ns = b["a_ns"].get<double>();
    if (b.contains("b_ns")) t.b_ns = b["b_ns"].get<double>();
    if (b.contains("delta_ns")) t.delta_ns = b["delta_ns"].get<double>();
    if (cv) t.cv = (*cv)["cpu_time"].get<double>();
    return t;
}

// name -> timing; per item (query or ray). rates: the exact-stage counters, if wanted.
std::map<std::string, Timing> read_bench(const std::string& path, std::map<std::string, double>* rates,
                                         json* context) {
    std::map<std::string, Timing> out;
    const std::optional<json> j = read_json(path);
    if (!j) return out;
    if (context && j->contains("context")) *context = (*j)["context"];
    std::map<std::string, json> median, cv, single;
    for (const auto& b : (*j)["benchmarks"]) {
        const std::string run = b.value("run_name", b.value("name", ""));
        if (b.value("run_type", "") == "aggregate") {
            const std::string agg = b.value("aggregate_name", "");
            if (agg == "median") median[run] = b;
            if (agg == "cv") cv[run] = b;
        } else if (!single.count(run)) {
            single[run] = b;
        }
    }
    auto take = [&](const std::string& run, const json& b) {
        out[run] = timing_of(b, cv.count(run) ? &cv[run] : nullptr);
        if (rates && b.contains("exact_rate")) (*rates)[run] = b["exact_rate"].get<double>();
        if (rates && b.contains("queries")) (*rates)[run + "#queries"] = b["queries"].get<double>();
    };
    for (const auto& [run, b] : median) take(run, b);
    for (const auto& [run, b] : single)
        if (!median.count(run)) take(run, b);
    return out;
}

// ---- accuracy ---------------------------------------------------------------------
struct Accuracy {
    double cases = 0, wrong = 0, false_hit = 0, false_miss = 0, invalid_mismatch = 0, face_mismatch = -1,
           t_judged = -1, t_off = -1, not_enclosing = -1, exact_hits = 0, refused = 0;
    std::string max_ulps = "n/a";
    std::string status = "ok";
    double answered() const { return cases - refused; }
    double per_million(double x) const { return answered() > 0 ? x / answered() * 1e6 : NAN; }
};

// One CSV row, by column name.
Accuracy accuracy_of(std::map<std::string, std::string>& row) {
    Accuracy a;
    auto num = [&](const char* k, double dflt) {
        const auto it = row.find(k);
        if (it == row.end() || it->second.empty() || it->second == "n/a") return dflt;
        return std::stod(it->second);
    };
    a.cases = num("cases", 0);
    a.wrong = num("wrong", 0);
    a.false_hit = num("false_hit", 0);
    a.false_miss = num("false_miss", 0);
    a.invalid_mismatch = num("invalid_mismatch", 0);
    a.face_mismatch = num("face_mismatch", -1);
    a.t_judged = num("t_judged", -1);
    a.t_off = num("t_off", -1);
    a.not_enclosing = num("not_enclosing", -1);
    a.exact_hits = num("exact_hits", 0);
    a.refused = num("refused", 0);
    a.max_ulps = row["max_ulps"].empty() ? "n/a" : row["max_ulps"];
    a.status = row.count("status") ? row["status"] : "ok";
    return a;
}

// shape/type/workload/method -> accuracy, from every CSV (a line "shape,..." is a header).
std::map<std::string, Accuracy> read_accuracy(const std::vector<std::string>& paths) {
    std::map<std::string, Accuracy> out;
    for (const auto& path : paths) {
        std::ifstream in(path);
        if (!in) {
            std::cerr << "trade_report: cannot read " << path << '\n';
            continue;
        }
        std::string line;
        std::vector<std::string> header;
        while (std::getline(in, line)) {
            if (line.empty()) continue;
            const auto f = split(line, ',');
            if (f.size() > 0 && f[0] == "shape") {
                header = f;
                continue;
            }
            if (header.empty() || f.size() != header.size()) continue;
            std::map<std::string, std::string> row;
            for (std::size_t i = 0; i < f.size(); ++i) row[header[i]] = f[i];
            out[row["shape"] + "/" + row["type"] + "/" + row["workload"] + "/" + row["method"]] = accuracy_of(row);
        }
    }
    return out;
}

// ---- formatting -------------------------------------------------------------------
std::string num(double x, int digits = 3) {
    if (std::isnan(x)) return "—";
    if (std::abs(x) >= 100 && std::abs(x) < 1e6) return fmt::format("{:.0f}", x);
    return fmt::format("{:.{}g}", x, digits);
}
std::string num_ppm(double x) {
    if (std::isnan(x)) return "—";
    if (x == 0) return "0";
    return num(x, 3);
}
// ulps: huge values (a wrong interval end, NaN) read better as powers of two.
std::string num_ulps(const std::string& s) {
    if (s == "n/a" || s.empty()) return "—";
    if (s == "inf") return "NaN t";
    const double v = std::stod(s);
    return v < 1e6 ? s : fmt::format("2^{:.0f}", std::log2(v));
}
std::string pct(double x) { return std::isnan(x) ? "—" : num(100 * x, 2) + "%"; }

// A row of a Markdown table; the rule under a header: `left` columns aligned left, `right` right.
std::string row(const std::vector<std::string>& cells) { return fmt::format("| {} |\n", fmt::join(cells, " | ")); }
std::string rule(std::size_t left, std::size_t right) {
    std::string o = "|";
    for (std::size_t i = 0; i < left + right; ++i) o += i < left ? "---|" : "--:|";
    return o + '\n';
}

// ---- the report -------------------------------------------------------------------
struct Report {
    std::map<std::string, Timing> timing, counters_timing;
    std::map<std::string, double> rates;
    std::map<std::string, Accuracy> accuracy;
    std::vector<std::pair<std::string, std::string>> meta;
    std::vector<std::pair<std::string, double>> tracer;  // label -> seconds
    std::map<std::string, double> tracer_facts;         // rays-MODE, queries-MODE, parity-*
    std::map<std::string, double> bvh;                  // --bvh: rayproof_bvh_bench and the generated scenes' timings
    std::map<std::string, double> packet_ns;            // packet benchmark -> median ns per box test
    std::map<std::string, double> packet_hits;          // packet benchmark -> share of box tests that hit
    std::string packet_build;                           // which packet benchmark ran (its backend)
    json context;

    const Timing* scalar(const std::string& shape, const std::string& type, const std::string& w,
                         const std::string& m) const {
        const auto it = timing.find("scalar/" + shape + "/" + type + "/" + w + "/" + m);
        return it == timing.end() ? nullptr : &it->second;
    }
    const Accuracy* acc(const std::string& shape, const std::string& type, const std::string& w,
                        const std::string& m) const {
        const auto it = accuracy.find(shape + "/" + type + "/" + w + "/" + m);
        return it == accuracy.end() ? nullptr : &it->second;
    }
    double ns(const std::string& shape, const std::string& type, const std::string& w, const std::string& m) const {
        const Timing* t = scalar(shape, type, w, m);
        return t ? t->ns : NAN;
    }
    // A ratio measured in pairs on workload w (certified_over_fast,
    // epeck_over_certified_verdict), NaN when not measured.
    double paired(const std::string& shape, const std::string& type, const std::string& w,
                  const std::string& pair) const {
        const Timing* t = pair_timing(shape, type, w, pair);
        return t ? t->ratio : NAN;
    }
    // Each process's ratio of that pair, where it ran in more than one (else empty).
    const std::vector<double>& paired_runs(const std::string& shape, const std::string& type, const std::string& w,
                                           const std::string& pair) const {
        static const std::vector<double> none;
        const Timing* t = pair_timing(shape, type, w, pair);
        return t ? t->process_ratios : none;
    }
    const Timing* pair_timing(const std::string& shape, const std::string& type, const std::string& w,
                              const std::string& pair) const {
        const auto it = timing.find("paired/" + shape + "/" + type + "/" + w + "/" + pair);
        return it == timing.end() ? nullptr : &it->second;
    }
};

std::string summary_table(const Report& r) {
    std::string o = row({"shape", "type", "fast", "conservative", "certified", "certified / fast",
                         "certified / fast, paired", "certified, verdict alone", "textbook", "branch-free slab",
                         "CGAL Epeck", "Epeck / certified", "Epeck / certified verdict", "CGAL rationals", "Embree",
                         "exact stage (certified)"}) +
                    rule(2, 14);
    for (const auto& s : kShapes)
        for (const auto& t : kTypes) {
            const auto ns = [&](const char* m) { return r.ns(s, t, "uniform", m); };
            const double f = ns("fast"), c = ns("certified"), e = ns("cgal_epeck"), v = ns("certified_verdict");
            const double p = r.paired(s, t, "uniform", "certified_over_fast");
            const auto rate = r.rates.find("exact_stage/" + s + "/" + t + "/general");
            o += row({kShapeLabel.at(s), t, num(f), num(ns("conservative")), num(c), num(c / f) + "×",
                      std::isnan(p) ? "—" : num(p) + "×", num(v), num(ns("textbook")), num(ns("branchless")), num(e),
                      std::isnan(e) ? "—" : num(e / c) + "×", std::isnan(e) ? "—" : num(e / v) + "×",
                      num(ns("cgal_rational")), num(ns("embree")),
                      rate == r.rates.end() ? "—" : num(rate->second)});
        }
    return o;
}

// ---- the ladder (issue #17): each mode within its factor of the one below ---------
// Every ratio in pairs (bench_common.hpp, register_ladder): fast over the textbook code of
// the shape, conservative over fast and certified over fast on uniform input, and
// certified over fast on the grazing-heavy workload. A cell reads "1.27× no" against its
// limit; "—" where the pair did not run.
struct Rung {
    const char* workload;
    const char* pair;
    double limit;
};
constexpr Rung kLadder[] = {
    {"uniform", "fast_over_textbook", 1.25},
    {"uniform", "conservative_over_fast", 1.3},
    {"uniform", "certified_over_fast", 1.5},
    {"grazing", "certified_over_fast", 10},
};

std::string ladder_table(const Report& r) {
    std::string o = row({"shape", "type", "fast / textbook (≤ 1.25)", "conservative / fast (≤ 1.3)",
                         "certified / fast (≤ 1.5)", "certified / fast, grazing (≤ 10)", "targets met"}) +
                    rule(2, 5);
    int met_all = 0, cells_all = 0;
    for (const auto& s : kShapes)
        for (const auto& t : kTypes) {
            std::vector<std::string> cells = {kShapeLabel.at(s), t};
            int met = 0, cells_here = 0;
            for (const Rung& g : kLadder) {
                const double q = r.paired(s, t, g.workload, g.pair);
                if (std::isnan(q)) {
                    cells.push_back("—");
                    continue;
                }
                ++cells_here;
                met += q <= g.limit;
                std::string cell = num(q, 3) + "× " + (q <= g.limit ? "yes" : "**no**");
                if (const std::vector<double>& v = r.paired_runs(s, t, g.workload, g.pair); v.size() > 1) {
                    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
                    cell += " (" + num(*lo, 3) + "–" + num(*hi, 3) + ")";
                }
                cells.push_back(cell);
            }
            cells.push_back(fmt::format("{} of {}", met, cells_here));
            met_all += met;
            cells_all += cells_here;
            o += row(cells);
        }
    std::size_t processes = 1;
    for (const auto& [name, t] : r.timing) processes = std::max(processes, t.process_ratios.size());
    std::string processes_text;
    if (processes > 1)
        processes_text =
            prose()("ladder.processes", {{"n", std::to_string(processes)}, {"extra", std::to_string(processes - 1)}});
    return prose()("ladder", {{"table", o},
                              {"met", std::to_string(met_all)},
                              {"cells", std::to_string(cells_all)},
                              {"processes", processes_text}});
}

// ---- the box packets (issue #17): ns per box test ----------------------------------
// rayproof_packet_bench's JSON: the median over repetitions of each benchmark's counter
// ns_per_box (ray_aabb_packet_bench.cpp), keyed by its name ("BM_soa_slab<float, 8>").
void read_packets(const std::string& path, Report& r) {
    const std::optional<json> j = read_json(path);
    if (!j) return;
    if (j->contains("context")) {
        const std::string exe = (*j)["context"].value("executable", "");
        r.packet_build = exe.substr(exe.find_last_of('/') + 1);
    }
    for (const auto& b : (*j)["benchmarks"]) {
        if (!b.contains("ns_per_box")) continue;
        const std::string run = b.value("run_name", b.value("name", ""));
        const bool median = b.value("run_type", "") == "aggregate" && b.value("aggregate_name", "") == "median";
        if (median || (b.value("run_type", "") != "aggregate" && !r.packet_ns.count(run))) {
            r.packet_ns[run] = b["ns_per_box"].get<double>() * 1e9;  // the counter is in seconds
            if (b.contains("hit_rate")) r.packet_hits[run] = b["hit_rate"].get<double>();
        }
    }
}

std::string packets_table(const Report& r) {
    if (r.packet_ns.empty()) return prose()("packets.none");
    const auto ns = [&](const std::string& bench, const std::string& type, int w) {
        const auto it = r.packet_ns.find(fmt::format("{}<{}, {}>", bench, type, w));
        return it == r.packet_ns.end() ? NAN : it->second;
    };
    const auto over = [](double q, double limit) {
        return std::isnan(q) ? std::string("—") : num(q, 3) + "× " + (q <= limit ? "yes" : "**no**");
    };
    std::string o = row({"type", "W", "branch-free SoA loop", "fast verdict", "fast / loop (≤ 1.25)",
                         "certified verdict", "certified / loop (≤ 2)", "certified verdict, no guard",
                         "certified verdict, in an FpEnvScope", "scoped / loop",
                         "certified intersect", "certified verdict / float's (≤ 2)"}) +
                    rule(2, 10);
    const auto mode_ns = [&](const std::string& type, int w, const char* mode) {
        const auto it = r.packet_ns.find(fmt::format("BM_packet_verdict<{}, {}, {}_t>", type, w, mode));
        return it == r.packet_ns.end() ? NAN : it->second;
    };
    const double float_cert = mode_ns("float", 8, "certified");
    for (const auto& [type, w] : std::vector<std::pair<std::string, int>>{{"float", 8}, {"double", 4}, {"double", 8}}) {
        const double loop = ns("BM_soa_slab", type, w), fast = mode_ns(type, w, "fast");
        const double cert = mode_ns(type, w, "certified");
        const double scoped = ns("BM_packet_verdict_certified_scoped", type, w);
        o += row({type, std::to_string(w), num(loop), num(fast), over(fast / loop, 1.25), num(cert),
                  over(cert / loop, 2), num(ns("BM_packet_verdict_certified_unguarded", type, w)),
                  num(scoped), std::isnan(scoped / loop) ? std::string("—") : num(scoped / loop, 3) + "×",
                  num(ns("BM_packet_intersect_certified", type, w)),
                  type == "double" && w == 8 ? over(cert / float_cert, 2) : "—"});
    }
    const auto embree = [&](const char* name) {
        const auto it = r.packet_ns.find(name);
        return it == r.packet_ns.end() ? NAN : it->second;
    };
    const double e1 = embree("BM_embree_intersect1"), e8 = embree("BM_embree_intersect8");
    const auto hits = [&](const char* name) {
        const auto it = r.packet_hits.find(name);
        return it == r.packet_hits.end() ? NAN : it->second;
    };
    const std::string embree_rows =
        std::isnan(e1) && std::isnan(e8)
            ? prose()("packets.no_embree")
            : prose()("packets.embree", {{"e1", num(e1)}, {"e8", num(e8)}, {"cert", num(float_cert)},
                                         {"r1", num(e1 / float_cert, 3)}, {"r8", num(e8 / float_cert, 3)},
                                         {"h1", num(hits("BM_embree_intersect1"), 3)},
                                         {"h8", num(hits("BM_embree_intersect8"), 3)}});
    return prose()("packets", {{"table", o}, {"embree", embree_rows}, {"build", r.packet_build}});
}

// ---- the acceptance checks ----------------------------------------------------------
// A target: one method's time over another's on a workload must stay at most (or at
// least) `limit`. It is read on the kernel's headline case (shape, type: Aabb, double,
// the slab method) from the pair benchmark `pair` where it ran (both passes of a pair
// see the machine in the same state), else from the ratio of the two medians; every
// shape and type is listed beside it. Its sentence is section "check.<pair>" of the
// template.
enum class Bound { at_most, at_least };
struct Target {
    const char* pair;               // the paired benchmark measuring it, and its sentence
    const char* num;                // time(num) / time(den)
    const char* den;
    Bound bound;
    double limit;
    const char* shape;              // the case the verdict is read on
    const char* type;
    const char* workload;
    int digits;                     // significant digits of the headline ratio
    bool measured_only;             // list only where num was timed, the medians' ratio in brackets
    const char* also_den = nullptr; // also list time(num) / time(also_den) (the medians)
};

constexpr Target kTargets[] = {
    // The certified mode costs at most 1.5 times the fast one.
    {"certified_over_fast", "certified", "fast", Bound::at_most, 1.5, "aabb", "double", "uniform", 3, false},
    // CGAL's do_intersect answers the verdict alone, so the like-for-like comparison is
    // with the kernel's verdict query; the full query (faithful t and face as well) is
    // listed beside it.
    {"epeck_over_certified_verdict", "cgal_epeck", "certified_verdict", Bound::at_least, 50, "aabb", "double",
     "uniform", 4, true, "certified"},
};

double medians(const Report& r, const std::string& s, const std::string& t, const Target& g, const char* den) {
    return r.ns(s, t, g.workload, g.num) / r.ns(s, t, g.workload, den);
}

double ratio(const Report& r, const std::string& s, const std::string& t, const Target& g) {
    const double p = r.paired(s, t, g.workload, g.pair);
    return std::isnan(p) ? medians(r, s, t, g, g.den) : p;
}

// "Aabb double 1.29×, ..." for every shape and type that item() answers.
std::string every_case(const std::function<std::optional<std::string>(const std::string&, const std::string&)>& item) {
    std::string out;
    for (const auto& s : kShapes)
        for (const auto& t : kTypes)
            if (const auto v = item(s, t)) out += (out.empty() ? "" : ", ") + kShapeLabel.at(s) + ' ' + t + ' ' + *v;
    return out;
}

std::string target_check(const Report& r, const Target& g) {
    const double q = ratio(r, g.shape, g.type, g);
    const bool met = g.bound == Bound::at_most ? q <= g.limit : q >= g.limit;
    auto listed = [&](const std::string& s, const std::string& t) {
        return !g.measured_only || !std::isnan(r.ns(s, t, g.workload, g.num));
    };
    Vars v = {{"limit", num(g.limit)},
              {"case", kShapeLabel.at(g.shape) + ", " + g.type},
              {"in_pairs", std::isnan(r.paired(g.shape, g.type, g.workload, g.pair)) ? "" : prose()("check.in_pairs")},
              {"value", num(q, g.digits)},
              {"mark", met ? "**yes**" : "**no**"},
              {"medians", num(medians(r, g.shape, g.type, g, g.den), 3)}};
    v["every"] = every_case([&](const std::string& s, const std::string& t) -> std::optional<std::string> {
        if (!listed(s, t)) return std::nullopt;
        const std::string bracket = g.measured_only ? " [" + num(medians(r, s, t, g, g.den), 3) + "×]" : "";
        return num(ratio(r, s, t, g), 3) + "×" + bracket;
    });
    if (g.also_den)
        v["also"] = every_case([&](const std::string& s, const std::string& t) -> std::optional<std::string> {
            if (!listed(s, t)) return std::nullopt;
            return num(medians(r, s, t, g, g.also_den), 3) + "×";
        });
    return prose()(std::string("check.") + g.pair, v) + '\n';
}

// Fast mode's wrong verdicts on the grazing-heavy workload, every shape and type.
std::string grazing_check(const Report& r) {
    const std::string every = every_case([&](const std::string& s, const std::string& t) -> std::optional<std::string> {
        const Accuracy* a = r.acc(s, t, "grazing", "fast");
        return a ? num_ppm(a->per_million(a->wrong)) : "—";
    });
    return prose()("check.grazing", {{"every", every}}) + '\n';
}

// Embree and the certified mode on the far-small-sphere workload (float).
std::string embree_check(const Report& r) {
    std::string methods, certified;
    for (const char* m : {"embree", "embree_robust"}) {
        const Accuracy* a = r.acc("sphere", "float", "far_small", m);
        if (!a) continue;
        methods += prose()("check.embree.method", {{"method", kMethodLabel.at(m)},
                                                   {"wrong", num_ppm(a->per_million(a->wrong))},
                                                   {"false_miss", num_ppm(a->per_million(a->false_miss))},
                                                   {"refused", num(a->refused / a->cases * 1e6)},
                                                   {"ulps", num_ulps(a->max_ulps)}}) +
                   ' ';
    }
    if (const Accuracy* a = r.acc("sphere", "float", "far_small", "certified"))
        certified = prose()("check.embree.certified", {{"wrong", num_ppm(a->per_million(a->wrong))},
                                                       {"ulps", num_ulps(a->max_ulps)}});
    return prose()("check.embree", {{"methods", methods}, {"certified", certified}}) + '\n';
}

std::string checks(const Report& r) {
    std::string o;
    for (const Target& g : kTargets) o += target_check(r, g);
    o += grazing_check(r) + embree_check(r);
    // Any method that hung or crashed on some case.
    for (const auto& [key, a] : r.accuracy)
        if (a.status != "ok") o += prose()("check.unfinished", {{"key", key}, {"status", a.status}}) + '\n';
    return o;
}

// ---- the tables of the full report --------------------------------------------------
std::string shape_table(const Report& r, const std::string& s) {
    std::string o = row({"type", "workload", "method", "ns / query", "spread", "Mq/s", "× fast", "wrong / M",
                         "false miss / M", "face wrong / M", "t not faithful / M", "max t error (ulps)",
                         "cases judged"}) +
                    rule(3, 10);
    for (const auto& t : kTypes)
        for (const auto& w : kWorkloads)
            for (const auto& m : kMethods) {
                const Timing* tm = r.scalar(s, t, w, m);
                const Accuracy* a = r.acc(s, t, w, m);
                if (!tm && !a) continue;
                const double ns = tm ? tm->ns : NAN, f = r.ns(s, t, w, "fast");
                o += fmt::format("| {} | {} | {} | {} | {} | {} | {} | ", t, w, kMethodLabel.at(m), num(ns),
                                 tm ? pct(tm->cv) : "—", num(1e3 / ns), num(ns / f));
                if (!a) {
                    o += "— | — | — | — | — | — |\n";
                } else if (a->status != "ok") {
                    o += a->status + " | | | | | |\n";
                } else {
                    const auto per_m = [&](double x) { return x < 0 ? "—" : num_ppm(a->per_million(x)); };
                    o += fmt::format("{} | {} | {} | {} | {} | {}{} |\n", per_m(a->wrong), per_m(a->false_miss),
                                     per_m(a->face_mismatch), per_m(a->t_off), num_ulps(a->max_ulps),
                                     num(a->cases, 6),
                                     a->refused > 0 ? " (" + num(a->refused, 6) + " refused)" : "");
                }
            }
    return o;
}

std::string batch_size(long n) {
    if (n >= 1000000) return std::to_string(n / 1000000) + "M";
    return n >= 1000 ? std::to_string(n / 1000) + "k" : std::to_string(n);
}

std::string batch_table(const Report& r) {
    std::vector<long> sizes;
    for (const auto& [name, t] : r.timing) {
        if (name.rfind("batch/", 0) != 0) continue;
        const long n = std::stol(name.substr(name.rfind('/') + 1));
        if (std::find(sizes.begin(), sizes.end(), n) == sizes.end()) sizes.push_back(n);
    }
    std::sort(sizes.begin(), sizes.end());
    if (sizes.empty()) return prose()("batch.none");
    std::vector<std::string> cells = {"shape", "type", "mode"};
    for (long n : sizes) cells.push_back(batch_size(n));
    std::string o = row(cells) + rule(3, sizes.size());
    for (const auto& s : kShapes)
        for (const auto& t : kTypes)
            for (const std::string m : {"fast", "conservative", "certified", "certified_avx2"}) {
                cells = {kShapeLabel.at(s), t, m == "certified_avx2" ? "certified, AVX2" : m};
                bool timed = false;  // shapes without a batch sweep (the polyhedron) get no row
                for (long n : sizes) {
                    const auto it = r.timing.find("batch/" + s + "/" + t + "/" + m + "/" + std::to_string(n));
                    timed = timed || it != r.timing.end();
                    cells.push_back(it == r.timing.end() ? "—" : num(1e3 / it->second.ns));
                }
                if (timed) o += row(cells);
            }
    // The largest batch is the pool every size takes its calls' rays from (bench_common.hpp).
    return prose()("batch", {{"table", o}, {"pool", batch_size(sizes.back())}});
}

// The environment guard's cost (bench/fp_env_bench.cpp): per shape, type and guarded
// mode, the query without and with the guard in the default environment, their paired
// difference, and the query called from a foreign environment.
std::string fp_env_table(const Report& r) {
    std::string o = row({"shape", "type", "mode", "guard off", "guard, default", "cost", "× guard off", "foreign",
                         "foreign cost", "in an FpEnvScope", "scope / guard, default"}) +
                    rule(3, 8);
    bool any = false;
    for (const auto& s : kShapes)
        for (const auto& t : kTypes)
            for (const char* m : {"certified", "conservative"}) {
                const auto g = r.timing.find("fpenv/" + s + "/" + t + "/" + m + "/guard");
                const auto f = r.timing.find("fpenv/" + s + "/" + t + "/" + m + "/foreign");
                const auto c = r.timing.find("fpenv/" + s + "/" + t + "/" + m + "/scope");
                if (g == r.timing.end() && f == r.timing.end() && c == r.timing.end()) continue;
                any = true;
                const Timing none;
                const Timing& gt = g == r.timing.end() ? none : g->second;
                const Timing& ft = f == r.timing.end() ? none : f->second;
                const Timing& ct = c == r.timing.end() ? none : c->second;
                o += row({kShapeLabel.at(s), t, m, num(gt.a_ns), num(gt.b_ns), num(gt.delta_ns, 2), num(gt.ratio),
                          num(ft.b_ns), num(ft.delta_ns), num(ct.b_ns), num(ct.ratio)});
            }
    if (!any) return prose()("fp_env.none");
    const bool x86 = r.context.is_object() && r.context.value("fp_env_x86", std::string("1")) == "1";
    return prose()("fp_env", {{"table", o},
                              {"probe", x86 ? "one `_mm_getcsr`, an AND and a compare" : "`fegetround`"},
                              {"foreign", x86 ? "MXCSR FTZ and DAZ" : "FE_UPWARD"}});
}

// The generators with exact-stage counts, in the registry's order, unknown ones last.
std::vector<std::string> counted_generators(const Report& r) {
    std::vector<std::string> gens;
    for (const auto& [name, rate] : r.rates) {
        if (name.find('#') != std::string::npos) continue;
        const std::string g = name.substr(name.rfind('/') + 1);
        if (std::find(gens.begin(), gens.end(), g) == gens.end()) gens.push_back(g);
    }
    const std::vector<std::string> order = {"general",     "log_uniform", "grazing", "near_grazing",    "parallel",
                                            "on_boundary", "extreme",     "rotated_integer", "invalid"};
    std::vector<std::string> sorted;
    for (const auto& g : order)
        if (std::find(gens.begin(), gens.end(), g) != gens.end()) sorted.push_back(g);
    for (const auto& g : gens)
        if (std::find(sorted.begin(), sorted.end(), g) == sorted.end()) sorted.push_back(g);
    return sorted;
}

std::string exact_stage_table(const Report& r) {
    const std::vector<std::string> gens = counted_generators(r);
    if (gens.empty()) return prose()("exact_stage.none");
    std::vector<std::string> cells = {"shape", "type"};
    for (const auto& g : gens) cells.push_back(g == "general" ? "general (uniform)" : g);
    std::string o = row(cells) + rule(2, gens.size());
    for (const auto& s : kShapes)
        for (const auto& t : kTypes) {
            cells = {kShapeLabel.at(s), t};
            for (const auto& g : gens) {
                const std::string key = "exact_stage/" + s + "/" + t + "/" + g;
                const auto it = r.rates.find(key);
                const auto q = r.rates.find(key + "#queries");
                const bool counted = it != r.rates.end() && q != r.rates.end() && q->second != 0;
                cells.push_back(counted ? num(it->second) : "—");
            }
            o += row(cells);
        }
    return o;
}

std::string parity_paragraph(const Report& r);

std::string tracer_table(const Report& r, const std::string& png) {
    if (r.tracer.empty()) return prose()("tracer.none");
    // Labels: MODE and povray (wall seconds), MODE-cpu and povray-cpu (user + system).
    std::map<std::string, double> wall, cpu;
    std::vector<std::string> order;
    for (const auto& [k, v] : r.tracer) {
        const bool is_cpu = k.size() > 4 && k.compare(k.size() - 4, 4, "-cpu") == 0;
        const std::string name = is_cpu ? k.substr(0, k.size() - 4) : k;
        (is_cpu ? cpu : wall)[name] = v;
        if (std::find(order.begin(), order.end(), name) == order.end()) order.push_back(name);
    }
    const double pw = wall.count("povray") ? wall["povray"] : NAN, pc = cpu.count("povray") ? cpu["povray"] : NAN;
    std::string o = row({"renderer", "wall s", "÷ POV-Ray", "CPU s", "÷ POV-Ray"}) + rule(1, 4);
    for (const auto& name : order) {
        const double w = wall.count(name) ? wall[name] : NAN, c = cpu.count(name) ? cpu[name] : NAN;
        o += row({name == "povray" ? "POV-Ray 3.7 (exported scene)" : "rayproof render, " + name, num(w),
                  num(w / pw), num(c), num(c / pc)});
    }
    o += '\n' + parity_paragraph(r);
    if (!png.empty()) o += prose()("tracer.image", {{"png", png}});
    return o;
}

// ---- tracer and BVH (issue #18) -----------------------------------------------------
// The generated scenes' targets: the certified render at most `limit` times POV-Ray's wall
// time on the exported scene, same threads.
struct SceneTarget {
    long long objects;
    double limit;
};
constexpr SceneTarget kSceneTargets[] = {{2000, 1.0}, {100000, 2.0}};
// Closest-hit rays per second: the faster Embree scene's rate over the method's, at most `limit`.
struct RayTarget {
    const char* method;
    double limit;
};
constexpr RayTarget kRayTargets[] = {{"fast", 1.5}, {"certified", 2.0}, {"fast_avx2", 1.5}, {"certified_avx2", 2.0}};
// *_avx2: the same Bvh<float, 8> in the bench's AVX2 build (rayproof_bvh_bench_avx2).
// *_double: the tracer's Bvh<double, W> over the same balls (no target of its own; W is
// 4 in the default x86-64 build, 8 in the AVX2 build: render/tracer.hpp).
const std::vector<std::string> kBvhMethods = {
    "fast",          "conservative",          "certified",          "fast_avx2",
    "conservative_avx2", "certified_avx2",    "fast_double",        "conservative_double",
    "certified_double",  "fast_double_avx2",  "conservative_double_avx2", "certified_double_avx2",
    "embree",        "embree_robust"};
const std::map<std::string, std::string> kBvhLabel = {
    {"fast", "rayproof Bvh, fast"},
    {"conservative", "rayproof Bvh, conservative"},
    {"certified", "rayproof Bvh, certified"},
    {"fast_avx2", "rayproof Bvh, fast, AVX2 build"},
    {"conservative_avx2", "rayproof Bvh, conservative, AVX2 build"},
    {"certified_avx2", "rayproof Bvh, certified, AVX2 build"},
    {"fast_double", "rayproof Bvh, double, fast"},
    {"conservative_double", "rayproof Bvh, double, conservative"},
    {"certified_double", "rayproof Bvh, double, certified"},
    {"fast_double_avx2", "rayproof Bvh, double, fast, AVX2 build"},
    {"conservative_double_avx2", "rayproof Bvh, double, conservative, AVX2 build"},
    {"certified_double_avx2", "rayproof Bvh, double, certified, AVX2 build"},
    {"embree", "Embree 3"},
    {"embree_robust", "Embree 3, robust"}};
const std::vector<std::string> kBvhSets = {"camera", "grazing"};

std::string count(double v);
std::string yes_no(bool met) { return met ? "**yes**" : "**no**"; }

// The generated scenes against POV-Ray: keys scene-N-MODE, scene-N-MODE-cpu,
// scene-N-MODE-timeout (the render was stopped after that many seconds), scene-N-povray,
// scene-N-povray-cpu, scene-N-parity-mean (the mean absolute difference per channel of the
// two pictures, out of 255).
std::string bvh_scene_table(const Report& r) {
    const auto get = [&](const std::string& k) { return r.bvh.count(k) ? r.bvh.at(k) : NAN; };
    std::string o = row({"scene", "objects", "rayproof certified, wall s", "CPU s", "POV-Ray 3.7, wall s", "CPU s",
                         "rayproof ÷ POV-Ray, wall", "CPU", "target (wall)", "met", "pictures: mean difference"}) +
                    rule(1, 10);
    bool any = false;
    for (const SceneTarget& g : kSceneTargets) {
        const std::string p = "scene-" + std::to_string(g.objects) + "-";
        const double pw = get(p + "povray"), stopped = get(p + "certified-timeout");
        if (std::isnan(pw) && std::isnan(get(p + "certified")) && std::isnan(stopped)) continue;
        any = true;
        const double w = get(p + "certified");
        const bool finished = std::isnan(stopped) && !std::isnan(w);
        const double q = w / pw;
        o += row({"generated field", count(double(g.objects)),
                  finished ? num(w) : std::isnan(stopped) ? "—" : "stopped at " + num(stopped),
                  finished ? num(get(p + "certified-cpu")) : "—", num(pw), num(get(p + "povray-cpu")),
                  finished ? num(q) : std::isnan(stopped) ? "—" : "> " + num(stopped / pw),
                  finished ? num(get(p + "certified-cpu") / get(p + "povray-cpu")) : "—", "≤ " + num(g.limit) + "×",
                  yes_no(finished && q <= g.limit),
                  std::isnan(get(p + "parity-mean")) ? "—" : fmt::format("{:.3f}/255", get(p + "parity-mean"))});
    }
    return any ? o : prose()("bvh.scenes.none");
}

std::string bvh_rays_table(const Report& r) {
    const auto get = [&](const std::string& k) { return r.bvh.count(k) ? r.bvh.at(k) : NAN; };
    std::string o = row({"method", "ray set", "M rays / s", "Embree ÷ method", "Embree robust ÷ method", "target", "met"}) +
                    rule(2, 5);
    for (const auto& set : kBvhSets) {
        const double e = get("bvh-rate-" + set + "-embree"), er = get("bvh-rate-" + set + "-embree_robust");
        const double best = std::isnan(e) ? er : std::isnan(er) ? e : std::max(e, er);
        for (const auto& m : kBvhMethods) {
            const double rate = get("bvh-rate-" + set + "-" + m);
            if (std::isnan(rate)) continue;
            std::string target = "—", met = "—";
            for (const RayTarget& g : kRayTargets)
                if (m == g.method) {
                    target = "≤ " + num(g.limit) + "× the faster Embree";
                    met = yes_no(best / rate <= g.limit);
                }
            const bool is_embree = m.rfind("embree", 0) == 0;
            o += row({kBvhLabel.at(m), set, num(rate / 1e6), is_embree ? "—" : num(e / rate),
                      is_embree ? "—" : num(er / rate), target, met});
        }
    }
    return o;
}

std::string bvh_wrong_table(const Report& r) {
    const auto get = [&](const std::string& k) { return r.bvh.count(k) ? r.bvh.at(k) : NAN; };
    std::string o = row({"method", "ray set", "judged", "hit (brute force)", "wrong closest hit", "false misses",
                         "false hits", "another ball"}) +
                    rule(2, 6);
    for (const auto& set : kBvhSets)
        for (const auto& m : kBvhMethods) {
            const double w = get("bvh-wrong-" + set + "-" + m);
            if (std::isnan(w)) continue;
            const double fm = get("bvh-falsemiss-" + set + "-" + m), fh = get("bvh-falsehit-" + set + "-" + m);
            o += row({kBvhLabel.at(m), set, count(get("bvh-judged-" + set)), count(get("bvh-hits-" + set)), count(w),
                      count(fm), count(fh), count(w - fm - fh)});
        }
    return o;
}

std::string bvh_build_table(const Report& r) {
    const auto get = [&](const std::string& k) { return r.bvh.count(k) ? r.bvh.at(k) : NAN; };
    const double n = get("bvh-spheres");
    std::string o = row({"structure", "build, ms (one thread)", "ns per primitive", "bytes per primitive",
                         "of which the primitive's copy"}) +
                    rule(1, 4);
    const double w = get("bvh-double-width");
    const std::string double_tree = std::isnan(w) ? "rayproof Bvh, double" : fmt::format("rayproof Bvh<double, {:.0f}>", w);
    const std::map<std::string, std::string> label = {{"rayproof", "rayproof Bvh<float, 8>"},
                                                      {"rayproof_double", double_tree},
                                                      {"embree", kBvhLabel.at("embree")},
                                                      {"embree_robust", kBvhLabel.at("embree_robust")}};
    for (const std::string m : {"rayproof", "rayproof_double", "embree", "embree_robust"}) {
        const double s = get("bvh-build-s-" + m);
        if (std::isnan(s)) continue;
        o += row({label.at(m), num(1e3 * s), num(1e9 * s / n),
                  num(get("bvh-bytes-" + m) / n), num(get("bvh-bytes-items-" + m) / n)});
    }
    return o;
}

std::string bvh_section(const Report& r) {
    if (r.bvh.empty()) return prose()("bvh.none");
    const auto get = [&](const std::string& k) { return r.bvh.count(k) ? r.bvh.at(k) : NAN; };
    Vars v = {{"scenes", bvh_scene_table(r)},
              {"rays", bvh_rays_table(r)},
              {"wrong", bvh_wrong_table(r)},
              {"build", bvh_build_table(r)},
              {"spheres", count(get("bvh-spheres"))},
              {"camera_rays", count(get("bvh-rays-camera"))},
              {"grazing_rays", count(get("bvh-rays-grazing"))},
              {"brute_camera", num(get("bvh-brute-rate-camera"))},
              {"brute_grazing", num(get("bvh-brute-rate-grazing"))}};
    return prose()("bvh", v);
}

// Integers as integers, with thin separators: 1234567 -> 1,234,567.
std::string count(double v) {
    std::string d = fmt::format("{:.0f}", v), o;
    for (std::size_t i = 0; i < d.size(); ++i) {
        if (i && (d.size() - i) % 3 == 0) o += ',';
        o += d[i];
    }
    return o;
}

// The pixel-by-pixel comparison of the two pictures (rayproof compare), when it ran.
std::string parity_paragraph(const Report& r) {
    const auto& f = r.tracer_facts;
    for (const char* k : {"parity-mean", "parity-max", "parity-differing", "parity-pixels", "parity-inexact"})
        if (!f.count(k)) return prose()("tracer.parity.none");
    const double mean = f.at("parity-mean");
    return prose()("tracer.parity", {{"mean", fmt::format("{:.3f}", mean)},
                                     {"mark", mean <= 3 ? "**yes**" : "**no**"},
                                     {"max", count(f.at("parity-max"))},
                                     {"differing", count(f.at("parity-differing"))},
                                     {"pixels", count(f.at("parity-pixels"))},
                                     {"inexact", count(f.at("parity-inexact"))}});
}

// render/README.md's paragraph on speed, from the same run; empty when a figure is missing.
std::string render_speed(const Report& r) {
    std::map<std::string, double> v(r.tracer_facts.begin(), r.tracer_facts.end());
    for (const auto& [k, s] : r.tracer) v[k] = s;
    Vars vars;
    for (const char* m : {"fast", "conservative", "certified", "povray"})
        for (const std::string& k : {std::string(m), std::string(m) + "-cpu"}) {
            if (!v.count(k)) return "";
            vars[k == m ? k : std::string(m) + "_cpu"] = fmt::format("{:.2f}", v[k]);
        }
    if (!v.count("rays-certified") || !v.count("queries-certified")) return "";
    vars["rays"] = count(v["rays-certified"]);
    vars["queries"] = count(v["queries-certified"]);
    vars["date"] = "";
    for (const auto& [k, m] : r.meta)
        if (k == "date") vars["date"] = m;
    return prose()("render_speed", vars);
}

// ---- the plot -----------------------------------------------------------------------
const std::vector<std::string> kColors = {"#1b9e77", "#e6ab02", "#d95f02", "#fb9a99", "#7570b3",
                                          "#e7298a", "#66a61e", "#a6761d", "#1f78b4", "#666666"};

// trade.dat: one index block per workload, one sub-block per method; columns: ns/query,
// wrong per million (0 drawn at the floor), point type (shape; filled = double), shape,
// type.
void write_plot_data(const Report& r, const std::string& path) {
    std::ofstream dat(path);
    const std::map<std::string, int> pt_open = {{"aabb", 4}, {"obb", 6}, {"plane", 8}, {"sphere", 12},
                                                {"polyhedron", 14}};
    const double floor_ppm = 0.5;
    for (const auto& w : kWorkloads) {
        fmt::print(dat, "# workload {}\n", w);
        for (const auto& m : kMethods) {
            fmt::print(dat, "# method {}\n", m);
            int rows = 0;
            for (const auto& s : kShapes)
                for (const auto& t : kTypes) {
                    const Timing* tm = r.scalar(s, t, w, m);
                    const Accuracy* a = r.acc(s, t, w, m);
                    if (!tm || !a || a->status != "ok" || a->answered() <= 0) continue;
                    const double ppm = a->per_million(a->wrong);
                    fmt::print(dat, "{:g} {:g} {} {} {}\n", tm->ns, std::max(ppm, floor_ppm),
                               pt_open.at(s) + (t == "double"), s, t);
                    ++rows;
                }
            if (rows == 0) dat << "NaN NaN 1 none none\n";
            dat << "\n\n";
        }
    }
}

// The sixth panel: the methods' colours and the point types.
void write_plot_legend(std::ostream& gp) {
    gp << "unset title\nunset grid\nunset logscale\nunset xtics\nunset ytics\nunset xlabel\nunset ylabel\nunset "
          "border\nset xrange [0:10]\nset yrange [0:10]\n";
    for (std::size_t mi = 0; mi < kMethods.size(); ++mi) {
        const double y = 9.3 - 0.85 * double(mi);
        fmt::print(gp, "set label {} '{}' at 1.2,{:g} tc rgb '{}' font ',11'\n", mi + 1, kMethodLabel.at(kMethods[mi]),
                   y, kColors[mi]);
        fmt::print(gp, "set object {} circle at 0.6,{:g} size 0.18 fc rgb '{}' fs solid noborder\n", mi + 1, y,
                   kColors[mi]);
    }
    gp << "set label 20 'point: Aabb square, Obb circle,' at 5.2,9.3\n";
    gp << "set label 21 'Plane triangle, Sphere diamond,' at 5.2,8.45\n";
    gp << "set label 22 'ConvexPolyhedron pentagon;' at 5.2,7.6\n";
    gp << "set label 23 'filled: double, open: float' at 5.2,6.75\n";
    gp << "plot NaN notitle\nunset multiplot\n";
}

// trade.gp: one panel per workload of trade.dat, drawn into png, and the legend.
void write_plot_script(const std::string& path, const std::string& png) {
    std::ofstream gp(path);
    if (kColors.size() < kMethods.size()) throw std::logic_error("trade_report: a color per method is missing");
    gp << "set terminal pngcairo size 1500,900 font 'DejaVu Sans,10'\n";
    fmt::print(gp, "set output '{}'\n", png);
    gp << "set multiplot layout 2,3 title 'Time per query against wrong verdicts (per million, judged by the exact "
          "oracle); 0 drawn on the floor'\n";
    gp << "set logscale xy\nset xrange [1:3e5]\nset yrange [0.3:2e6]\n";
    gp << "set ytics ('0' 0.5, '1' 1, '10' 10, '100' 100, '1k' 1000, '10k' 10000, '100k' 100000, '1M' 1000000)\n";
    gp << "set xtics ('1 ns' 1, '10' 10, '100' 100, '1 µs' 1000, '10' 10000, '100 µs' 100000)\n";
    gp << "set grid\nset key off\nset xlabel 'ns per query (median CPU time)'\nset ylabel 'wrong verdicts per "
          "million'\n";
    int wi = 0;
    for (const auto& w : kWorkloads) {
        fmt::print(gp, "set title '{}'\nplot ", kWorkloadLabel.at(w));
        for (std::size_t mi = 0; mi < kMethods.size(); ++mi)
            fmt::print(gp, "{}'trade.dat' index {} using 1:2:3 with points pt variable ps 1.6 lc rgb '{}'",
                       mi ? ", " : "", wi * kMethods.size() + mi, kColors[mi]);
        gp << '\n';
        ++wi;
    }
    write_plot_legend(gp);
}

// ---- the command line and the outputs -----------------------------------------------
// The paired/ ratios of further processes of the benchmark program: a process on a
// shared machine may draw a speed and keep it for its whole run, moving both halves of a
// pair but not always alike (docs/trade.md), so each ratio becomes the median over the
// processes (for an even count, the mean of the middle two), each process's kept.
void merge_paired(Report& r, const std::vector<std::string>& paths) {
    if (paths.empty()) return;
    std::vector<std::map<std::string, Timing>> runs;
    for (const auto& p : paths) runs.push_back(read_bench(p, nullptr, nullptr));
    for (auto& [name, t] : r.timing) {
        if (name.rfind("paired/", 0) != 0 || std::isnan(t.ratio)) continue;
        std::vector<double> v{t.ratio};
        for (const auto& run : runs)
            if (const auto it = run.find(name); it != run.end() && !std::isnan(it->second.ratio))
                v.push_back(it->second.ratio);
        t.process_ratios = v;
        std::sort(v.begin(), v.end());
        const std::size_t n = v.size();
        t.ratio = n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
    }
}

struct Args {
    std::string bench, counters, tracer, tracer_facts, md, plot_dir, plot_png, plot_ref, tracer_png, audit, summary_md;
    std::string render_md, packets, batch_avx2;
    std::vector<std::string> accuracy, bvh, paired;
    std::vector<std::pair<std::string, std::string>> meta;
};

// The exit status when the program is to stop (help, a usage error), else nothing.
std::optional<int> parse_args(int argc, char** argv, Args& a) {
    CLI::App app{"Turns one run of the trade into its report (Markdown, plot data, the checks on stdout).",
                 "rayproof_trade_report"};
    std::vector<std::string> meta;
    app.add_option("--bench", a.bench, "rayproof_bench's JSON")->required();
    app.add_option("--counters", a.counters, "rayproof_bench_counters' JSON");
    app.add_option("--accuracy", a.accuracy, "rayproof_trade_accuracy's CSV (repeatable)");
    app.add_option("--tracer", a.tracer, "the tracer timings: lines LABEL SECONDS");
    app.add_option("--tracer-facts", a.tracer_facts,
                   "the tracer's counts and its comparison with POV-Ray: lines KEY VALUE (rays-MODE, "
                   "queries-MODE, parity-mean, parity-max, parity-differing, parity-pixels, parity-inexact)");
    app.add_option("--bvh", a.bvh,
                   "the BVH timings: lines KEY VALUE (rayproof_bvh_bench's and the generated scenes', scene-N-MODE "
                   "seconds; repeatable)");
    app.add_option("--packets", a.packets, "rayproof_packet_bench's JSON (the box packets' table)");
    app.add_option("--paired", a.paired,
                   "rayproof_bench's JSON of another process's paired/ benchmarks (repeatable): each pair's ratio "
                   "becomes the median over --bench's process and these");
    app.add_option("--batch-avx2", a.batch_avx2, "rayproof_batch_bench_avx2's JSON (the batch table's AVX2 rows)");
    app.add_option("--render-md", a.render_md, "write render/README.md's paragraph on speed here");
    app.add_option("--meta", meta, "a line of the report's head (repeatable)")
        ->type_name("KEY=VALUE")
        ->check(CLI::Validator(
            [](const std::string& v) { return v.find('=') == std::string::npos ? "expects KEY=VALUE, got " + v : ""; },
            ""));
    app.add_option("--md", a.md, "write the full report here");
    app.add_option("--plot-dir", a.plot_dir, "write trade.dat and trade.gp here (with --plot-png)");
    app.add_option("--plot-png", a.plot_png, "the image trade.gp draws");
    app.add_option("--plot-ref", a.plot_ref, "the plot's name as the report refers to it");
    app.add_option("--tracer-png", a.tracer_png, "the tracer comparison image's name as the report refers to it");
    app.add_option("--audit", a.audit, "rayproof-audit's Markdown, included in the report");
    app.add_option("--summary-md", a.summary_md, "write the README's summary here");
    if (const auto stop = rayproof::cli::parse(app, argc, argv)) return stop;
    for (const auto& m : meta) a.meta.emplace_back(m.substr(0, m.find('=')), m.substr(m.find('=') + 1));
    return std::nullopt;
}

Report load(const Args& a) {
    Report r;
    r.meta = a.meta;
    r.timing = read_bench(a.bench, nullptr, &r.context);
    if (!a.counters.empty()) r.counters_timing = read_bench(a.counters, &r.rates, nullptr);
    if (!a.batch_avx2.empty()) r.timing.merge(read_bench(a.batch_avx2, nullptr, nullptr));  // names distinct: *_avx2
    r.accuracy = read_accuracy(a.accuracy);
    if (!a.packets.empty()) read_packets(a.packets, r);
    merge_paired(r, a.paired);
    if (!a.tracer.empty()) {
        std::ifstream in(a.tracer);
        std::string label;
        double seconds;
        while (in >> label >> seconds) r.tracer.emplace_back(label, seconds);
    }
    for (const auto& path : a.bvh) {
        std::ifstream in(path);
        std::string key;
        double value;
        while (in >> key >> value) r.bvh[key] = value;
    }
    if (!a.tracer_facts.empty()) {
        std::ifstream in(a.tracer_facts);
        std::string key;
        double value;
        while (in >> key >> value) r.tracer_facts[key] = value;
    }
    return r;
}

// How the numbers were made: the --meta lines and the machine.
std::string head(const Report& r) {
    std::string o;
    for (const auto& [k, v] : r.meta) o += prose()("head.meta", {{"key", k}, {"value", v}}) + '\n';
    if (r.context.is_null()) return o;
    const json& c = r.context;
    const bool load = c.contains("load_avg") && c["load_avg"].is_array() && !c["load_avg"].empty();
    return o + prose()("head.cpu", {{"cpus", std::to_string(c.value("num_cpus", 0))},
                                    {"mhz", std::to_string(c.value("mhz_per_cpu", 0))},
                                    {"load", load ? num(c["load_avg"][0].get<double>(), 3) : ""}}) +
           '\n';
}

// The audit's Markdown, its headings one level down.
std::string audit_section(const std::string& path) {
    std::ifstream in(path);
    std::string line, audit;
    while (std::getline(in, line)) audit += (line.rfind('#', 0) == 0 ? "##" : "") + line + '\n';
    return prose()("report.audit", {{"audit", audit}});
}

// The full report (docs/trade.md).
std::string full_report(const Report& r, const Args& a, const Vars& common) {
    Vars v = common;
    v["plot"] = a.plot_ref.empty() ? "" : prose()("report.plot", {{"plot_ref", a.plot_ref}});
    v["batch"] = batch_table(r);
    v["packets"] = packets_table(r);
    v["fp_env"] = fp_env_table(r);
    v["exact_stage"] = exact_stage_table(r);
    v["tracer"] = tracer_table(r, a.tracer_png);
    v["bvh"] = bvh_section(r);
    for (const auto& s : kShapes)
        v["shapes"] += prose()("report.shape", {{"shape", kShapeLabel.at(s)}, {"table", shape_table(r, s)}});
    v["audit"] = a.audit.empty() ? "" : audit_section(a.audit);
    return prose()("report", v);
}

// The short version for the README: how it was made, the uniform table, the checks, the
// plot (paths relative to the repository root).
std::string summary_report(const Args& a, const Vars& common) {
    Vars v = common;
    v["plot"] = a.plot_ref.empty() ? "" : prose()("summary.plot", {{"plot_ref", a.plot_ref}});
    v["tracer_png"] = a.tracer_png.empty() ? "" : prose()("summary.tracer", {{"tracer_png", a.tracer_png}});
    return prose()("summary", v);
}

}  // namespace

int main(int argc, char** argv) {
    Args a;
    if (const auto status = parse_args(argc, argv, a)) return *status;
    const Report r = load(a);
    const Vars common = {{"head", head(r)}, {"summary", summary_table(r)}, {"ladder", ladder_table(r)},
                         {"checks", checks(r)}};
    std::cout << prose()("stdout", common);
    if (!a.md.empty()) std::ofstream(a.md) << full_report(r, a, common);
    if (!a.summary_md.empty()) std::ofstream(a.summary_md) << summary_report(a, common);
    if (!a.render_md.empty()) std::ofstream(a.render_md) << render_speed(r);
    if (!a.plot_dir.empty() && !a.plot_png.empty()) {
        write_plot_data(r, a.plot_dir + "/trade.dat");
        write_plot_script(a.plot_dir + "/trade.gp", a.plot_png);
    }
    return 0;
}
