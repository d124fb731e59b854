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
//       [--tracer T.txt] [--meta KEY=VALUE ...] [--md OUT.md] [--plot-dir DIR --plot-png PNG]
//       [--plot-ref NAME] [--tracer-png NAME] [--audit AUDIT.md] [--summary-md OUT.md]
//
// Times are the median over repetitions of the CPU time of one pass over the cases,
// divided by the number of cases (CPU time, not wall time: the machine may be shared);
// the spread is the coefficient of variation over repetitions. certified / fast and
// Epeck / certified verdict are also measured in pairs (bench_common.hpp, time_pair:
// the median over back-to-back pairs of passes of the ratio), which the checks use.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using json = nlohmann::json;

const std::vector<std::string> kShapes = {"aabb", "obb", "plane", "sphere"};
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
    {"aabb", "Aabb"}, {"obb", "Obb"}, {"plane", "Plane"}, {"sphere", "Sphere"}};

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::string cur;
    std::istringstream in(s);
    while (std::getline(in, cur, sep)) out.push_back(cur);
    if (!s.empty() && s.back() == sep) out.emplace_back();
    return out;
}

// ---- timings ----------------------------------------------------------------------
struct Timing {
    double ns = NAN;     // per query / per ray
    double cv = NAN;     // relative spread over repetitions
    double hit_rate = NAN;
    double cases = NAN;
    double ratio = NAN;  // paired/ benchmarks: the second method over the first, median over pairs
};

double to_ns(double t, const std::string& unit) {
    if (unit == "us") return t * 1e3;
    if (unit == "ms") return t * 1e6;
    if (unit == "s") return t * 1e9;
    return t;
}

// name -> timing; per item (query or ray).
std::map<std::string, Timing> read_bench(const std::string& path, std::map<std::string, double>* rates,
                                         json* context) {
    std::map<std::string, Timing> out;
    std::ifstream in(path);
    if (!in) {
        std::cerr << "trade_report: cannot read " << path << '\n';
        return out;
    }
    json j;
    try {
        in >> j;
    } catch (const std::exception& e) {
        std::cerr << "trade_report: " << path << ": " << e.what() << '\n';
        return out;
    }
    if (context && j.contains("context")) *context = j["context"];
    std::map<std::string, json> median, cv, single;
    for (const auto& b : j["benchmarks"]) {
        const std::string run = b.value("run_name", b.value("name", ""));
        if (b.value("run_type", "") == "aggregate") {
            const std::string agg = b.value("aggregate_name", "");
            if (agg == "median") median[run] = b;
            if (agg == "cv") cv[run] = b;
        } else if (!single.count(run)) {
            single[run] = b;
        }
    }
    auto items = [](const json& b) {
        if (b.contains("cases")) return b["cases"].get<double>();
        if (b.contains("rays")) return b["rays"].get<double>();
        return 1.0;
    };
    auto take = [&](const std::string& run, const json& b) {
        Timing t;
        t.cases = items(b);
        t.ns = to_ns(b["cpu_time"].get<double>(), b.value("time_unit", "ns")) / t.cases;
        if (b.contains("hit_rate")) t.hit_rate = b["hit_rate"].get<double>();
        if (b.contains("ratio")) t.ratio = b["ratio"].get<double>();
        if (cv.count(run)) t.cv = cv[run]["cpu_time"].get<double>();
        out[run] = t;
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
            out[row["shape"] + "/" + row["type"] + "/" + row["workload"] + "/" + row["method"]] = a;
        }
    }
    return out;
}

