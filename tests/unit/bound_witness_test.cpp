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
#include <rayproof/detail/ray_sphere_residual.hpp>
#include <rayproof/oracle/contract.hpp>
#include <rayproof/oracle/oracle.hpp>
#include <rayproof/rayproof.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <span>
#include <sstream>
#include <string>
#include <utility>

using namespace rayproof;

namespace {

using Scalars = ::testing::Types<float, double>;
struct ScalarNames {
    template <class T> static std::string GetName(int) { return std::is_same_v<T, float> ? "float" : "double"; }
};

constexpr double u = 0x1p-53;
// fl(x·y) rounded on its own (no contraction into a later addition: detail/eft.hpp).
double mul(double x, double y) { return detail::rounded(x * y); }

// q(t) = |Δ + t·d|² - r² (Δ = o - c) at one end of the range, as the certified sphere's
// verdict filter and cheap signs evaluate it, and the sum ΣM_j² + r² their bound scales
// (M_j = |Δ~_j| + |fl(t·d_j)|).
struct FilteredQ {
    double q, bound_sum;
};
FilteredQ filtered_q(const Sphere<double>& s, const Ray<double>& r, double t) {
    const double rr = mul(s.radius, s.radius);
    FilteredQ f{-rr, rr};
    for (int j = 0; j < 3; ++j) {
        const double delta = r.origin[j] - s.center[j], p = mul(t, r.direction[j]);
        const double w = delta + p, m = std::abs(delta) + std::abs(p);
        f.q += mul(w, w);
        f.bound_sum += mul(m, m);
    }
    return f;
}

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
    EXPECT_EQ(verdict(r, s, certified), oracle::exact(r, s).verdict) << "certified verdict(): " << repro(r, s);
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

// obb-common-bound-gamma1: the certified Obb straight-line path (obb_certified_common in
// ray_obb.hpp), whose bounds of o'_i and d'_i, 2·gamma(4)·Σ|a_ji Δ~_j| and
// 2·gamma(3)·Σ|a_ji d_j|, the mutant shrinks to gamma(1)·Σ.
// Slab 1 (axis (0, 1, 0), centre 0) is entered at t1 = -1 - o_1 = 0x1.0000000000196p+0
// exactly. Slab 0 (axis a = (1 + 2^-21.., -2^-30.., -2^-32..)) is entered at t0 = (-h_0 -
// o'_0)/d'_0, o'_0 = a·(o - c) ~ -2^8, which exceeds t1 by 0.62u (u = 2^-53): the entry
// face is 0. Computed, o'_0 = fl(fl(fl(a_0·Δ~_0) + fl(a_1·Δ~_1)) + fl(a_2·Δ~_2)) with
// Δ~_0 = fl(o_0 - c_0): the four roundings that carry the large term all fall the same
// way, by 0.40, 1.00, 0.98 and 0.85 times u|x| (values near 2^8 from above, where a
// rounding can reach u|x|), and Δ~_2's product and the sum with it are below u|x|: o'_0
// is off by 3.24u|o'_0|, so the computed entry value t0~ = 0x1.ffffffffffffp-1 lies 828u
// below t1. The mutant's bounds, E_0 = 522u and E_1 = 14u (the slab value's bound
// doubles gamma(1)·Σ|a_j0 Δ~_j| = u·|o'_0|·(1 + u)), put slab 1 certainly ahead: face 2.
// The kernel's, E_0 = 4116u and E_1 = 52u, do not; its general path finds face 0.
// Found by a search over boxes with one tilted axis, the origin far out on it (so that
// o'_0 is large against the entry value) and values near powers of two, the other slab's
// entry put on the double just below the exact t0; checked here by the oracle.
TEST(BoundWitnessDouble, ObbCommonBoundGamma1) {
    Mat3<double> axes;
    axes << 0x1.00000c1a1431ap+0, 0, 0, -0x1.33d10481187c4p-30, 1, 0, -0x1.77150e22073a8p-32, 0, 1;
    const Obb<double> box{Vec3<double>(0x1.589944b2d19cbp-7, 0, 0x1.51b7257d274fbp+0), axes,
                          Vec3<double>(0x1.fe0736aa17a7dp+7, 1, 0x1.f4p+9)};
    const Ray<double> ray{Vec3<double>(-0x1.0000de145ed4p+8, -0x1.00000000000cbp+1, 0x1.42121012ddae8p+1),
                          Vec3<double>(1, 1, 1)};
    // The computed o'_0 in the straight path's order, against the exact one: off by more
    // than three times u|o'_0| (gamma(1) allows one).
    const double delta0 = ray.origin[0] - box.center[0], delta2 = ray.origin[2] - box.center[2];
    const double op = (mul(axes(0, 0), delta0) + mul(axes(1, 0), ray.origin[1])) + mul(axes(2, 0), delta2);
    using BD = detail::BigDyadic;
    BD exact_op(0.0);
    for (int j = 0; j < 3; ++j) exact_op = exact_op + BD(axes(j, 0)) * (BD(ray.origin[j]) - BD(box.center[j]));
    const BD err = BD(op) - exact_op;
    EXPECT_EQ((BD(double(err.sign())) * err - BD(3 * u * std::abs(op))).sign(), 1);
    const oracle::Exact<double> exact = oracle::exact(ray, box);
    ASSERT_EQ(exact.verdict, Verdict::hit) << exact;
    EXPECT_EQ(exact.face, 0) << exact;
    EXPECT_EQ(intersect(ray, box, certified).face, 0) << repro(ray, box);
    expect_contract(ray, box);
}

// aabb-lanes-bound-gamma1: the certified Aabb straight-line lanes (aabb_lanes in
// ray_aabb.hpp), whose bound of each computed slab value, K|t~| + eta with K =
// 2·gamma(3), the mutant shrinks to gamma(1)|t~| + eta.
// The ray enters slab 0 at t_a = (lo_0 - o_0)/d_0 and leaves slab 1 at t_b = (hi_1 -
// o_1)/d_1; t_b is the largest value of its kind below t_a (t_a - t_b = 0.033u|t|, u =
// 2^-53, t ~ 0.913): a miss by a hair. Each computed value is fl(fl(p - o)·fl(1/d)),
// three roundings; here they fall apart: for t_a by -0.28, -0.71 and -0.26 times u|x|
// (1/d_0 just above a power of two, where a rounding can reach u|x|), -1.25u|t| in all;
// for t_b by +0.55, +1.00 and +0.52, +2.07u|t| in all. So t_b~ - t_a~ = 3.28u|t|: the
// entry's upper bound t_a~ + gamma(1)|t_a~| lies below the exit's lower bound t_b~ -
// gamma(1)|t_b~|, and the mutant proves a hit (its verdict and its full query). The
// kernel's bounds (12u|t| apart at least) prove nothing; the general path finds the
// miss.
// Found by a search over values near powers of two for slab 0, then the exit of slab 1
// put on the double just below t_a for random d_1 until its own roundings fell upward;
// checked here by the oracle.
TEST(BoundWitnessDouble, AabbLanesBoundGamma1) {
    const Aabb<double> box{Vec3<double>(0x1.000002c60e85p-8, -0x1p20, -0x1p20), Vec3<double>(0x1p20, 0x1.5391242b36c1p+1, 0x1p20)};
    const Ray<double> ray{Vec3<double>(-0x1.cc1a981f3f933p-2, -0x1.000fb23deca03p+0, 0),
                          Vec3<double>(0x1.fc2cacaebc866p-2, 0x1.ffffffffff7f7p+1, 1)};
    // The two computed values as the lanes compute them, and the shrunk bounds apart.
    const double ta = mul(box.lo[0] - ray.origin[0], 1 / ray.direction[0]);
    const double tb = mul(box.hi[1] - ray.origin[1], 1 / ray.direction[1]);
    EXPECT_GT(tb - ta, 3 * u * std::abs(ta));
    EXPECT_LT(ta + detail::gamma<double>(1) * std::abs(ta), tb - detail::gamma<double>(1) * std::abs(tb));
    using BD = detail::BigDyadic;  // exactly, t_a > t_b: (lo_0 - o_0)·d_1 > (hi_1 - o_1)·d_0 (d > 0)
    EXPECT_EQ(((BD(box.lo[0]) - BD(ray.origin[0])) * BD(ray.direction[1]) -
               (BD(box.hi[1]) - BD(ray.origin[1])) * BD(ray.direction[0])).sign(), 1);
    EXPECT_EQ(oracle::exact(ray, box).verdict, Verdict::miss);
    EXPECT_EQ(intersect(ray, box, certified).verdict, Verdict::miss) << repro(ray, box);
    expect_contract(ray, box);
}

// sphere-verdict-margin-gamma1: the certified Sphere verdict filter
// (sphere_verdict_common in detail/ray_sphere_verdict.hpp), whose certificate of the
// line's distance l against r, D~ = fl(S~ - R~) with S = |Δ × d|² and R = r²|d|², has the
// margin E = 2·gamma(13)·ΣM~_j² + 2·gamma(7)·R~ (+ underflow terms), which the mutant
// shrinks to 2·gamma(1)·(ΣM~_j² + R~).
// The ray passes 0.46u·S/(2|d|²r) inside the ball's boundary (exactly, S - R = -0.46u·S,
// u = 2^-53): a hit. Computed, the three components of w = Δ × d (the products fl(Δ~_k
// d_m) of opposite signs, so M ~ |w|) are off by 0.58, 1.64 and 0.15 times u|w_j|, each
// the same way as the others' share of S, and the squares and sums add theirs: S~ is
// 4.05u·S too large; R~ = fl(fl(r·r)·fl(|d|²)) is 1.01u·R too small. So D~ = +4.59u·S:
// the line looks outside. ΣM~² = 1.07·S, so the mutant's margin is 4.14u·S and it
// answers miss; the kernel's is 41.9u·S and its verdict goes on to the full query: hit.
// Found by a search over random lines with directions near powers of two, the radius
// put on the doubles next to the exact distance; checked here by the oracle.
TEST(BoundWitnessDouble, SphereVerdictMarginGamma1) {
    const Sphere<double> sphere{Vec3<double>(0x1.bb2cdadcc390bp+0, -0x1.4a3e59fc2a55p-1, -0x1.ff156876cf92ep+2),
                                0x1.d32785f945fp+3};
    const Ray<double> ray{Vec3<double>(0x1.bb0ef1dbcf1e6p+1, 0x1.6e127c03963fdp-1, 0x1.efb4a3f0c8c0dp+2),
                          Vec3<double>(0x1.fff9d83e91951p+0, -0x1.0000000189d98p+0, -0x1.21717a548ff43p+0)};
    // The certificate as the filter computes it, against the shrunk margin.
    double delta[3], d[3];
    for (int j = 0; j < 3; ++j) delta[j] = ray.origin[j] - sphere.center[j], d[j] = ray.direction[j];
    const double a = (mul(d[0], d[0]) + mul(d[1], d[1])) + mul(d[2], d[2]);
    double S = 0, MM = 0;
    for (int j = 0; j < 3; ++j) {
        const int k = (j + 1) % 3, m = (j + 2) % 3;
        const double A = mul(delta[k], d[m]), B = mul(delta[m], d[k]), w = A - B, M = std::abs(A) + std::abs(B);
        S += mul(w, w);
        MM += mul(M, M);
    }
    const double R = mul(mul(sphere.radius, sphere.radius), a), D = S - R;
    EXPECT_GT(D, 2 * detail::gamma<double>(1) * (MM + R));
    EXPECT_LT(D, 2 * detail::gamma<double>(13) * MM + 2 * detail::gamma<double>(7) * R);
    // Exactly, the line passes inside: |Δ × d|² < r²|d|².
    using BD = detail::BigDyadic;
    BD Sx(0.0), ax(0.0);
    for (int j = 0; j < 3; ++j) {
        const int k = (j + 1) % 3, m = (j + 2) % 3;
        const BD w = (BD(ray.origin[k]) - BD(sphere.center[k])) * BD(d[m]) - (BD(ray.origin[m]) - BD(sphere.center[m])) * BD(d[k]);
        Sx = Sx + w * w;
        ax = ax + BD(d[j]) * BD(d[j]);
    }
    EXPECT_EQ((Sx - BD(sphere.radius) * BD(sphere.radius) * ax).sign(), -1);
    EXPECT_EQ(oracle::exact(ray, sphere).verdict, Verdict::hit);
    EXPECT_EQ(verdict(ray, sphere, certified), Verdict::hit) << repro(ray, sphere);
    expect_contract(ray, sphere);
}

// The input of the two witnesses below: the ray starts at t_min just outside the ball.
std::pair<Sphere<double>, Ray<double>> sphere_end_witness() {
    const Sphere<double> sphere{Vec3<double>(-0x1.94bf2ca0fa1a5p+2, 0x1.85dbc5409e165p+3, -0x1.bf2c2d48c403dp+0),
                                0x1.376b15c63de69p+4};
    Ray<double> ray{Vec3<double>(-0x1.042cb13203524p+1, -0x1.86fb9804a9628p+2, -0x1.ec93883ff221ap-1),
                    Vec3<double>(0x1.8931d1df7650ep+0, -0x1.001716e4e7a67p+0, -0x1.000000077d384p+0)};
    ray.t_min = 0x1.00024cee578f9p-1;
    return {sphere, ray};
}

// sphere-verdict-bounds-gamma1: the certified Sphere verdict filter
// (sphere_verdict_common), whose bound of q(t) = |Δ + t d|² - r² at the range's ends,
// gamma(9)·(ΣM_j² + r²) doubled, the mutant shrinks to 2·gamma(1)·(ΣM_j² + r²).
// At t_min = 0x1.00024cee578f9p-1 the point lies just outside the ball, q(t_min) =
// +0.30u·r² exactly (u = 2^-53), and moves away from it (the slope d·w > 0): a miss. The
// dominant component, w_1 = Δ~_1 + fl(t_min·d_1) ~ -18.8 (r ~ 19.5), comes out 1.66u|w_1|
// too small in magnitude (Δ~_1 = fl(o_1 - c_1) by 0.87u, the sum by nearly u, the
// product by 0.33u), and the squares and sums add their share: v~ = fl(Σ w~_j² - r²) =
// -4.19u·r², which the mutant's bound 4.01u·r² (ΣM~² + r² = 2.0·r²) takes as inside: a
// hit. The kernel's bound, 36.1u·r², decides nothing there; the full query finds the miss.
// Found by a search over random rays with directions near powers of two, the radius put
// on the doubles next to |w|; checked here by the oracle.
TEST(BoundWitnessDouble, SphereVerdictBoundsGamma1) {
    auto [sphere, ray] = sphere_end_witness();
    // q(t_min) as the filter computes it, against the shrunk bound.
    const FilteredQ f = filtered_q(sphere, ray, ray.t_min);
    EXPECT_LT(f.q, -2 * detail::gamma<double>(1) * f.bound_sum);
    EXPECT_GT(f.q, -2 * detail::gamma<double>(9) * f.bound_sum);
    // Exactly, the point at t_min lies outside (q > 0) and leaves (slope > 0).
    using BD = detail::BigDyadic;
    BD q = -BD(sphere.radius) * BD(sphere.radius), slope(0.0);
    for (int j = 0; j < 3; ++j) {
        const BD w = BD(ray.origin[j]) - BD(sphere.center[j]) + BD(ray.t_min) * BD(ray.direction[j]);
        q = q + w * w;
        slope = slope + BD(ray.direction[j]) * w;
    }
    EXPECT_EQ(q.sign(), 1);
    EXPECT_EQ(slope.sign(), 1);
    EXPECT_EQ(oracle::exact(ray, sphere).verdict, Verdict::miss);
    EXPECT_EQ(verdict(ray, sphere, certified), Verdict::miss) << repro(ray, sphere);
    expect_contract(ray, sphere);
}

// sphere-cheap-signs-gamma1: the certified Sphere straight-line path's cheap signs of q
// at the range's ends (sphere_cheap_signs in detail/ray_sphere_straight_line.hpp: the
// same evaluation and bound as the verdict filter's, above), shrunk to 2·gamma(1). The
// range of the previous witness cut to the single point t_min = t_max: q there is
// +0.30u·r² exactly (a miss), computed -4.19u·r² against the mutant's 4.01u·r², so the
// mutant takes both ends as inside and answers the hit [t_min, t_max]. The line itself
// passes through the ball, so the path gets that far; the kernel's bound (36.1u·r²)
// decides nothing and the general path finds the miss.
TEST(BoundWitnessDouble, SphereCheapSignsGamma1) {
    auto [sphere, ray] = sphere_end_witness();
    ray.t_max = ray.t_min;
    const double delta[3] = {ray.origin[0] - sphere.center[0], ray.origin[1] - sphere.center[1],
                             ray.origin[2] - sphere.center[2]};
    const double d[3] = {ray.direction[0], ray.direction[1], ray.direction[2]};
    // The kernel's cheap sign is undecided there; the shrunk bound's would be "inside".
    EXPECT_EQ(detail::sphere_cheap_signs(delta, d, double(sphere.radius), ray.t_min).q, 2);
    const FilteredQ f = filtered_q(sphere, ray, ray.t_min);
    EXPECT_LT(f.q, -2 * detail::gamma<double>(1) * f.bound_sum);
    EXPECT_EQ(oracle::exact(ray, sphere).verdict, Verdict::miss);
    EXPECT_EQ(intersect(ray, sphere, certified).verdict, Verdict::miss) << repro(ray, sphere);
    expect_contract(ray, sphere);
}

// sphere-residual-gamma1: the certified Sphere's double-word residual q(t) = |Δ + t d|² - r²
// (detail::SphereResidual, detail/ray_sphere_residual.hpp), whose bound
// (1 + 20u)(gamma(7)·Σ|τ| + ΣF_j + u|v|) the mutant shrinks to gamma(1)·Σ|τ| (and F_j's
// gamma(2) to gamma(1)).
// The centre is 0, Δ = (x, y, z) and d = (0, 0, d_2): x² + y² - r² = -h² exactly for a
// double h ~ 2^-25, and t·d_2 = P + p (two_prod) was chosen (its low part by a modular
// inverse) so that w_2 = z + P + p = h + p with p ~ 2^-79 ~ -(the rest of x² + y² - r²)/(2h):
// q(t) = +1.2e-47 exactly, 6e-17 times the mutant's bound. Computed (ω_0 = ω_1 = 0,
// ω_2 = p exactly): small = -ρ + a_0 (exact) + a_1, the low parts of r², x², y², lands
// on a tie at ~2^-49 (ulp 2^-101) and rounds to even, 2^-102 down; the third
// coordinate's terms a_2 + fl(2 W_2 ω_2) + fl(ω_2²) sum to exactly 2^-102, and adding
// them is a tie again that rounds to even, 2^-102 lost; the rest is exact. So
// v = σ + small = -2^-101 where q ~ 0: |q - v| = 1.94·u·Σ|τ| (Σ|τ| ~ 1.03·2^-49; F_j ~
// 2^-157). The mutant's bound, 1.03·2^-102, takes q < 0; the kernel's (7.2·2^-102)
// decides nothing.
// Found by a search over such constructed rays; checked here in exact arithmetic.
TEST(BoundWitnessDouble, SphereResidualGamma1) {
    const std::array<double, 3> o{0x1.812043c306d6ep+1, 0x1.20d707bec13e5p+1, 0x1.0e76aa2c1c96p-30};
    const std::array<double, 3> d{0, 0, 0x1.fd8af422efe14p-25}, c{0, 0, 0};
    const double r = 0x1.e167a141e8132p+1, t = 0x1.608965750d22fp-1;
    // Exactly, q(t) > 0 (by less than 2^-150).
    using BD = detail::BigDyadic;
    BD q = -BD(r) * BD(r);
    for (int j = 0; j < 3; ++j) {
        const BD w = BD(o[j]) - BD(c[j]) + BD(t) * BD(d[j]);
        q = q + w * w;
    }
    EXPECT_EQ(q.sign(), 1);
    // The residual's terms as value_at sums them: Σ|τ| and ΣF_j with gamma(1), the mutant's.
    const detail::Pair r2 = detail::two_prod(r, r);
    double A[3], abs_small = std::abs(r2.lo), F = 0;
    const double g1 = detail::gamma<double>(1);
    for (int j = 0; j < 3; ++j) {
        const detail::Pair oc = detail::two_sum(o[j], -c[j]), p = detail::two_prod(t, d[j]);
        const detail::Pair x = detail::two_sum(oc.hi, p.hi);
        const double om = (x.lo + oc.lo) + p.lo;
        const double beta = g1 * (std::abs(x.lo) + std::abs(oc.lo) + std::abs(p.lo)) + 0x1p-1070;
        F += beta * (2 * std::abs(x.hi) + 2 * std::abs(om) + beta);
        const detail::Pair sq = detail::two_prod(x.hi, x.hi);
        A[j] = sq.hi;
        abs_small += (std::abs(sq.lo) + std::abs(mul(2 * x.hi, om))) + mul(om, om);
    }
    const detail::Pair s1 = detail::two_sum(A[0], A[1]), s2 = detail::two_sum(s1.hi, A[2]),
                       s3 = detail::two_sum(s2.hi, -r2.hi);
    abs_small += (std::abs(s1.lo) + std::abs(s2.lo)) + std::abs(s3.lo);
    const detail::SphereResidual residual(o, d, c, r);
    const detail::SphereResidual::Value val = residual.value_at(t);
    EXPECT_EQ(val.v, -0x1p-101);
    const double shrunk = (1 + 20 * u) * ((g1 * abs_small + F) + u * std::abs(val.v)) + 0x1p-1000;
    EXPECT_GT(std::abs(val.v), shrunk);  // the shrunk bound would decide q < 0
    EXPECT_GE(val.err, std::abs(val.v));  // the kernel's holds (q ~ 0): no sign
    EXPECT_EQ(residual.sign_at(t), 2) << "v " << val.v << " err " << val.err;
    const Sphere<double> sphere{Vec3<double>(c[0], c[1], c[2]), r};
    const Ray<double> ray{Vec3<double>(o[0], o[1], o[2]), Vec3<double>(d[0], d[1], d[2])};
    expect_contract(ray, sphere);
}
