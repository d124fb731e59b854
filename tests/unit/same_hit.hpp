// Bit-for-bit comparison of answers, shared by the unit tests that hold one form of a
// query to another (prepared and Ray, run-time mode and tag, batch and scalar, packet
// lane and scalar): -0 and +0 told apart, a NaN equal only to the same NaN.
#pragma once

#include <rayproof/io.hpp>
#include <rayproof/types.hpp>

#include <gtest/gtest.h>

#include <cstring>

namespace rayproof::testing {

template <class T> bool same_bits(T a, T b) { return std::memcmp(&a, &b, sizeof(T)) == 0; }

template <class T> ::testing::AssertionResult same_hit(const Hit<T>& a, const Hit<T>& b) {
    if (a.verdict == b.verdict && same_bits(a.t_enter, b.t_enter) && same_bits(a.t_exit, b.t_exit) && a.face == b.face)
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << a << " vs " << b;
}

}  // namespace rayproof::testing