// ---- formatting -------------------------------------------------------------------
std::string fmt(double x, int digits = 3) {
    if (std::isnan(x)) return "—";
    char b[64];
    if (x != 0 && (std::abs(x) >= 1e6 || std::abs(x) < 1e-3))
        std::snprintf(b, sizeof b, "%.*g", digits, x);
    else if (std::abs(x) >= 100)
        std::snprintf(b, sizeof b, "%.0f", x);
    else
        std::snprintf(b, sizeof b, "%.*g", digits, x);
    return b;
}
std::string fmt_ppm(double x) {
    if (std::isnan(x)) return "—";
    if (x == 0) return "0";
    return fmt(x, 3);
}
// ulps: huge values (a wrong interval end, NaN) read better as powers of two.
std::string fmt_ulps(const std::string& s) {
    if (s == "n/a" || s.empty()) return "—";
    if (s == "inf") return "NaN t";
    const double v = std::stod(s);
    if (v < 1e6) return s;
    char b[32];
    std::snprintf(b, sizeof b, "2^%.0f", std::log2(v));
    return b;
}
std::string pct(double x) { return std::isnan(x) ? "—" : fmt(100 * x, 2) + "%"; }

// ---- the report -------------------------------------------------------------------
struct Report {
    std::map<std::string, Timing> timing, counters_timing;
    std::map<std::string, double> rates;
    std::map<std::string, Accuracy> accuracy;
    std::vector<std::pair<std::string, std::string>> meta;
    std::vector<std::pair<std::string, double>> tracer;  // label -> seconds
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
    // certified / fast on uniform input measured in pairs (NaN when not measured), or
    // another pair by its name.
    double paired(const std::string& shape, const std::string& type,
                  const std::string& pair = "certified_over_fast") const {
        const auto it = timing.find("paired/" + shape + "/" + type + "/uniform/" + pair);
        return it == timing.end() ? NAN : it->second.ratio;
    }
};

std::string summary_table(const Report& r) {
    std::ostringstream o;
    o << "| shape | type | fast | conservative | certified | certified / fast | certified / fast, paired | certified, "
         "verdict alone | textbook | branch-free slab | CGAL Epeck | Epeck / certified | Epeck / certified verdict | CGAL "
         "rationals | Embree | exact stage (certified) |\n";
    o << "|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n";
    for (const auto& s : kShapes)
        for (const auto& t : kTypes) {
            const double f = r.ns(s, t, "uniform", "fast"), c = r.ns(s, t, "uniform", "certified");
            const double e = r.ns(s, t, "uniform", "cgal_epeck"), v = r.ns(s, t, "uniform", "certified_verdict");
            const auto rate = r.rates.find("exact_stage/" + s + "/" + t + "/general");
            o << "| " << kShapeLabel.at(s) << " | " << t << " | " << fmt(f) << " | "
              << fmt(r.ns(s, t, "uniform", "conservative")) << " | " << fmt(c) << " | " << fmt(c / f, 3) << "× | "
              << (std::isnan(r.paired(s, t)) ? std::string("—") : fmt(r.paired(s, t), 3) + "×") << " | " << fmt(v)
              << " | " << fmt(r.ns(s, t, "uniform", "textbook")) << " | " << fmt(r.ns(s, t, "uniform", "branchless")) << " | "
              << fmt(e) << " | " << (std::isnan(e) ? std::string("—") : fmt(e / c, 3) + "×") << " | "
              << (std::isnan(e) ? std::string("—") : fmt(e / v, 3) + "×") << " | "
              << fmt(r.ns(s, t, "uniform", "cgal_rational")) << " | " << fmt(r.ns(s, t, "uniform", "embree")) << " | "
              << (rate == r.rates.end() ? std::string("—") : fmt(rate->second, 3)) << " |\n";
        }
    return o.str();
}

