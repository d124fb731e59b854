// exact_number.hpp — internal to the oracle library: the exact number type and the
// representation behind ExactValue. Only the library's own files include it.
//
// Q is CGAL::Gmpq, CGAL's own reference-counted wrapper of GMP's mpq_t: it needs the C
// GMP library only (no gmpxx), so the oracle also builds where the C++ GMP wrapper is
// unavailable (libc++ builds). Gmpq has no expression templates: every operator returns
// a Gmpq, and the code below still writes the types out.
#pragma once

#include <rayproof/oracle/oracle.hpp>

#include <CGAL/Gmpq.h>

#include <cmath>
#include <memory>

namespace rayproof::oracle {

using Q = CGAL::Gmpq;
using Z = CGAL::Gmpz;

// kind == rational: `p`. kind == quadratic_root: p + sigma·sqrt(r), r > 0 and not the
// square of a rational (so this form is canonical: two roots are equal iff p, r and sigma
// are). The infinite kinds use no number.
struct ExactValue::Impl {
    Kind kind = Kind::none;
    Q p{0}, r{0};
    int sigma = 0;
};

namespace internal {

// An exact rational from a finite float or double (the caller has checked finiteness:
// GMP raises SIGFPE on NaN and inf).
inline Q to_q(double x) { return Q{x}; }
inline Q to_q(float x) { return Q{double(x)}; }

inline ExactValue make_infinite(int sign) {
    auto impl = std::make_shared<ExactValue::Impl>();
    impl->kind = sign < 0 ? ExactValue::Kind::minus_infinity : ExactValue::Kind::plus_infinity;
    return ExactValue{std::move(impl)};
}
inline ExactValue make_rational(const Q& q) {
    auto impl = std::make_shared<ExactValue::Impl>();
    impl->kind = ExactValue::Kind::rational;
    impl->p = q;
    return ExactValue{std::move(impl)};
}
// p + sigma·sqrt(r), r >= 0 (a rational when r is the square of a rational).
ExactValue make_root(const Q& p, const Q& r, int sigma);

// sign(v - x) for a finite value v (rational or root); precondition: v.kind is finite.
int sign_minus(const ExactValue::Impl& v, const Q& x);

}  // namespace internal
}  // namespace rayproof::oracle
