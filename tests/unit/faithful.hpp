// faithful.hpp — the contract's tolerance for a certified t, as the one test helper every
// suite uses: r is the exact value v "faithfully rounded" when r is one of the two floats
// of T that enclose v, and v itself when v is representable. Beyond the largest finite
// float the upper neighbour is +inf (and symmetrically below -max); -0 and +0 are one
// point. Nothing looser passes: a float one step outside that pair fails.
//
// The exact value comes from the caller as sign_vs(x) = sign(x - v), decided exactly for
// every float x of T, ±inf included (from a rational, the oracle or CGAL); adapters:
//   minus_value(v)    for a v that is itself a T (hand-computed answers, ±inf allowed),
//   minus_rational(q) for a rational q of an exact type (mpq_class, CGAL::Gmpq) built
//                     exactly from a double and ordered by < and >.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace rayproof::testing {

template <class T, class SignVs> ::testing::AssertionResult is_faithful(T r, SignVs&& sign_vs) {
    static_assert(std::is_floating_point_v<T>);
    constexpr T inf = std::numeric_limits<T>::infinity();
    const auto hex = [](T x) {
        std::ostringstream os;
        os << std::hexfloat << x;
        return os.str();
    };
    if (std::isnan(r)) return ::testing::AssertionFailure() << "t is NaN";
    const int s = sign_vs(r);
    if (s == 0) return ::testing::AssertionSuccess();
    // r below v: faithful iff the next float up is already above v (and symmetrically;
    // the step from +inf towards v is the largest finite float).
    const T next = s < 0 ? std::nextafter(r, inf) : std::nextafter(r, -inf);
    const int sn = sign_vs(next);
    if ((s < 0 && sn > 0) || (s > 0 && sn < 0)) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "t = " << hex(r) << " is " << (s < 0 ? "below" : "above")
                                         << " the exact value and not one of the two floats enclosing it";
}

// sign(x - v) for v a T (±inf included).
template <class T> auto minus_value(T v) {
    return [v](T x) { return int(x > v) - int(x < v); };
}

// sign(x - q) for q a rational of type Rat, constructed exactly from a double.
template <class Rat> auto minus_rational(const Rat& q) {
    return [q](auto x) {
        if (std::isinf(x)) return x > 0 ? 1 : -1;
        const Rat xq(static_cast<double>(x));
        return int(xq > q) - int(xq < q);
    };
}

}  // namespace rayproof::testing