std::string checks(const Report& r) {
    std::ostringstream o;
    auto mark = [](bool ok) { return ok ? "**yes**" : "**no**"; };
    // One method's time over another's on uniform input: the ratio of the two medians,
    // and the paired measurement where it was made (both passes of a pair see the
    // machine in the same state), else the ratio of the medians. Both checks are read
    // on the kernel's headline case (Aabb, double: the slab method), with every shape
    // and type listed beside it.
    auto medians = [&](const std::string& s, const std::string& t, const char* num, const char* den) {
        return r.ns(s, t, "uniform", num) / r.ns(s, t, "uniform", den);
    };
    auto ratio = [&](const std::string& s, const std::string& t, const char* pair, const char* num, const char* den) {
        const double p = r.paired(s, t, pair);
        return std::isnan(p) ? medians(s, t, num, den) : p;
    };
    auto in_pairs = [&](const char* pair) {
        return std::isnan(r.paired("aabb", "double", pair)) ? "" : ", measured in pairs";
    };
    const char* const cf[] = {"certified_over_fast", "certified", "fast"};
    const double q = ratio("aabb", "double", cf[0], cf[1], cf[2]);
    o << "- Certified within 1.5× of fast on uniform input (Aabb, double" << in_pairs(cf[0]) << "): " << fmt(q, 3)
      << "× — " << mark(q <= 1.5)
      << " (the ratio of the two medians in the table: " << fmt(medians("aabb", "double", cf[1], cf[2]), 3)
      << "×). Every shape and type: ";
    bool first = true;
    for (const auto& s : kShapes)
        for (const auto& t : kTypes) {
            o << (first ? "" : ", ") << kShapeLabel.at(s) << ' ' << t << ' ' << fmt(ratio(s, t, cf[0], cf[1], cf[2]), 3)
              << "×";
            first = false;
        }
    o << ".\n";
    // CGAL's do_intersect answers the verdict alone, so the like-for-like comparison is
    // with the kernel's verdict query; the full query (faithful t and face as well) is
    // listed beside it.
    const char* const ev[] = {"epeck_over_certified_verdict", "cgal_epeck", "certified_verdict"};
    const double ae = ratio("aabb", "double", ev[0], ev[1], ev[2]);
    o << "- Certified at least 50× faster than CGAL Epeck on uniform input, the same question (`verdict`, "
         "certified, against `do_intersect`; Aabb, double"
      << in_pairs(ev[0]) << "): " << fmt(ae, 4) << "× — " << mark(ae >= 50)
      << " (the ratio of the two medians in the table: " << fmt(medians("aabb", "double", ev[1], ev[2]), 3)
      << "×). Every shape and type, in pairs where the pair ran (the ratio of the two medians in brackets): ";
    first = true;
    for (const auto& s : kShapes)
        for (const auto& t : kTypes) {
            if (std::isnan(r.ns(s, t, "uniform", "cgal_epeck"))) continue;
            o << (first ? "" : ", ") << kShapeLabel.at(s) << ' ' << t << ' ' << fmt(ratio(s, t, ev[0], ev[1], ev[2]), 3)
              << "× [" << fmt(medians(s, t, ev[1], ev[2]), 3) << "×]";
            first = false;
        }
    o << ". The full certified answer (verdict, faithful t and face) against the same `do_intersect`: ";
    first = true;
    for (const auto& s : kShapes)
        for (const auto& t : kTypes) {
            const double e = r.ns(s, t, "uniform", "cgal_epeck");
            if (std::isnan(e)) continue;
            o << (first ? "" : ", ") << kShapeLabel.at(s) << ' ' << t << ' '
              << fmt(e / r.ns(s, t, "uniform", "certified"), 3) << "×";
            first = false;
        }
    o << ".\n";
    o << "- Fast mode's wrong verdicts on the grazing-heavy workload (per million): ";
    first = true;
    for (const auto& s : kShapes)
        for (const auto& t : kTypes) {
            const Accuracy* a = r.acc(s, t, "grazing", "fast");
            o << (first ? "" : ", ") << kShapeLabel.at(s) << ' ' << t << ' '
              << (a ? fmt_ppm(a->per_million(a->wrong)) : "—");
            first = false;
        }
    o << ".\n";
    o << "- Embree on the far-small-sphere workload (float): ";
    for (const char* m : {"embree", "embree_robust"}) {
        const Accuracy* a = r.acc("sphere", "float", "far_small", m);
        if (!a) continue;
        o << kMethodLabel.at(m) << " " << fmt_ppm(a->per_million(a->wrong)) << " wrong verdicts per million answered ("
          << fmt_ppm(a->per_million(a->false_miss)) << " false misses), " << fmt(a->refused / a->cases * 1e6)
          << " per million rays refused (beyond its 1.8e18 coordinate limit), t_enter up to " << fmt_ulps(a->max_ulps)
          << " ulps; ";
    }
    if (const Accuracy* a = r.acc("sphere", "float", "far_small", "certified"))
        o << "certified " << fmt_ppm(a->per_million(a->wrong)) << " wrong, t off by " << fmt_ulps(a->max_ulps)
          << " ulps";
    o << ".\n";
    // Any method that hung or crashed on some case.
    for (const auto& [key, a] : r.accuracy)
        if (a.status != "ok") o << "- Did not finish: `" << key << "`: " << a.status << ".\n";
    return o.str();
}

