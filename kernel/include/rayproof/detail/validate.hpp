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
// most boxes are decided by an inline filter first, without a call. det3_filter
// evaluates det and perm (the sum of the monomials' magnitudes) in double in det3_sign's
// order. With every entry's magnitude at most 2^300 (so no product overflows),
// det3_sign's derivation bounds the error by gamma(6)·perm~ while no product underflows;
// a product in the subnormal range is off by at most 2^-1075, and multiplied by an entry
// (at most 2^300), each of the 12 rounded products carries at most 2^-774 into det and
// perm. So |det~ - det| <= gamma(6)·perm~·(1 + 2^-50) + 2^-770, and fl(fl(gamma(7)·perm~)
// + 2^-760) (two roundings of a value at least gamma(7)(1 - u)^2·perm~ + 2^-760(1 - u))
// exceeds it: |det~| above that proves det != 0. Float entries are below 2^128, so only
// double input tests the range; a float query pays no loop over the entries.
// Contraction: class C1 (a fused evaluation has fewer roundings).
struct Det3Filter {
    double det, perm;
    bool in_range;  // every |entry| at most 2^300 (always, for float)
};
template <class T> RAYPROOF_ALWAYS_INLINE Det3Filter det3_filter(const Eigen::Matrix<T, 3, 3>& m) {
    const double a = m(0, 0), b = m(0, 1), c = m(0, 2);
    const double d = m(1, 0), e = m(1, 1), f = m(1, 2);
    const double g = m(2, 0), h = m(2, 1), i = m(2, 2);
    const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
    const double perm = std::abs(a) * (std::abs(e) * std::abs(i) + std::abs(f) * std::abs(h)) +
                        std::abs(b) * (std::abs(d) * std::abs(i) + std::abs(f) * std::abs(g)) +
                        std::abs(c) * (std::abs(d) * std::abs(h) + std::abs(e) * std::abs(g));
    if constexpr (std::is_same_v<T, float>) {
        return {det, perm, true};
    } else {
        double amax = 0;
        for (int k = 0; k < 9; ++k) {
            const double x = std::abs(double(m.data()[k]));
            amax = x > amax ? x : amax;
        }
        return {det, perm, amax <= 0x1p300};
    }
}
RAYPROOF_ALWAYS_INLINE bool det3_filter_proves(const Det3Filter& f) {
    return int(f.in_range) & int(std::abs(f.det) > gamma<double>(7) * f.perm + 0x1p-760);
}

// What the inline filter leaves (entries beyond 2^300, or a determinant lost to
// underflow or to rounding): the same filter on the axes scaled by the power of two 2^k
// that brings the largest magnitude amax into [1, 2), then det3_sign. det(2^k·M) =
// 2^(3k)·det(M) has det(M)'s sign. The scaled entries M' = fl(2^k·M) are exact unless
// one falls below 2^-1022, and then within 2^-1073 of 2^k·M's (times_pow2: two
// roundings in the subnormal range at most); det is multilinear with every minor of
// entries at most 2 below 8 in magnitude, so |det(M') - det(2^k·M)| < 9·2^-1073·8·(1 +
// 2^-40) < 2^-1066. The filter's bound on M' (every entry at most 2, so the argument
// above applies with room: each rounded product carries at most 2^-1073 into det and
// perm) covers that too: |det~| > fl(fl(gamma(7)·perm~) + 2^-760) proves det(2^k·M)
// != 0, hence det(M) != 0. The entries are finite here (valid(Obb) tests them first).
template <class T> [[gnu::noinline, gnu::cold]] bool obb_axes_independent_rare(const Eigen::Matrix<T, 3, 3>& m) {
    double amax = 0;
    for (int k = 0; k < 9; ++k) amax = std::max(amax, std::abs(double(m.data()[k])));
    if (amax > 0) {
        const int s = -binary_exponent(amax);  // amax·2^s in [1, 2); |s| <= 1074
        Eigen::Matrix<double, 3, 3> w;
        for (int k = 0; k < 9; ++k) w.data()[k] = times_pow2(double(m.data()[k]), s);
        if (det3_filter_proves(det3_filter(w))) return true;
    }
    return det3_sign(m) != 0;
}

template <class T> RAYPROOF_ALWAYS_INLINE bool obb_axes_independent(const Eigen::Matrix<T, 3, 3>& m) {
    if (det3_filter_proves(det3_filter(m))) [[likely]]
        return true;
    return obb_axes_independent_rare(m);
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
