// rayproof/detail/validate.hpp — the contract's validity rules, one function per input type.
//
// Invalid (every mode answers Verdict::invalid): any NaN or infinite number except
// t_min = -inf and t_max = +inf; t_min > t_max; a zero direction; lo > hi on an axis;
// radius < 0; a zero plane normal (also in any plane of a polyhedron); a negative Obb
// half extent; linearly dependent Obb axes (decided exactly: the sign of the
// determinant of the stored floats).
#pragma once

#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/float_util.hpp>
#include <rayproof/types.hpp>

namespace rayproof::detail {

// x - x is +0 for every finite x and NaN for ±inf and NaN, so a sum of such differences
// is 0 exactly when every term is finite: one comparison for many numbers, no branch per
// number (most queries are valid; the checks are joined with & for the same reason).
template <class T> RAYPROOF_ALWAYS_INLINE T finite_probe(const T* v) { return ((v[0] - v[0]) + (v[1] - v[1])) + (v[2] - v[2]); }

// v is not the zero vector (every component +0 or -0).
template <class T> RAYPROOF_ALWAYS_INLINE bool nonzero3(const T* v) { return (v[0] != 0) | (v[1] != 0) | (v[2] != 0); }

// The rules on t_min and t_max alone: t_min <= t_max is false when either is NaN; -inf
// and +inf are the allowed exceptions.
template <class T> RAYPROOF_ALWAYS_INLINE bool valid_range(const Ray<T>& r) {
    return (r.t_min <= r.t_max) & (r.t_min != inf<T>) & (r.t_max != -inf<T>);
}

// valid(r) for a ray whose direction is known to be finite and nonzero.
template <class T> RAYPROOF_ALWAYS_INLINE bool valid_apart_from_direction(const Ray<T>& r) {
    const bool range = valid_range(r);
    return (finite_probe(r.origin.data()) == 0) & range;
}

template <class T> RAYPROOF_ALWAYS_INLINE bool valid(const Ray<T>& r) {
    const T* d = r.direction.data();
    const bool rest = valid_apart_from_direction(r), finite = finite_probe(d) == 0, nonzero = nonzero3(d);
    return rest & finite & nonzero;
}

template <class T> RAYPROOF_ALWAYS_INLINE bool valid(const Aabb<T>& b) {
    const T* lo = b.lo.data();
    const T* hi = b.hi.data();
    return (finite_probe(lo) + finite_probe(hi) == 0) & (lo[0] <= hi[0]) & (lo[1] <= hi[1]) & (lo[2] <= hi[2]);
}

template <class T> RAYPROOF_ALWAYS_INLINE bool valid(const Sphere<T>& s) {
    // radius >= 0 is false for NaN; radius - radius is NaN for +inf.
    return (finite_probe(s.center.data()) + (s.radius - s.radius) == 0) & (s.radius >= 0);
}

template <class T> RAYPROOF_ALWAYS_INLINE bool valid(const Plane<T>& p) {
    const T* n = p.normal.data();
    const bool finite = finite_probe(n) + (p.offset - p.offset) == 0, nonzero = nonzero3(n);
    return finite & nonzero;
}

// Every plane valid (a finite offset, a finite nonzero normal); no planes is valid.
template <class T> bool valid(const ConvexPolyhedron<T>& c) {
    bool ok = true;
    for (const Plane<T>& p : c.planes) ok &= valid(p);
    return ok;
}

// The exact sign of det(axes) decides linear dependence (det3_sign, detail/exact.hpp);
// most boxes are decided by an inline filter first, without a call: det and perm (the
// sum of the monomials' magnitudes) in double in det3_sign's order, with every entry's
// magnitude at most 2^300 (so no product overflows). det3_sign's derivation bounds the
// error by gamma(6)·perm~ while no product underflows; a product in the subnormal range
// is off by at most 2^-1075, and multiplied by an entry (at most 2^300), each of the 12
// rounded products carries at most 2^-774 into det and perm. So |det~ - det| <=
// gamma(6)·perm~·(1 + 2^-50) + 2^-770, and fl(fl(gamma(7)·perm~) + 2^-760) (two
// roundings of a value at least gamma(7)(1 - u)^2·perm~ + 2^-760(1 - u)) exceeds it:
// |det~| above that proves det != 0. Otherwise det3_sign decides, out of line. The
// answer is the exact one either way.
// Contraction: class C1 (a fused evaluation has fewer roundings).
template <class T> RAYPROOF_ALWAYS_INLINE bool obb_axes_independent(const Eigen::Matrix<T, 3, 3>& m) {
    const double a = m(0, 0), b = m(0, 1), c = m(0, 2);
    const double d = m(1, 0), e = m(1, 1), f = m(1, 2);
    const double g = m(2, 0), h = m(2, 1), i = m(2, 2);
    const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
    const double perm = std::abs(a) * (std::abs(e) * std::abs(i) + std::abs(f) * std::abs(h)) +
                        std::abs(b) * (std::abs(d) * std::abs(i) + std::abs(f) * std::abs(g)) +
                        std::abs(c) * (std::abs(d) * std::abs(h) + std::abs(e) * std::abs(g));
    double amax = 0;
    for (int k = 0; k < 9; ++k) {
        const double x = std::abs(double(m.data()[k]));
        amax = x > amax ? x : amax;
    }
    const double bound = gamma<double>(7) * perm + 0x1p-760;
    if (int(amax <= 0x1p300) & int(std::abs(det) > bound)) [[likely]]
        return true;
    return det3_sign(m) != 0;
}

template <class T> RAYPROOF_ALWAYS_INLINE bool valid(const Obb<T>& b) {
    // Every number finite (one probe, as finite_probe), the half extents >= 0, then the
    // axes independent.
    const T* ax = b.axes.data();
    const T probe = ((finite_probe(b.center.data()) + finite_probe(b.half_extent.data())) +
                     (finite_probe(ax) + finite_probe(ax + 3))) + finite_probe(ax + 6);
    const T* h = b.half_extent.data();
    if (!(int(probe == 0) & int(h[0] >= 0) & int(h[1] >= 0) & int(h[2] >= 0))) return false;
    return obb_axes_independent(b.axes);
}

template <class T> Hit<T> invalid_hit() {
    Hit<T> h;
    h.verdict = Verdict::invalid;
    return h;
}

// What a straight-line path declines after vouching for its input itself: the ray r (a
// Ray or a prepared ray, whose validity is decided already) and the shape s validated in
// full, then answer(), which may take them as valid.
template <class R, class S, class F> RAYPROOF_ALWAYS_INLINE auto answer_if_valid(const R& r, const S& s, F&& answer) {
    using H = decltype(answer());
    bool ray_ok;
    if constexpr (requires { r.valid(); })
        ray_ok = r.valid();
    else
        ray_ok = valid(r);
    if (!valid(s) || !ray_ok) return invalid_hit<decltype(H::t_enter)>();
    return answer();
}

}  // namespace rayproof::detail