std::string shape_table(const Report& r, const std::string& s) {
    std::ostringstream o;
    o << "| type | workload | method | ns / query | spread | Mq/s | × fast | wrong / M | false miss / M | "
         "face wrong / M | t not faithful / M | max t error (ulps) | cases judged |\n";
    o << "|---|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n";
    for (const auto& t : kTypes)
        for (const auto& w : kWorkloads)
            for (const auto& m : kMethods) {
                const Timing* tm = r.scalar(s, t, w, m);
                const Accuracy* a = r.acc(s, t, w, m);
                if (!tm && !a) continue;
                const double ns = tm ? tm->ns : NAN, f = r.ns(s, t, w, "fast");
                o << "| " << t << " | " << w << " | " << kMethodLabel.at(m) << " | " << fmt(ns) << " | "
                  << (tm ? pct(tm->cv) : "—") << " | " << fmt(1e3 / ns) << " | " << fmt(ns / f, 3) << " | ";
                if (!a) {
                    o << "— | — | — | — | — | — |\n";
                } else if (a->status != "ok") {
                    o << a->status << " | | | | | |\n";
                } else {
                    o << fmt_ppm(a->per_million(a->wrong)) << " | " << fmt_ppm(a->per_million(a->false_miss)) << " | "
                      << (a->face_mismatch < 0 ? "—" : fmt_ppm(a->per_million(a->face_mismatch))) << " | "
                      << (a->t_off < 0 ? "—" : fmt_ppm(a->per_million(a->t_off))) << " | " << fmt_ulps(a->max_ulps)
                      << " | " << fmt(a->cases, 6) << (a->refused > 0 ? " (" + fmt(a->refused, 6) + " refused)" : "")
                      << " |\n";
                }
            }
    return o.str();
}

std::string batch_table(const Report& r) {
    std::vector<long> sizes;
    for (const auto& [name, t] : r.timing) {
        if (name.rfind("batch/", 0) != 0) continue;
        const long n = std::stol(name.substr(name.rfind('/') + 1));
        if (std::find(sizes.begin(), sizes.end(), n) == sizes.end()) sizes.push_back(n);
    }
    std::sort(sizes.begin(), sizes.end());
    if (sizes.empty()) return "(no batch timings)\n";
    std::ostringstream o;
    o << "Million rays per second, `intersect(span<const Ray>, shape, mode, span<Hit>)`, one shape, uniform rays:\n\n";
    o << "| shape | type | mode |";
    for (long n : sizes) o << ' ' << (n >= 1000000 ? std::to_string(n / 1000000) + "M" : n >= 1000 ? std::to_string(n / 1000) + "k" : std::to_string(n)) << " |";
    o << "\n|---|---|---|";
    for (std::size_t i = 0; i < sizes.size(); ++i) o << "--:|";
    o << '\n';
    for (const auto& s : kShapes)
        for (const auto& t : kTypes)
            for (const char* m : {"fast", "conservative", "certified"}) {
                o << "| " << kShapeLabel.at(s) << " | " << t << " | " << m << " |";
                for (long n : sizes) {
                    const auto it = r.timing.find("batch/" + s + "/" + t + "/" + m + "/" + std::to_string(n));
                    o << ' ' << (it == r.timing.end() ? "—" : fmt(1e3 / it->second.ns)) << " |";
                }
                o << '\n';
            }
    return o.str();
}

