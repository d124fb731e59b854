// oracle_test_support.hpp — helpers shared by the oracle's own tests: the scalar type
// list, hand-computed answer checks, the invalid-ray classes, and the cross-check of the
// oracle and of the kernel's certified mode against CGAL's own answer over every
// registered generator.
#pragma once

#include <rayproof/generators.hpp>
#include <rayproof/oracle/crosscheck.hpp>
#include <rayproof/oracle/oracle.hpp>
#include <rayproof/rayproof.hpp>

#include "faithful.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace rayproof::oracle_test {

using Scalars = ::testing::Types<float, double>;
struct ScalarNames {
    template <class T> static std::string GetName(int) { return std::is_same_v<T, float> ? "float" : "double"; }
};

template <class T> T inf() { return std::numeric_limits<T>::infinity(); }
template <class T> T nan() { return std::numeric_limits<T>::quiet_NaN(); }

// Cases per generator and scalar type for the CGAL cross-checks (exact, a few ms each).
inline constexpr int kCrosscheckCases = 400;

// A hit with exactly these rational (or "-inf"/"+inf") t values and this face.
template <class T>
void expect_answer(const oracle::Exact<T>& e, const std::string& enter, const std::string& exit, int face) {
    ASSERT_EQ(e.verdict, Verdict::hit) << e;
    EXPECT_EQ(e.t_enter.str(), enter) << e;
    EXPECT_EQ(e.t_exit.str(), exit) << e;
    EXPECT_EQ(e.face, face) << e;
}

// Every ray-side invalid class of the contract, starting from the valid ray r.
template <class T, class Shape> void expect_invalid_ray_classes(const Ray<T>& r, const Shape& s) {
    ASSERT_NE(oracle::exact(r, s).verdict, Verdict::invalid);
    const auto check = [&](Ray<T> bad, const char* what) {
        EXPECT_EQ(oracle::exact(bad, s).verdict, Verdict::invalid) << what << ": " << bad;
        EXPECT_FALSE(oracle::valid(bad)) << what;
    };
    for (int i = 0; i < 3; ++i) {
        Ray<T> b = r;
        b.origin[i] = nan<T>();
        check(b, "NaN origin");
        b = r;
        b.origin[i] = -inf<T>();
        check(b, "inf origin");
        b = r;
        b.direction[i] = nan<T>();
        check(b, "NaN direction");
        b = r;
        b.direction[i] = inf<T>();
        check(b, "inf direction");
    }
    Ray<T> b = r;
    b.t_min = nan<T>();
    check(b, "NaN t_min");
    b = r;
    b.t_max = nan<T>();
    check(b, "NaN t_max");
    b = r;
    b.t_min = inf<T>();
    check(b, "t_min = +inf");
    b = r;
    b.t_max = -inf<T>();
    check(b, "t_max = -inf");
    b = r;
    b.t_min = 2;
    b.t_max = std::nextafter(T(2), T(0));
    check(b, "t_min > t_max");
    b = r;
    b.direction = Vec3<T>(T(0), -T(0), T(0));
    check(b, "zero direction");
}

// sign(x - v) for the cross-check's exact value v, decided by CGAL's numbers
// (crosscheck::compare), for the shared tolerance helper; 2 when v has no value (then no
// float is faithful to it).
template <class T> auto minus_cgal(const oracle::ExactValue& v) {
    return [&v](T x) {
        switch (oracle::crosscheck::compare(x, v)) {
            case oracle::Order::below: return -1;
            case oracle::Order::equal: return 0;
            case oracle::Order::above: return 1;
            case oracle::Order::unordered: break;
        }
        return 2;
    };
}

