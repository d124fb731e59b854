// Witnesses for the certified error bounds: one input per bound, built so that the
// bound's floating-point evaluation errs by more than a shrunk constant (gamma(1) or
// 2·gamma(1), the `-gamma1` mutants of fuzz/mutants/) would allow, while it stays within
// the kernel's derived constant. Each TEST is named after the mutant it kills; it checks
// first that its input still reaches past the shrunk bound (the realized error, computed
// as the kernel computes it, against the shrunk constant), then that every mode's answer
// keeps its contract against the oracle's exact answer (rayproof::oracle, CGAL). The
// inputs are chosen, not drawn: random inputs almost never align the roundings. Each
// comment derives why the roundings align and by how much the realized error exceeds
// the shrunk bound. Every failure prints the input in hexfloat.
#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/exact.hpp>
#include <rayproof/oracle/contract.hpp>
#include <rayproof/oracle/oracle.hpp>
#include <rayproof/rayproof.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <span>
#include <sstream>
#include <string>

using namespace rayproof;

namespace {

using Scalars = ::testing::Types<float, double>;
struct ScalarNames {
    template <class T> static std::string GetName(int) { return std::is_same_v<T, float> ? "float" : "double"; }
};

constexpr double u = 0x1p-53;
// fl(x·y) rounded on its own (no contraction into a later addition: detail/eft.hpp).
double mul(double x, double y) { return detail::rounded(x * y); }

template <class T, class Shape> std::string repro(const Ray<T>& r, const Shape& s) {
    std::ostringstream os;
    os << r << " vs " << s;
    return os.str();
}

// Every mode's answer, scalar and span form, against the oracle's exact answer, each by
// its mode's contract (rayproof/oracle/contract.hpp).
template <class T, class Shape, class Mode> void expect_mode_keeps_contract(const Ray<T>& r, const Shape& s, Mode m) {
    const oracle::Exact<T> exact = oracle::exact(r, s);
    Hit<T> answers[2] = {intersect(r, s, m), {}};
    intersect(std::span<const Ray<T>>(&r, 1), s, m, std::span<Hit<T>>(answers + 1, 1));
    for (const Hit<T>& h : answers) {
        const oracle::ContractCheck c = oracle::check_contract(r, s, h, exact, m);
        EXPECT_TRUE(c.ok()) << oracle::to_string(oracle::mode_id(m)) << ": " << oracle::describe(c.first())
                            << "\n  input: " << repro(r, s) << "\n  answer: " << h << "\n  exact:  " << exact;
    }
}
template <class T, class Shape> void expect_contract(const Ray<T>& r, const Shape& s) {
    expect_mode_keeps_contract(r, s, certified);
    expect_mode_keeps_contract(r, s, conservative);
    expect_mode_keeps_contract(r, s, fast);  // fast promises validity only
}

}  // namespace

template <class T> class BoundWitness : public ::testing::Test {};
TYPED_TEST_SUITE(BoundWitness, Scalars, ScalarNames);

// obb-det-filter-gamma1: Obb validity, the filter of det3_sign (detail/exact.hpp), whose
// bound gamma(7)·P_fl the mutant shrinks to gamma(1)·P_fl.
// The axes (rows of the matrix below; the columns are the box axes) have rows 0 and 2
// equal, so the determinant is 0 exactly and the box is invalid. The entries are floats
// (22 and 24 bits), so every product of two entries is exact in double; the roundings are
// the minors' differences, the three products entry·minor and the two sums. With
// a = 0x1.6f6128p+0, b = -0x1.f3a23p+0 and the others as below, in units of u:
//   m1 = fl(e·i - f·h) = 0x1.6552bf8cdefc6p+1 rounds by -0.72u|m1|, A = fl(a·m1) by
//   -0.88u|A| (A ~ 4.006); m2 = fl(d·i - f·g) rounds by -0.97u|m2| away from 0 and, b
//   being negative, B = fl(b·m2) by +0.83u|B| (B ~ 4.016); A - B and the sum with C
//   (~0.0098, its minor exact) are exact (Sterbenz; the result is a multiple of A - B's
//   last bit). So det_fl = fl(A - B) + C's rounding = -0x1.b48p-50 = -13.6u, all of it
//   error, against P_fl = 0x1.017cc1d72eee7p+3 ~ 8.05: |det_fl| = 1.695·u·P_fl exceeds
//   gamma(1)·P_fl (about u·P_fl: the mutant trusts the sign and takes the box as valid)
//   and is far below gamma(7)·P_fl ~ 7u·P_fl (the kernel goes exact, finds 0: invalid).
// Found by a search over matrices with two equal rows and one small entry (so that the
// subtractions of the minors round), checked here in exact arithmetic.
TYPED_TEST(BoundWitness, ObbDetFilterGamma1) {
    using T = TypeParam;
    const double a = 0x1.6f6128p+0, b = -0x1.f3a23p+0, c = 0x1.20e448p-8;
    const double d = -0x1.fcc676p+0, e = 0x1.2733cap+0, f = 0x1.6d8028p+0;
    const double g = a, h = b, i = c;
    Mat3<T> axes;
    axes << T(a), T(b), T(c), T(d), T(e), T(f), T(g), T(h), T(i);
    // The exact determinant is 0 (rows 0 and 2 equal), decided by the kernel's exact type.
    ASSERT_EQ(detail::det3_exact<detail::BigDyadic>(axes).sign(), 0);
    // The filter's evaluation, as det3_sign computes it, reaches past gamma(1)·P_fl.
    const double m1 = mul(e, i) - mul(f, h), m2 = mul(d, i) - mul(f, g), m3 = mul(d, h) - mul(e, g);
    const double det = (mul(a, m1) - mul(b, m2)) + mul(c, m3);
    const double perm = std::abs(a) * (std::abs(e) * std::abs(i) + std::abs(f) * std::abs(h)) +
                        std::abs(b) * (std::abs(d) * std::abs(i) + std::abs(f) * std::abs(g)) +
                        std::abs(c) * (std::abs(d) * std::abs(h) + std::abs(e) * std::abs(g));
    EXPECT_EQ(det, -0x1.b48p-50);
    EXPECT_GT(std::abs(det), detail::gamma<double>(1) * perm);
    EXPECT_GT(std::abs(det), 1.6 * u * perm);
    EXPECT_LT(std::abs(det), detail::gamma<double>(7) * perm);

    const Obb<T> box{Vec3<T>(0, 0, 0), axes, Vec3<T>(1, 1, 1)};
    EXPECT_FALSE(oracle::valid(box)) << box;
    EXPECT_EQ(detail::det3_sign(axes), 0) << box;
    const Ray<T> ray{Vec3<T>(-4, 0, 0), Vec3<T>(1, 0, 0)};
    EXPECT_EQ(intersect(ray, box, certified).verdict, Verdict::invalid) << repro(ray, box);
    expect_contract(ray, box);
}