std::string exact_stage_table(const Report& r) {
    std::vector<std::string> gens;
    for (const auto& [name, rate] : r.rates) {
        if (name.find('#') != std::string::npos) continue;
        const std::string g = name.substr(name.rfind('/') + 1);
        if (std::find(gens.begin(), gens.end(), g) == gens.end()) gens.push_back(g);
    }
    if (gens.empty()) return "(no exact-stage counts)\n";
    const std::vector<std::string> order = {"general",     "log_uniform", "grazing", "near_grazing",    "parallel",
                                            "on_boundary", "extreme",     "rotated_integer", "invalid"};
    std::vector<std::string> sorted;
    for (const auto& g : order)
        if (std::find(gens.begin(), gens.end(), g) != gens.end()) sorted.push_back(g);
    for (const auto& g : gens)
        if (std::find(sorted.begin(), sorted.end(), g) == sorted.end()) sorted.push_back(g);
    std::ostringstream o;
    o << "| shape | type |";
    for (const auto& g : sorted) o << ' ' << (g == "general" ? "general (uniform)" : g) << " |";
    o << "\n|---|---|";
    for (std::size_t i = 0; i < sorted.size(); ++i) o << "--:|";
    o << '\n';
    for (const auto& s : kShapes)
        for (const auto& t : kTypes) {
            o << "| " << kShapeLabel.at(s) << " | " << t << " |";
            for (const auto& g : sorted) {
                const std::string key = "exact_stage/" + s + "/" + t + "/" + g;
                const auto it = r.rates.find(key);
                const auto q = r.rates.find(key + "#queries");
                if (it == r.rates.end() || q == r.rates.end() || q->second == 0)
                    o << " — |";
                else
                    o << ' ' << fmt(it->second, 3) << " |";
            }
            o << '\n';
        }
    return o.str();
}

std::string tracer_table(const Report& r, const std::string& png) {
    if (r.tracer.empty()) return "(no tracer timings)\n";
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
    std::ostringstream o;
    o << "| renderer | wall s | ÷ POV-Ray | CPU s | ÷ POV-Ray |\n|---|--:|--:|--:|--:|\n";
    for (const auto& name : order) {
        const double w = wall.count(name) ? wall[name] : NAN, c = cpu.count(name) ? cpu[name] : NAN;
        o << "| " << (name == "povray" ? "POV-Ray 3.7 (exported scene)" : "rayproof render, " + name) << " | "
          << fmt(w, 3) << " | " << fmt(w / pw, 3) << " | " << fmt(c, 3) << " | " << fmt(c / pc, 3) << " |\n";
    }
    if (!png.empty()) o << "\n![rayproof (left) and POV-Ray (right), the same scene](" << png << ")\n";
    return o.str();
}

