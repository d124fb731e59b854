// exact_answer.hpp — internal to the oracle library: what the per-shape exact answers
// (ray_<shape>_oracle.hpp) share: the extended rationals t_min and t_max may be, the
// invalid answer, and a vector converted exactly. Part of oracle.cpp's translation unit
// (CGAL translation units are expensive; the oracle keeps one).
#pragma once

#include "exact_number.hpp"

#include <array>
#include <cmath>

namespace rayproof::oracle {

using internal::to_q;

namespace {

// An extended rational: -inf, +inf or a rational (t_min and t_max may be infinite).
struct XQ {
    int inf = 0;  // -1, +1, or 0 for the rational q
    Q q{0};
};
template <class T> XQ xq(T t) {
    if (std::isinf(t)) return {t < 0 ? -1 : 1, Q{0}};
    return {0, to_q(t)};
}
int cmp(const XQ& a, const XQ& b) {
    if (a.inf != 0 || b.inf != 0) return a.inf == b.inf ? 0 : (a.inf < b.inf ? -1 : 1);
    return int(CGAL::compare(a.q, b.q));
}
ExactValue value_of(const XQ& x) { return x.inf ? internal::make_infinite(x.inf) : internal::make_rational(x.q); }

template <class T> Exact<T> invalid_answer() {
    Exact<T> e;
    e.verdict = Verdict::invalid;
    return e;
}

template <class T> std::array<Q, 3> q3(const Vec3<T>& v) { return {to_q(v[0]), to_q(v[1]), to_q(v[2])}; }

}  // namespace
}  // namespace rayproof::oracle
