// rayproof/detail/primitive_bounds.hpp — a box that contains a primitive exactly, for
// the bounding volumes of a BVH.
//
// Question:  enclosing_box(p): an Aabb B with S ⊆ B, S the exact solid of p (the
//            contract's meaning, every input number exact). B need not be tight: an
//            acceleration structure only needs never to cull a primitive the ray meets.
// Answer:    std::nullopt when no finite box is given: planes (unbounded), invalid
//            primitives, and any primitive whose box would overflow to infinity. A BVH
//            keeps those beside its tree and tests them on every ray, still correct.
// Shapes:    Aabb: itself. Sphere: center ± radius, each sum stepped outward once. Obb:
//            center ± Σ_j |minor_kj(A)|·h_j / |det A| (exact numerator and determinant,
//            the quotient enclosed with a derived margin). ConvexPolyhedron of at most
//            kMaxBoxedPlanes planes: boundedness decided exactly, then the box of every
//            three-plane vertex that is not provably outside. Plane: nullopt.
// Rounding:  every computed bound is rounded outward by the derivation at its code; the
//            exact bound lies inside the returned one.
#pragma once

#include <rayproof/detail/entry_order.hpp>
#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/detail/validate.hpp>
#include <rayproof/types.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <span>
#include <utility>
#include <variant>