void write_plot(const Report& r, const std::string& dir, const std::string& png) {
    // trade.dat: one index block per workload, one sub-block per method; columns:
    // ns/query, wrong per million (0 drawn at the floor), point type (shape; filled =
    // double), shape, type.
    std::ofstream dat(dir + "/trade.dat");
    const std::map<std::string, int> pt_open = {{"aabb", 4}, {"obb", 6}, {"plane", 8}, {"sphere", 12}};
    const double floor_ppm = 0.5;
    for (const auto& w : kWorkloads) {
        dat << "# workload " << w << '\n';
        for (const auto& m : kMethods) {
            dat << "# method " << m << '\n';
            int rows = 0;
            for (const auto& s : kShapes)
                for (const auto& t : kTypes) {
                    const Timing* tm = r.scalar(s, t, w, m);
                    const Accuracy* a = r.acc(s, t, w, m);
                    if (!tm || !a || a->status != "ok" || a->answered() <= 0) continue;
                    const double ppm = a->per_million(a->wrong);
                    dat << tm->ns << ' ' << std::max(ppm, floor_ppm) << ' ' << pt_open.at(s) + (t == "double")
                        << ' ' << s << ' ' << t << '\n';
                    ++rows;
                }
            if (rows == 0) dat << "NaN NaN 1 none none\n";
            dat << "\n\n";
        }
    }
    std::ofstream gp(dir + "/trade.gp");
    const std::vector<std::string> colors = {"#1b9e77", "#e6ab02", "#d95f02", "#fb9a99", "#7570b3",
                                             "#e7298a", "#66a61e", "#a6761d", "#1f78b4", "#666666"};
    if (colors.size() < kMethods.size()) throw std::logic_error("trade_report: a color per method is missing");
    gp << "set terminal pngcairo size 1500,900 font 'DejaVu Sans,10'\n";
    gp << "set output '" << png << "'\n";
    gp << "set multiplot layout 2,3 title 'Time per query against wrong verdicts (per million, judged by the exact "
          "oracle); 0 drawn on the floor'\n";
    gp << "set logscale xy\nset xrange [1:3e5]\nset yrange [0.3:2e6]\n";
    gp << "set ytics ('0' 0.5, '1' 1, '10' 10, '100' 100, '1k' 1000, '10k' 10000, '100k' 100000, '1M' 1000000)\n";
    gp << "set xtics ('1 ns' 1, '10' 10, '100' 100, '1 µs' 1000, '10' 10000, '100 µs' 100000)\n";
    gp << "set grid\nset key off\nset xlabel 'ns per query (median CPU time)'\nset ylabel 'wrong verdicts per "
          "million'\n";
    int wi = 0;
    for (const auto& w : kWorkloads) {
        gp << "set title '" << kWorkloadLabel.at(w) << "'\n";
        gp << "plot ";
        for (std::size_t mi = 0; mi < kMethods.size(); ++mi) {
            gp << (mi ? ", " : "") << "'trade.dat' index " << wi * int(kMethods.size()) + int(mi)
               << " using 1:2:3 with points pt variable ps 1.6 lc rgb '" << colors[mi] << "'";
        }
        gp << '\n';
        ++wi;
    }
    // The legend panel.
    gp << "unset title\nunset grid\nunset logscale\nunset xtics\nunset ytics\nunset xlabel\nunset ylabel\nunset "
          "border\nset xrange [0:10]\nset yrange [0:10]\n";
    for (std::size_t mi = 0; mi < kMethods.size(); ++mi) {
        const double y = 9.3 - 0.85 * double(mi);
        gp << "set label " << mi + 1 << " '" << kMethodLabel.at(kMethods[mi]) << "' at 1.2," << y
           << " tc rgb '" << colors[mi] << "' font ',11'\n";
        gp << "set object " << mi + 1 << " circle at 0.6," << y << " size 0.18 fc rgb '" << colors[mi]
           << "' fs solid noborder\n";
    }
    gp << "set label 20 'point: Aabb square, Obb circle,' at 5.2,9.3\n";
    gp << "set label 21 'Plane triangle, Sphere diamond;' at 5.2,8.45\n";
    gp << "set label 22 'filled: double, open: float' at 5.2,7.6\n";
    gp << "plot NaN notitle\nunset multiplot\n";
}

