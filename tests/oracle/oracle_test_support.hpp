// oracle_test_support.hpp — helpers shared by the oracle's own tests: the scalar type
// list, hand-computed answer checks, the invalid-ray classes, and the cross-check of the
// oracle against CGAL's geometric predicates over every registered generator.
#pragma once

#include <rayproof/generators.hpp>
#include <rayproof/oracle/crosscheck.hpp>
#include <rayproof/oracle/oracle.hpp>
#include <rayproof/rayproof.hpp>

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

// For every generator of the shape: the oracle's verdict equals CGAL's (and, with
// with_interval, its exact interval equals the one built from CGAL's intersection).
template <class T, class Shape> void crosscheck_all_generators(int cases, bool with_interval) {
    for (const auto& g : gen::generators<T, Shape>()) {
        const std::uint64_t seed = 0x0bac1e ^ gen::name_hash(g.name);
        gen::Rng rng(seed);
        int checked = 0, failures = 0;
        for (int i = 0; i < cases; ++i) {
            const auto c = g.make(rng);
            const auto e = oracle::exact(c.ray, c.shape);
            const auto v = oracle::crosscheck::verdict(c.ray, c.shape);
            if (e.verdict == Verdict::invalid) {
                EXPECT_FALSE(v.has_value()) << c;
                continue;
            }
            if (!v) continue;  // the cross-check does not apply (a flat Obb)
            ++checked;
            if (*v != e.verdict) {
                if (++failures <= 5)
                    ADD_FAILURE() << g.name << " seed " << seed << " case " << i << ": oracle " << e << " vs CGAL "
                                  << *v << "\n  " << c;
                continue;
            }
            if constexpr (std::is_same_v<Shape, Aabb<T>> || std::is_same_v<Shape, Plane<T>>) {
                if (with_interval && e.verdict == Verdict::hit) {
                    const auto iv = oracle::crosscheck::interval(c.ray, c.shape);
                    if (!iv || !(iv->t_enter == e.t_enter) || !(iv->t_exit == e.t_exit)) {
                        if (++failures <= 5)
                            ADD_FAILURE() << g.name << " seed " << seed << " case " << i << ": oracle " << e
                                          << " vs CGAL interval "
                                          << (iv ? iv->t_enter.str() + ", " + iv->t_exit.str() : std::string("none"))
                                          << "\n  " << c;
                    }
                }
            }
        }
        EXPECT_EQ(failures, 0) << g.name;
        if (g.name != "invalid") {
            EXPECT_GT(checked, cases / 4) << g.name << ": too few cases cross-checked";
        }
    }
}

}  // namespace rayproof::oracle_test