// One input judged three ways against CGAL's answer x (crosscheck::answer, a route that
// shares no algebra with the oracle's):
//   the oracle: the same verdict, the same exact t_enter and t_exit (equal values), the
//     same face, and its faithful brackets enclosing x's values (by CGAL's comparisons);
//   CGAL's predicates: the same verdict when they apply (crosscheck::verdict);
//   the kernel's certified mode: the same verdict and face, each t one of the two floats
//     enclosing x's value (the contract's tolerance, faithful.hpp);
//   the kernel's conservative mode: a hit wherever x hits, its interval enclosing x's.
// Returns what disagrees, empty when nothing does, and adds what was covered to `cov`.
struct Coverage {
    int checked = 0, hits = 0, faces = 0, predicate = 0, failures = 0;
};
template <class T, class Shape> std::string disagreement(const Ray<T>& ray, const Shape& shape, Coverage& cov) {
    std::ostringstream why;
    const auto e = oracle::exact(ray, shape);
    const auto x = oracle::crosscheck::answer(ray, shape);
    const auto v = oracle::crosscheck::verdict(ray, shape);
    ++cov.checked;
    cov.hits += x.verdict == Verdict::hit;
    cov.faces += x.verdict == Verdict::hit && x.face >= 0;
    cov.predicate += v.has_value();
    if (x.verdict != e.verdict) why << "verdicts: oracle " << e << " vs CGAL " << x << "; ";
    if (e.verdict == Verdict::invalid ? v.has_value() : (v && *v != e.verdict)) {
        why << "CGAL's predicate says ";
        if (v) why << *v;
        why << " vs oracle " << e << "; ";
    }
    if (x.verdict == Verdict::hit && e.verdict == Verdict::hit) {
        if (!(x.t_enter == e.t_enter) || !(x.t_exit == e.t_exit) || x.face != e.face)
            why << "answers: oracle " << e << " vs CGAL " << x << "; ";
        const auto be = e.enter_bracket(), bx = e.exit_bracket();
        for (const T b : {be.lo, be.hi})
            if (const auto r = testing::is_faithful(b, minus_cgal<T>(x.t_enter)); !r) why << "oracle's enter bracket: " << r.message() << "; ";
        for (const T b : {bx.lo, bx.hi})
            if (const auto r = testing::is_faithful(b, minus_cgal<T>(x.t_exit)); !r) why << "oracle's exit bracket: " << r.message() << "; ";
    }
    const Hit<T> h = intersect(ray, shape, certified);
    if (h.verdict != x.verdict) {
        why << "certified verdict " << h << " vs CGAL " << x << "; ";
    } else if (h.verdict == Verdict::hit) {
        if (const auto r = testing::is_faithful(h.t_enter, minus_cgal<T>(x.t_enter)); !r)
            why << "certified t_enter: " << r.message() << "; ";
        if (const auto r = testing::is_faithful(h.t_exit, minus_cgal<T>(x.t_exit)); !r)
            why << "certified t_exit: " << r.message() << "; ";
        if (h.face != x.face) why << "certified face " << h.face << " vs CGAL " << x.face << "; ";
        if (why.tellp() > 0) why << "certified " << h << " CGAL " << x << "; ";
    }
    // Conservative: invalid stays invalid; an exact hit is a hit whose interval encloses
    // CGAL's exact one.
    const Hit<T> hc = intersect(ray, shape, conservative);
    if ((hc.verdict == Verdict::invalid) != (x.verdict == Verdict::invalid)) {
        why << "conservative " << hc << " vs CGAL " << x << "; ";
    } else if (x.verdict == Verdict::hit) {
        if (hc.verdict != Verdict::hit || !(minus_cgal<T>(x.t_enter)(hc.t_enter) <= 0) ||
            !(minus_cgal<T>(x.t_exit)(hc.t_exit) == 0 || minus_cgal<T>(x.t_exit)(hc.t_exit) == 1))
            why << "conservative " << hc << " does not enclose CGAL's " << x << "; ";
    }
    return why.str();
}

// Judges `cases` cases of the generator `make` (seeded by `seed`, named `name` in
// failures); `variant(c, i)` may replace the case first (e.g. by a flat copy).
template <class T, class Shape, class Make, class Variant>
Coverage crosscheck_cases(std::string_view name, std::uint64_t seed, int cases, Make make, Variant variant) {
    gen::Rng rng(seed);
    Coverage cov;
    for (int i = 0; i < cases; ++i) {
        const gen::Case<T, Shape> c = variant(make(rng), i);
        const std::string why = disagreement(c.ray, c.shape, cov);
        if (!why.empty() && ++cov.failures <= 5)
            ADD_FAILURE() << name << " seed " << seed << " case " << i << ": " << why << "\n  " << c;
    }
    return cov;
}

// For every generator of the shape: the oracle, CGAL's predicates and the kernel's
// certified mode against CGAL's full answer (see disagreement).
template <class T, class Shape> void crosscheck_all_generators(int cases) {
    for (const auto& g : gen::generators<T, Shape>()) {
        const Coverage cov = crosscheck_cases<T, Shape>(g.name, 0x0bac1e ^ gen::name_hash(g.name), cases, g.make,
                                                        [](const gen::Case<T, Shape>& c, int) { return c; });
        EXPECT_EQ(cov.failures, 0) << g.name;
        if (g.name != "invalid") {
            EXPECT_GT(cov.predicate, cases / 4) << g.name << ": too few cases cross-checked by CGAL's predicates";
        }
    }
}

}  // namespace rayproof::oracle_test