namespace rayproof::detail {

// The box itself, finite when it is valid.
template <class T> std::optional<Aabb<T>> box_of(const Aabb<T>& b) {
    if (!valid(b)) return std::nullopt;
    return b;
}

// center ± radius per axis. fl(c + r) is the exact c + r rounded to nearest, so the exact
// value lies within half an ulp of it, inside [step_down(fl), step_up(fl)]: one step
// outward from each rounded sum encloses the exact one (a rounded sum that is already
// exact is only enlarged). An overflow gives ±inf, and step_up of the largest finite
// value is +inf: either way a non-finite bound, answered nullopt.
template <class T> std::optional<Aabb<T>> box_of(const Sphere<T>& s) {
    if (!valid(s)) return std::nullopt;
    Aabb<T> b;
    for (int i = 0; i < 3; ++i) {
        b.lo[i] = step_down(T(s.center[i] - s.radius));
        b.hi[i] = step_up(T(s.center[i] + s.radius));
        if (!std::isfinite(b.lo[i]) || !std::isfinite(b.hi[i])) return std::nullopt;
    }
    return b;
}

// The exact quotient n/d (d != 0) of two exact values given by their approximations
// (Approx: relative error below 2^-50, any exponent) enclosed by two doubles [lo, hi], or
// nullopt when the enclosure would overflow.
// Derivation: n = n~(1 + e1), d = d~(1 + e2), |e1|, |e2| < 2^-50, so n/d = (n~/d~)(1 + e)
// with |e| < 2^-50·2/(1 − 2^-50) < 2^-48.9. q~ = ldexp(fl(mant_n/mant_d), exp_n − exp_d)
// adds one rounding of the division (relative u = 2^-53) and, when the result is
// subnormal, at most 2^-1075 absolute from ldexp: |q~ − n/d| < 2^-48.8·|q~| + 2^-1074.
// The margin m = fl(fl(|q~|·2^-40) + 2^-1070) >= 2^-40|q~|(1 − u) + 2^-1070(1 − u) covers
// that with room for the final roundings of q~ ± m (at most u·(|q~| + m) each, and
// subnormal sums are exact): 2^-40(1 − u) − 2^-48.8 − u(1 + 2^-39) > 0 and
// 2^-1070(1 − u) > 2^-1074 + u·2^-1069.
inline std::optional<std::pair<double, double>> enclose_quotient(const Approx& n, const Approx& d) {
    if (n.mant == 0) return std::pair<double, double>{-0x1p-1070, 0x1p-1070};
    const long e = n.exp - d.exp;
    if (e > 1100) return std::nullopt;                   // |n/d| > 2^1099: beyond double
    const double q = e < -1200 ? 0.0 : std::ldexp(n.mant / d.mant, int(e));  // |n/d| < 2^-1199
    const double m = std::abs(q) * 0x1p-40 + 0x1p-1070;
    const double lo = q - m, hi = q + m;
    if (!std::isfinite(lo) || !std::isfinite(hi)) return std::nullopt;
    return std::pair<double, double>{lo, hi};
}

// The T values just outside a double enclosure: the largest T <= lo and the smallest
// T >= hi (T = double: lo and hi themselves; float: the nearest float, stepped once
// outward when the rounding went inward). Non-finite: nullopt.
template <class T> std::optional<std::pair<T, T>> outward(double lo, double hi) {
    T l = narrow<T>(lo), h = narrow<T>(hi);
    if (double(l) > lo) l = step_down(l);
    if (double(h) < hi) h = step_up(h);
    if (!std::isfinite(l) || !std::isfinite(h)) return std::nullopt;
    return std::pair<T, T>{l, h};
}

// An oriented box { p : |a_i·(p − c)| <= h_i } with A = [a_0 a_1 a_2] (columns): with
// y_i = a_i·(p − c), p − c = A^{-T} y, so the solid is c + A^{-T}[−h, h] and its extent
// along axis k is e_k = Σ_j |(A^{-T})_kj|·h_j = Σ_j |minor_kj(A)|·h_j / |det A|
// ((A^{-T})_kj = cofactor_kj(A)/det A, minor_kj = the determinant of A without row k and
// column j). For orthonormal axes |(A^{-T})_kj| = |A_kj|. The numerator (degree 3) and
// det A are exact (detail/exact.hpp), the quotient enclosed by enclose_quotient, and
// c_k ± e_k rounded outward: the exact c_k + e_k <= c_k + hi_e lies below step_up of its
// rounded value (as for the sphere), likewise below.
template <class T> std::optional<Aabb<T>> box_of(const Obb<T>& b) {
    if (!valid(b)) return std::nullopt;  // dependent axes: det A == 0
    const Mat3<T>& A = b.axes;
    const bool safe = expansion_safe(A) && expansion_safe(b.half_extent);
    const auto extents = with_exact(safe, [&](auto tag) -> std::optional<std::array<std::pair<Approx, Approx>, 3>> {
        using E = typename decltype(tag)::type;
        const E det = det3_exact<E>(A);
        std::array<std::pair<Approx, Approx>, 3> out;
        for (int k = 0; k < 3; ++k) {
            const int k0 = k == 0 ? 1 : 0, k1 = k == 2 ? 1 : 2;  // the rows kept
            E num;
            for (int j = 0; j < 3; ++j) {
                const int j0 = j == 0 ? 1 : 0, j1 = j == 2 ? 1 : 2;
                const E minor = E(A(k0, j0)) * E(A(k1, j1)) - E(A(k0, j1)) * E(A(k1, j0));
                num += (minor.sign() < 0 ? -minor : minor) * E(b.half_extent[j]);
            }
            if (any_overflowed(num, det)) return std::nullopt;
            out[std::size_t(k)] = {num.approx(), det.sign() < 0 ? (-det).approx() : det.approx()};
        }
        return out;
    });
    if (!extents) return std::nullopt;
    Aabb<T> box;
    for (int k = 0; k < 3; ++k) {
        const auto e = enclose_quotient((*extents)[std::size_t(k)].first, (*extents)[std::size_t(k)].second);
        if (!e) return std::nullopt;
        const double c = double(b.center[k]);
        const auto r = outward<T>(step_down(c - e->second), step_up(c + e->second));
        if (!r) return std::nullopt;
        box.lo[k] = r->first;
        box.hi[k] = r->second;
    }
    return box;
}

// An enclosure [lo, hi] of the determinant of m (rows of doubles), or nullopt outside the
// filter's range. The evaluation and its bound are det3_sign's filter (detail/exact.hpp,
// derivation there): with every nonzero entry in [2^-300, 2^300], det evaluated as
// a(ei − fh) − b(di − fg) + c(dh − eg) is within fl(gamma(7)·P) of the exact one, P the
// permanent evaluated the same way on |entries|. The ends det ∓ bound are each rounded
// once, so one step outward encloses the exact ends.
inline std::optional<std::pair<double, double>> det3_enclosure(const double (&m)[3][3]) {
    for (const auto& row : m)
        for (const double x : row)
            if (!(x == 0 || (std::abs(x) >= 0x1p-300 && std::abs(x) <= 0x1p300))) return std::nullopt;
    const double a = m[0][0], b = m[0][1], c = m[0][2], d = m[1][0], e = m[1][1], f = m[1][2], g = m[2][0], h = m[2][1],
                 i = m[2][2];
    const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
    const double perm = std::abs(a) * (std::abs(e) * std::abs(i) + std::abs(f) * std::abs(h)) +
                        std::abs(b) * (std::abs(d) * std::abs(i) + std::abs(f) * std::abs(g)) +
                        std::abs(c) * (std::abs(d) * std::abs(h) + std::abs(e) * std::abs(g));
    const double bound = gamma<double>(7) * perm;
    return std::pair<double, double>{step_down(det - bound), step_up(det + bound)};
}

// An enclosure of x/y for x in [xl, xh] and y in [yl, yh] not holding 0: the quotient is
// monotone in each, so its extremes are at the corners; each corner quotient is rounded
// once, so one step outward encloses it. Non-finite: nullopt.
inline std::optional<std::pair<double, double>> divide_enclosures(const std::pair<double, double>& x,
                                                                  const std::pair<double, double>& y) {
    if (!(y.first > 0 || y.second < 0)) return std::nullopt;
    const double q[4] = {x.first / y.first, x.first / y.second, x.second / y.first, x.second / y.second};
    const double lo = step_down(std::min(std::min(q[0], q[1]), std::min(q[2], q[3])));
    const double hi = step_up(std::max(std::max(q[0], q[1]), std::max(q[2], q[3])));
    if (!std::isfinite(lo) || !std::isfinite(hi)) return std::nullopt;
    return std::pair<double, double>{lo, hi};
}

// A convex polyhedron { p : n_k·p <= o_k }. Boxed when it is bounded and has at most
// kMaxBoxedPlanes planes (the work below grows as the fourth power of the count; a larger
// one is kept beside the tree). Nonempty and bounded, it is the convex hull of its
// vertices, each the intersection point of three planes with independent normals that
// satisfies every constraint; so the box of all such points contains it.
//   Bounded: with rank(N) = 3 (some triple has det != 0) the recession cone
//   { d : n_k·d <= 0 for every k } is pointed; it is not {0} exactly when it has an
//   extreme ray, on which two independent normals are active: d = ±(n_i × n_j). So the
//   polyhedron is unbounded (or empty) exactly when rank(N) < 3 or some pair with
//   n_i × n_j != 0 and a sign s has s·det(n_k, n_i, n_j) <= 0 for every k (det3_sign,
//   exact). Either gives nullopt.
//   Vertices: for each triple with det(N_ijk) = D != 0, Cramer's rule gives the point
//   x_c = D_c/D (D_c: column c replaced by the offsets, degree 3, exact), each coordinate
//   enclosed by enclose_quotient. It is dropped when it is outside some plane l: first
//   by a float filter (Cramer's rule on determinant enclosures, det3_enclosure, then
//   outside_filter on the point's enclosure), then the same filter on the exact point's
//   enclosure, then exactly,
//   sign(n_l·(D_0, D_1, D_2) − o_l·D)·sign(D) > 0 (degree 4), so the exact test runs
//   about once per true vertex. No point kept: the polyhedron is empty (nullopt).
inline constexpr std::size_t kMaxBoxedPlanes = 32;

template <class T> std::optional<Aabb<T>> box_of(const ConvexPolyhedron<T>& poly) {
    const std::span<const Plane<T>> P = poly.planes;
    const std::size_t m = P.size();
    if (!valid(poly) || m < 4 || m > kMaxBoxedPlanes) return std::nullopt;  // < 4 half-spaces: unbounded
    auto rows = [&](std::size_t i, std::size_t j, std::size_t k) {
        Mat3<T> M;
        M.row(0) = P[i].normal.transpose();
        M.row(1) = P[j].normal.transpose();
        M.row(2) = P[k].normal.transpose();
        return M;
    };
    bool safe = true;
    for (const Plane<T>& q : P) safe &= expansion_safe(q.normal) && expansion_safe(q.offset);
    // Bounded?
    bool rank3 = false;
    for (std::size_t i = 0; i < m && !rank3; ++i)
        for (std::size_t j = i + 1; j < m && !rank3; ++j)
            for (std::size_t k = j + 1; k < m && !rank3; ++k) rank3 = det3_sign(rows(i, j, k)) != 0;
    if (!rank3) return std::nullopt;
    for (std::size_t i = 0; i < m; ++i)
        for (std::size_t j = i + 1; j < m; ++j) {
            const Vec3<T>&ni = P[i].normal, &nj = P[j].normal;
            const bool parallel = exact_sign(safe, [&](auto tag) {
                                      using E = typename decltype(tag)::type;
                                      const E x = E(ni[1]) * E(nj[2]) - E(ni[2]) * E(nj[1]);
                                      const E y = E(ni[2]) * E(nj[0]) - E(ni[0]) * E(nj[2]);
                                      const E z = E(ni[0]) * E(nj[1]) - E(ni[1]) * E(nj[0]);
                                      return x * x + y * y + z * z;
                                  }) == 0;
            if (parallel) continue;
            bool all_le = true, all_ge = true;  // s = +1: every det <= 0; s = −1: every det >= 0
            for (std::size_t k = 0; k < m && (all_le || all_ge); ++k) {
                const int s = det3_sign(rows(k, i, j));
                all_le &= s <= 0;
                all_ge &= s >= 0;
            }
            if (all_le || all_ge) return std::nullopt;  // a recession direction ±(n_i × n_j)
        }
    // Vertices.
    using Approx3 = std::array<std::pair<Approx, Approx>, 3>;  // (D_c, D) per coordinate
    auto cramer = [&](auto tag, const std::size_t* idx) {        // D_0, D_1, D_2, D exactly
        using E = typename decltype(tag)::type;
        auto det_with = [&](int c) {  // column c replaced by the offsets (c = -1: none)
            auto at = [&](int r, int col) { return col == c ? E(P[idx[r]].offset) : E(P[idx[r]].normal[col]); };
            return at(0, 0) * (at(1, 1) * at(2, 2) - at(1, 2) * at(2, 1)) -
                   at(0, 1) * (at(1, 0) * at(2, 2) - at(1, 2) * at(2, 0)) +
                   at(0, 2) * (at(1, 0) * at(2, 1) - at(1, 1) * at(2, 0));
        };
        return std::array<E, 4>{det_with(0), det_with(1), det_with(2), det_with(-1)};
    };
    // Exactly outside some plane l: sign(n_l·(D_0, D_1, D_2) − o_l·D)·sign(D) > 0.
    auto outside_exactly = [&](const std::size_t* idx) {
        return with_exact(safe, [&](auto tag) -> std::optional<bool> {
            using E = typename decltype(tag)::type;
            const std::array<E, 4> X = cramer(tag, idx);
            if (any_overflowed(X[0], X[1], X[2], X[3])) return std::nullopt;
            for (const Plane<T>& q : P) {
                const E s = E(q.normal[0]) * X[0] + E(q.normal[1]) * X[1] + E(q.normal[2]) * X[2] - E(q.offset) * X[3];
                if (s.overflowed()) return std::nullopt;
                if (s.sign() * X[3].sign() > 0) return true;
            }
            return false;
        });
    };
    // Outside some plane by a float filter on the vertex's enclosure [vlo, vhi]: the least
    // n·v over the enclosure is Σ_j min(n_j·vlo_j, n_j·vhi_j); evaluated with four
    // roundings as S~ = fl(Σ p_j − o) it is within gamma(4)·(Σ|p_j| + |o|) plus 3·2^-1075
    // (products that underflow) of the exact least value minus o; the bound
    // fl(gamma(5)·fl(Σ|p_j| + |o|)) + 2^-1070 covers that with its own roundings (gamma(5)
    // over gamma(4) leaves more than the three roundings of the bound's sum and product).
    // S~ above the bound: every point of the enclosure is outside. Non-finite: undecided.
    auto outside_filter = [&](const double* vlo, const double* vhi) {
        constexpr double g5 = gamma<double>(5);
        for (const Plane<T>& q : P) {
            double sum = 0, mag = 0;
            for (int j = 0; j < 3; ++j) {
                const double n = double(q.normal[j]);
                const double p = std::min(n * vlo[j], n * vhi[j]);
                sum += p;
                mag += std::abs(p);
            }
            const double o = double(q.offset);
            const double S = sum - o, bound = g5 * (mag + std::abs(o)) + 0x1p-1070;
            if (std::isfinite(S) && std::isfinite(bound) && S > bound) return true;
        }
        return false;
    };
    double lo[3] = {inf<double>, inf<double>, inf<double>}, hi[3] = {-inf<double>, -inf<double>, -inf<double>};
    bool any = false;
    for (std::size_t i = 0; i < m; ++i)
        for (std::size_t j = i + 1; j < m; ++j)
            for (std::size_t k = j + 1; k < m; ++k) {
                const std::size_t idx[3] = {i, j, k};
                {  // The float filter first: Cramer's rule on determinant enclosures.
                    double M[3][3];
                    for (int r = 0; r < 3; ++r)
                        for (int c = 0; c < 3; ++c) M[r][c] = double(P[idx[r]].normal[c]);
                    const auto D = det3_enclosure(M);
                    double vlo[3], vhi[3];
                    bool enclosed = D.has_value();
                    for (int c = 0; c < 3 && enclosed; ++c) {
                        double Mc[3][3];
                        for (int r = 0; r < 3; ++r)
                            for (int cc = 0; cc < 3; ++cc) Mc[r][cc] = cc == c ? double(P[idx[r]].offset) : M[r][cc];
                        const auto X = det3_enclosure(Mc);
                        const auto v = X ? divide_enclosures(*X, *D) : std::nullopt;
                        enclosed = v.has_value();
                        if (enclosed) vlo[c] = v->first, vhi[c] = v->second;
                    }
                    if (enclosed && outside_filter(vlo, vhi)) continue;
                }
                const auto point = with_exact(safe, [&](auto tag) -> std::optional<std::optional<Approx3>> {
                    const auto X = cramer(tag, idx);
                    if (any_overflowed(X[0], X[1], X[2], X[3])) return std::nullopt;
                    if (X[3].sign() == 0) return std::optional<Approx3>{};  // dependent normals: no point
                    Approx3 out;
                    for (int c = 0; c < 3; ++c) out[std::size_t(c)] = {X[c].approx(), X[3].approx()};
                    return std::optional<Approx3>{out};
                });
                if (!point) return std::nullopt;  // past the exact types' capacity: not reached
                if (!*point) continue;
                double vlo[3], vhi[3];
                bool finite = true;
                for (int c = 0; c < 3 && finite; ++c) {
                    const auto e = enclose_quotient((**point)[std::size_t(c)].first, (**point)[std::size_t(c)].second);
                    finite = e.has_value();
                    if (finite) vlo[c] = e->first, vhi[c] = e->second;
                }
                if (finite && outside_filter(vlo, vhi)) continue;
                // Not dropped by the filter (a vertex, or nearly one): decided exactly. A point
                // outside is dropped; a vertex beyond the double range leaves no finite box.
                const std::optional<bool> out = outside_exactly(idx);
                if (!out) return std::nullopt;  // past the exact types' capacity: not reached
                if (*out) continue;
                if (!finite) return std::nullopt;
                for (int c = 0; c < 3; ++c) {
                    lo[c] = std::min(lo[c], vlo[c]);
                    hi[c] = std::max(hi[c], vhi[c]);
                }
                any = true;
            }
    if (!any) return std::nullopt;  // bounded with no vertex: empty
    Aabb<T> box;
    for (int c = 0; c < 3; ++c) {
        const auto r = outward<T>(lo[c], hi[c]);
        if (!r) return std::nullopt;
        box.lo[c] = r->first;
        box.hi[c] = r->second;
    }
    return box;
}

// A plane is unbounded.
template <class T> std::optional<Aabb<T>> box_of(const Plane<T>&) { return std::nullopt; }

template <class T> std::optional<Aabb<T>> enclosing_box(const Primitive<T>& p) {
    return std::visit([](const auto& shape) { return box_of(shape); }, p);
}

}  // namespace rayproof::detail