int usage() {
    std::cerr << "usage: rayproof_trade_report --bench B.json [--counters C.json] [--accuracy A.csv ...]\n"
                 "       [--tracer T.txt] [--meta KEY=VALUE ...] [--md OUT.md] [--plot-dir DIR --plot-png PNG]\n"
                 "       [--plot-ref NAME] [--tracer-png NAME] [--audit AUDIT.md] [--summary-md OUT.md]\n";
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    std::string bench, counters, tracer, md, plot_dir, plot_png, plot_ref, tracer_png, audit, summary_md;
    std::vector<std::string> accuracy;
    Report r;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            usage();
            return 0;
        }
        if (i + 1 >= argc) return usage();
        const std::string v = argv[++i];
        if (a == "--bench") bench = v;
        else if (a == "--counters") counters = v;
        else if (a == "--accuracy") accuracy.push_back(v);
        else if (a == "--tracer") tracer = v;
        else if (a == "--md") md = v;
        else if (a == "--plot-dir") plot_dir = v;
        else if (a == "--plot-png") plot_png = v;
        else if (a == "--plot-ref") plot_ref = v;
        else if (a == "--tracer-png") tracer_png = v;
        else if (a == "--audit") audit = v;
        else if (a == "--summary-md") summary_md = v;
        else if (a == "--meta") {
            const auto eq = v.find('=');
            if (eq == std::string::npos) return usage();
            r.meta.emplace_back(v.substr(0, eq), v.substr(eq + 1));
        } else
            return usage();
    }
    if (bench.empty()) return usage();
    r.timing = read_bench(bench, nullptr, &r.context);
    if (!counters.empty()) r.counters_timing = read_bench(counters, &r.rates, nullptr);
    r.accuracy = read_accuracy(accuracy);
    if (!tracer.empty()) {
        std::ifstream in(tracer);
        std::string label;
        double seconds;
        while (in >> label >> seconds) r.tracer.emplace_back(label, seconds);
    }

    std::ostringstream head;
    for (const auto& [k, v] : r.meta) head << "- " << k << ": " << v << '\n';
    if (!r.context.is_null()) {
        head << "- CPU: " << r.context.value("num_cpus", 0) << " cores at " << r.context.value("mhz_per_cpu", 0)
             << " MHz; load average at the start of the timings: ";
        if (r.context.contains("load_avg") && r.context["load_avg"].is_array() && !r.context["load_avg"].empty())
            head << fmt(r.context["load_avg"][0].get<double>(), 3);
        head << '\n';
    }

    const std::string summary = summary_table(r), check = checks(r);
    std::cout << "## Uniform random input: ns per query (median CPU time)\n\n" << summary << "\n## Checks\n\n" << check;

    if (!md.empty()) {
        std::ofstream o(md);
        o << "# The trade: speed against accuracy\n\n"
             "Generated by `./scripts/trade.sh` (do not edit by hand). Every number below comes from one run: the "
             "timings (Google Benchmark, `bench/`), the exact-stage counts, the accuracy judgements (every answer "
             "compared with the exact CGAL oracle, on the very cases that were timed) and the tracer comparison.\n\n"
          << head.str()
          << "\nTimes are the median CPU time over the repetitions of one pass over the cases, divided by the number "
             "of cases (CPU time rather than wall time, because the machine may be shared); *spread* is the "
             "coefficient of variation over the repetitions. *certified / fast, paired* times one pass of fast "
             "and one of certified over the same cases back to back, many times, each after an untimed pass of "
             "the same method (warm, as every method is timed alone), and is the median of the ratios "
             "(the median of the repetitions' medians): both halves of a pair run with the machine in the same "
             "state, which two independent medians on a shared machine need not; the checks use it. The Epeck check is measured the same way (one pass of the certified verdict query, one of Epeck's do_intersect, on the cases both are timed on). Accuracy rates are per million answered cases. CGAL "
             "answers a verdict only (no t, no face); Embree answers the first surface crossing only, computes in "
             "float, and refuses rays with a coordinate beyond 1.8e18.\n\n"
             "## Uniform random input (ns per query)\n\n"
          << summary << "\n## Checks\n\n" << check;
        if (!plot_ref.empty())
            o << "\n## The plot\n\n![time per query against wrong verdicts, one panel per workload](" << plot_ref
              << ")\n";
        o << "\n## Batch: throughput as the batch grows\n\n" << batch_table(r);
        o << "\n## How often the certified mode needs exact arithmetic\n\nThe fraction of certified queries that "
             "left the floating-point filter for the exact stage, per case generator (counted in a separate build "
             "with `RAYPROOF_COUNTERS=1`; the uniform column is the `general` generator, whose first cases are the "
             "uniform workload):\n\n"
          << exact_stage_table(r);
        o << "\n## Tracer: rayproof against POV-Ray\n\nThe default scene at 640×480, same depth, 2 threads each:\n\n"
          << tracer_table(r, tracer_png);
        o << "\n## Notes on the baselines\n\n"
             "- *certified, verdict alone*: `rayproof::verdict(ray, shape, certified)`, the exact verdict without t "
             "or face: the question CGAL's `do_intersect` answers, so the Epeck comparison of the checks uses it. "
             "The certified Aabb, plane and sphere have verdict filters of their own (no winner, face, root or "
             "rounding of t), the Obb answers it with the full query.\n"
             "- *textbook*: boxes the branchy slab, per axis (lo - o)/d and (hi - o)/d, swap, compare, early exit (the "
             "classic course notes), Obb in the box frame; Sphere the textbook quadratic b² - ac; Plane (offset - n·o)/(n·d). "
             "*branch-free slab*: inverse direction and min/max, no face. Neither validates its input.\n"
             "- *CGAL*: `do_intersect` on Ray_3 / Segment_3 / Line_3 / Point_3 chosen by the ray's range, built "
             "exactly from the inputs. CGAL 5.5's `do_intersect(Segment_3, Sphere_3)` answers for the sphere surface "
             "(false when both ends are inside), unlike its Ray_3 and Line_3 versions: the adapter adds the "
             "containment of the segment's source, for the ball. Left as measured: CGAL 5.5's "
             "`do_intersect(Line_3, Iso_cuboid_3)` answers hit for a line parallel to two axes that lies in the plane "
             "of a face of the first and outside the slab of the other (the wrong verdicts in the CGAL rows of the "
             "Aabb table).\n"
             "- *Embree* 3 (Debian): one scene with one `RTC_GEOMETRY_TYPE_SPHERE_POINT` per case, `rtcIntersect1`; "
             "float only. It needs t_near >= 0 (a ray with t_min < 0 is asked forwards and backwards), it reports "
             "surface crossings (a ray range inside the ball is a miss for it), and it requires every origin and "
             "direction component to be at most 1.844e18 (its `FLT_LARGE`; Debian's build asserts it): such rays are "
             "refused and counted apart (*refused*), the rates are per answered ray.\n";
        o << "\n## Everything, per shape\n\nWorkloads: *uniform* = the `general` generator; *grazing* = `grazing` and "
             "`near_grazing` alternately; *parallel* = `parallel`; *extreme* = `extreme`; *far_small* = the "
             "tiny-and-far cases of `extreme` (origin in [-1, 1]³, the shape at least 2^20 away and at most 2^-9 of "
             "that distance across). *t not faithful*: t_enter or t_exit is not one of the two floating-point "
             "neighbours of the exact value; *max t error*: how many representable values away from the nearest "
             "faithful one (a wrong interval end shows as a power of two; *NaN t* when some answer had a NaN t).\n";
        for (const auto& s : kShapes) o << "\n### " << kShapeLabel.at(s) << "\n\n" << shape_table(r, s);
        if (!audit.empty()) {
            std::ifstream in(audit);
            o << "\n## The audit: every generator, every mode\n\nThe output of `rayproof-audit` in the same run "
                 "(its own seed and sample sizes):\n\n";
            std::string line;
            while (std::getline(in, line)) o << (line.rfind('#', 0) == 0 ? "##" : "") << line << '\n';
        }
    }
    if (!summary_md.empty()) {
        // The short version for the README: how it was made, the uniform table, the checks,
        // the plot (paths relative to the repository root).
        std::ofstream o(summary_md);
        o << head.str() << "\nns per query on uniform random input (median CPU time):\n\n" << summary << "\n" << check;
        if (!plot_ref.empty()) o << "\n![time per query against wrong verdicts](docs/" << plot_ref << ")\n";
        if (!tracer_png.empty()) o << "\n![rayproof and POV-Ray, the default scene](docs/" << tracer_png << ")\n";
        o << "\nEverything else (every workload and baseline, batch sizes, exact-stage rates, the tracer timings): "
             "[docs/trade.md](docs/trade.md).\n";
    }
    if (!plot_dir.empty() && !plot_png.empty()) write_plot(r, plot_dir, plot_png);
    return 0;
}
