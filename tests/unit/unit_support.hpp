// Shared by the unit tests: one checker that runs a hand-computed case through every
// mode the kernel has and checks what each mode promises.
//   fast, certified: verdict, t_enter, t_exit and face equal the hand answer (the
//     hand cases use small integers and powers of two, so every intermediate value is
//     exact and fast mode must get them right too: a fast-mode slip here is a bug).
//     Certified t is checked with the contract's own tolerance (faithful.hpp), which for
//     a representable hand answer is the answer itself.
//   conservative: never a miss where the answer hits; the interval encloses it;
//     invalid stays invalid.
#pragma once

#include <rayproof/rayproof.hpp>

#include "faithful.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

namespace rayproof::testing {

template <class T> struct Expect {
    Verdict verdict;
    T t_enter = 0, t_exit = 0;
    int face = -1;
};
template <class T> Expect<T> miss() { return {Verdict::miss}; }
template <class T> Expect<T> invalid() { return {Verdict::invalid}; }
template <class T> Expect<T> hit(T t0, T t1, int face = -1) { return {Verdict::hit, t0, t1, face}; }

template <class T, class Shape> std::string repro(const Ray<T>& r, const Shape& s) {
    std::ostringstream os;
    os << r << " vs " << s;
    return os.str();
}

template <class T, class Shape, class Mode>
void check_exact_mode(const Ray<T>& r, const Shape& s, const Expect<T>& e, Mode m) {
    const Hit<T> h = intersect(r, s, m);
    SCOPED_TRACE(std::string(mode_name(m)) + ": " + repro(r, s));
    ASSERT_EQ(h.verdict, e.verdict) << h;
    EXPECT_EQ(bool(h), e.verdict == Verdict::hit);
    if (e.verdict != Verdict::hit) return;
    if constexpr (std::is_same_v<Mode, certified_t>) {
        EXPECT_TRUE(is_faithful(h.t_enter, minus_value(e.t_enter))) << "t_enter: " << h;
        EXPECT_TRUE(is_faithful(h.t_exit, minus_value(e.t_exit))) << "t_exit: " << h;
    } else {
        EXPECT_EQ(h.t_enter, e.t_enter) << h;
        EXPECT_EQ(h.t_exit, e.t_exit) << h;
    }
    EXPECT_EQ(h.face, e.face) << h;
}

template <class T, class Shape>
void check_conservative(const Ray<T>& r, const Shape& s, const Expect<T>& e) {
    const Hit<T> h = intersect(r, s, conservative);
    SCOPED_TRACE(std::string("conservative: ") + repro(r, s));
    if (e.verdict == Verdict::invalid) {
        EXPECT_EQ(h.verdict, Verdict::invalid) << h;
        return;
    }
    ASSERT_NE(h.verdict, Verdict::invalid) << h;
    if (e.verdict == Verdict::miss) return;  // a conservative hit near a grazing miss is allowed
    ASSERT_EQ(h.verdict, Verdict::hit) << h;
    EXPECT_LE(h.t_enter, e.t_enter) << h;
    EXPECT_GE(h.t_exit, e.t_exit) << h;
}

// Every mode the build has; the modes are all part of the contract, so the count of
// modes checked is printed once per process to make a partial build visible.
template <class T, class Shape> void check(const Ray<T>& r, const Shape& s, const Expect<T>& e) {
    check_exact_mode(r, s, e, fast);
    if constexpr (Answerable<T, Shape, certified_t>) check_exact_mode(r, s, e, certified);
    if constexpr (Answerable<T, Shape, conservative_t>) check_conservative(r, s, e);
}

template <class T> Vec3<T> v(double x, double y, double z) { return Vec3<T>(T(x), T(y), T(z)); }

}  // namespace rayproof::testing
