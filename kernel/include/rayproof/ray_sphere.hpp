// rayproof/ray_sphere.hpp — ray against sphere.
//
// Shape:     the closed ball { p : |p - c| <= r } (radius 0 is the single point c).
// Query:     with Δ = o - c, the squared distance q(t) = |Δ + t d|² - r² = a t² + 2 b t + c'
//            (a = d·d, b = d·Δ, c' = Δ·Δ - r²) is <= 0 exactly on [t0, t1], the roots
//            t0,1 = (-b ∓ sqrt(b² - a c'))/a; the answer is [t0, t1] ∩ [t_min, t_max].
//            face is always -1.
// Algorithm: the numerically careful quadratic (pbrt-v4, section 6.8.2; Haines et al.,
//            "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems, ch. 7):
//            the discriminant as b² - a c' = a·(r² - |Δ - (b/a) d|²) = a·(r - l)(r + l) with
//            l = |Δ - (b/a) d| the distance from c to the line, which avoids the
//            cancellation of b² - a c' for far or small spheres; the near root as
//            q/a and the far one as c'/q with q = -(b + sign(b)·sqrt(disc)), so neither
//            root subtracts nearly equal numbers.
// Degenerate cases: tangent rays (disc == 0, t0 == t1), radius 0, origin inside or on the
//            sphere, the sphere behind the origin, b == 0 with a tangent at t = 0.
// Modes:     fast — l carries a relative error of a few gamma(n) of |Δ|, so for a ray
//            passing at distance ~r from the centre, the verdict is uncertain within
//            about gamma(8)·|Δ| of tangency; measured, not promised.
//            conservative — in the pbrt-v4 manner first (sphere_conservative_common):
//            the closest approach t* = -b/a and the discriminant D = r²a - |Δ × d|² in
//            one plain evaluation in double, each widened by a bound derived for it (at
//            the code); the chord [t* - w, t* + w], w = sqrt(D)/a, from the widened
//            values. Outside its range (|d|² beyond [2^-400, 2^1000], a radius below
//            2^-300 or an overflow, double input only): the same formulas as fast
//            mode in interval arithmetic with outward rounding (in double for both
//            scalar types): the discriminant as
//            a·(r - l)(r + l), l = |Δ - (b/a) d|, and the roots from q = -(b + sign(b)·√disc)
//            when the sign of b is certain (the naive (-b ∓ √disc)/a otherwise). A
//            discriminant interval reaching 0 counts as a hit: never a false miss.
//            certified — decisions on exact signs, each tried first on intervals:
//            q(t) = a t² + 2 b t + c' is convex with its vertex at t* = -b/a, so on
//            [t_min, t_max] its minimum is at t_min when a·t_min + b >= 0, at t_max when
//            a·t_max + b <= 0, and at t* otherwise, where its sign is that of -(b² - a c').
//            hit iff that minimum is <= 0. t_enter is t_min when q(t_min) <= 0, else the
//            smaller root t0, found as the least float g with a·g + b >= 0 or q(g) <= 0
//            (a predicate that is false below t0 and true from t0 on): t0 lies in
//            (pred g, g], so g is t0 faithfully rounded (and t0 itself when q(g) == 0).
//            t_exit likewise from above. The search starts at the interval root and
//            gallops then bisects over the ordered floats (at most ~2·64 predicate
//            evaluations, usually 2). Exact signs: q(g) is degree 4, b² - a c' degree 4,
//            a·g + b degree 3 (detail/exact.hpp). For double, a q(g) the interval cannot
//            sign (near a root its enclosure holds 0) is tried next in double-word
//            arithmetic with a proven bound (SphereResidual), then exactly.
//            The common case runs as straight-line code first (sphere_certified_common):
//            the roots estimated in double as the fast mode does, each refined by one
//            Newton step on a double-word q(x) and proven by the signs of q at the
//            candidate float and a neighbour (from the exact expansion q(x + δ) =
//            q(x) + δ(a(2x + δ) + 2b)), both roots side by side in two lanes; a miss
//            proven by a bound on the line's distance
//            from the centre, or by q > 0 with the slope pointing away at an end of the
//            range. It answers for input magnitudes in [2^-300, 2^300] (or 0) and gives
//            the general path's answer bit for bit; everything it cannot prove goes to
//            the general path (sphere_certified). For float input a path without
//            double-word arithmetic runs first (sphere_certified_float): products of
//            floats are exact in double, so one plain double evaluation of q with its
//            gamma(9) bound decides the signs at the float candidates and their
//            neighbours, the candidates being the double root estimates rounded to float
//            (no Newton step), and the miss comes from the verdict filter's line
//            certificate (no division or square root); what it cannot prove goes to the
//            double-word path above. An exact tangent (b² - a c' exactly 0) is answered
//            before the double-word path (float) or the general path (double) from the
//            exact vertex, both decided in fixed-size sums (sphere_tangent_shortcut),
//            where the line's certificate leaves the tangency open; the discriminant's
//            sign it decided otherwise goes on to the general path. The verdict alone
//            (verdict() in intersect.hpp) comes from a filter of its own, signs only,
//            with no square root, division or root and no range restriction
//            (sphere_verdict_common), else from the full query.
// Stages:    each in a header of its own under detail/: ray_sphere_quadratic.hpp (q's
//            enclosures and exact signs), ray_sphere_residual.hpp (q in double-word
//            arithmetic with a proven bound), ray_sphere_general.hpp (the certified general
//            path), ray_sphere_straight_line.hpp (the certified straight-line path),
//            ray_sphere_verdict.hpp (the certified verdict filter) and
//            ray_sphere_fixed_exact.hpp (the exact discriminant's sign and vertex in
//            fixed-size sums, which answer an exact tangent before the other paths:
//            sphere_tangent_shortcut). This header holds the modes; the certified one
//            and the conservative one's fallback both call sphere_certified_answer.
#pragma once

#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/eft.hpp>
#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/detail/prepared.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/detail/ray_sphere_fixed_exact.hpp>
#include <rayproof/detail/ray_sphere_general.hpp>
#include <rayproof/detail/ray_sphere_quadratic.hpp>
#include <rayproof/detail/ray_sphere_straight_line.hpp>
#include <rayproof/detail/ray_sphere_verdict.hpp>
#include <rayproof/detail/validate.hpp>
#include <rayproof/prepared_ray.hpp>
#include <rayproof/types.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <type_traits>
#include <utility>

namespace rayproof::detail {

template <class T> using PreparedSphere = Prepared<Sphere<T>>;  // detail/prepared.hpp

// Fast mode in full: the validity rules checked one by one, then the careful quadratic.
// What sphere_fast_common declines, out of line.
template <class T> [[gnu::noinline, gnu::cold]] Hit<T> sphere_fast_general(const Ray<T>& r, const Sphere<T>& s) {
    if (!valid(s) || !valid(r)) return invalid_hit<T>();
    const Vec3<T>& d = r.direction;
    const Vec3<T> delta = r.origin - s.center;
    const T rad = s.radius;
    const T a = d.squaredNorm();
    const T b = d.dot(delta);
    const T l = (delta - (b / a) * d).norm();
    Hit<T> h;
    const T disc = a * ((rad - l) * (rad + l));
    if (!(disc >= 0)) return h;
    const T q = -(b + std::copysign(std::sqrt(disc), b));
    T t0, t1;
    if (q == 0) {  // b == 0 and disc == 0: tangent at t = -b/a = 0
        t0 = t1 = T(0);
    } else {
        const T c = delta.squaredNorm() - rad * rad;
        t0 = q / a;
        t1 = c / q;
        if (t1 < t0) std::swap(t0, t1);
    }
    // Squares that overflow or underflow T (|d|² beyond the range, say) leave NaN here:
    // fast mode answers miss then (it promises nothing; the other modes are exact there).
    if (std::isnan(t0) || std::isnan(t1) || t0 > r.t_max || t1 < r.t_min) return h;
    h.verdict = Verdict::hit;
    h.t_enter = std::max(t0, r.t_min);
    h.t_exit = std::min(t1, r.t_max);
    return h;
}

// Fast mode's common case: the same careful quadratic with no division before the
// verdict. The discriminant as b² - a c' = a r² - |Δ × d|² (Lagrange's identity:
// |Δ × d|² = |Δ|²|d|² - (Δ·d)² = a·l², l the distance from the centre to the line), so a
// miss (a r² < |Δ × d|²) costs neither a division nor a square root, and the cross
// product keeps l's absolute error near u·|Δ| (each component's error is a few u·|Δ||d|),
// as the foot vector Δ - (b/a) d does, without the cancellation of |Δ|² a - b². The roots
// as q/a and c'/q, q = -(b + sign(b)·sqrt(disc)), as in sphere_fast_general.
// The validity rules are folded into one probe: s = (disc + c') + b is finite only when
// the origin, the centre, the direction and the radius are finite (an infinite or NaN
// Δ_i makes the term d_i·Δ_i of b NaN or infinite; an infinite or NaN d_i makes a, hence
// r²·a, infinite or NaN, and disc with it; so does a NaN or infinite radius) and when
// none of a, b, |Δ × d|², r²·a, c' overflows; a zero direction (or a = 0 by underflow),
// a negative radius and the range rules are comparisons. Everything the probe rejects
// goes to sphere_fast_general, which answers it by the contract's rules.
template <class T> RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> sphere_fast_common(const Ray<T>& r, const Sphere<T>& s) {
    const Vec3<T>& d = r.direction;
    const Vec3<T> delta = r.origin - s.center;
    const T rad = s.radius;
    const T a = d.squaredNorm(), b = d.dot(delta);
    const T cx = delta[1] * d[2] - delta[2] * d[1], cy = delta[2] * d[0] - delta[0] * d[2],
            cz = delta[0] * d[1] - delta[1] * d[0];
    const T k2 = (cx * cx + cy * cy) + cz * cz;  // |Δ × d|²
    const T r2 = rad * rad, c = delta.squaredNorm() - r2;
    const T disc = r2 * a - k2;
    const T probe = (disc + c) + b;
    if (!(int(probe - probe == 0) & int(a > 0) & int(rad >= 0) & int(valid_range(r)))) [[unlikely]]
        return std::nullopt;
    Hit<T> h;
    if (!(disc >= 0)) return h;  // as the textbook code: no root, no square root
    // q == 0 only when b == 0 and disc == 0: a tangent at t = -b/a = 0 (c' is 0 then).
    const T q = -(b + std::copysign(std::sqrt(disc), b));
    const T t_q = q / a, t_c = q != 0 ? c / q : T(0);
    const T t0 = std::min(t_q, t_c), t1 = std::max(t_q, t_c);
    const T t_enter = std::max(t0, r.t_min), t_exit = std::min(t1, r.t_max);
    const bool hit = t_enter <= t_exit;  // t0 <= t_max and t1 >= t_min on a valid range
    h.verdict = Verdict(int(hit));
    h.t_enter = hit ? t_enter : T(0);
    h.t_exit = hit ? t_exit : T(0);
    return h;
}

template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Hit<T> query(const R& ray, const PreparedSphere<T>& p, fast_t) {
    if constexpr (is_prepared_ray_v<R>)
        if (!p.ok || !valid(ray)) return invalid_hit<T>();
    const Ray<T>& r = ray_of(ray);
    return common_or_fallback(sphere_fast_common(r, p.shape), [&, &s = p.shape] { return sphere_fast_general(r, s); });
}

// An exact tangent, answered from the vertex before the paths that would find it only
// after their own set-up (for float input before the double-word straight-line path,
// for double before the general path): where the fixed-size sums take the input, as
// given or rescaled (SphereFixedExact, SphereValues), and the line's certificate on that
// input (sphere_line_certificate, valid there: a >= 2^-298) leaves l = r open, the exact
// discriminant's sign and the vertex in fixed-size sums, and on a tangent line the
// general path's own tangent answer (sphere_tangent_answer). Otherwise no answer, with
// the discriminant's sign where it was decided (the general path then takes it).
// Valid input only.
template <class T> struct SphereTangentTry {
    std::optional<Hit<T>> answer;
    int disc_sign = 2;  // sign(b² - a c') where decided, else 2
};
template <class T> SphereTangentTry<T> sphere_tangent_shortcut(const Ray<T>& r, const Sphere<T>& s) {
    const std::optional<SphereFixedInput> e = sphere_fixed_input(r, s, [&] { return sphere_rescaled_values(r, s); });
    if (!e) return {};
    const SphereValues& v = e->values;
    const double delta[3] = {v.o[0] - v.c[0], v.o[1] - v.c[1], v.o[2] - v.c[2]};
    const double a = v.d[0] * v.d[0] + v.d[1] * v.d[1] + v.d[2] * v.d[2];
    const SphereLineCertificate lc = sphere_line_certificate(v.d, delta, v.r * v.r, a);
    if (std::abs(lc.D) > lc.E) return {};  // l != r proven: not a tangent
    const std::optional<int> sd = e->sign_discriminant();
    if (!sd) return {};
    if (*sd != 0) return {std::nullopt, *sd};
    const std::optional<std::pair<double, int>> vx = e->vertex();
    if (!vx) return {std::nullopt, 0};
    const std::optional<Hit<T>> h = sphere_tangent_answer(r, typename SphereQuadratic<T>::Vertex{vx->first, vx->second});
    if (h) {  // counted as a query that went to exact arithmetic
        [[maybe_unused]] const bool went_exact = true;
        RAYPROOF_COUNT_QUERY();
        RAYPROOF_COUNT_FLUSH(went_exact);
    }
    return {h, 0};
}

// The certified answer, shared by the certified mode and by the conservative mode's
// fallback: the straight-line path when it answers, else the general path. The
// straight-line paths answer only for valid input (each vouches for it from its own
// numbers: sphere_certified_float, sphere_certified_common), so the input is validated
// in full only where they decline, before the general path.
// For float, the float straight-line path first (no double-word arithmetic); what it
// declines, out of line, goes to the double-word straight-line path and the general path.
template <class T> [[gnu::noinline, gnu::cold]] Hit<T> sphere_certified_checked_general(const Ray<T>& r,
                                                                                        const Sphere<T>& s) {
    return answer_if_valid(r, s, [&] {
        const SphereTangentTry<T> tangent = sphere_tangent_shortcut(r, s);
        if (tangent.answer) return *tangent.answer;
        return sphere_certified_general(r, s, tangent.disc_sign);
    });
}
template <class T> [[gnu::noinline]] Hit<T> sphere_certified_declined(const Ray<T>& r, const Sphere<T>& s) {
    return answer_if_valid(r, s, [&] {
        const SphereTangentTry<T> tangent = sphere_tangent_shortcut(r, s);
        if (tangent.answer) return *tangent.answer;
        return common_or_general(sphere_certified_common(r, s),
                                 [&] { return sphere_certified_general(r, s, tangent.disc_sign); });
    });
}
template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> sphere_certified_answer(const Ray<T>& r, const Sphere<T>& s) {
    if constexpr (std::is_same_v<T, float>)
        return common_or_general(sphere_certified_float(r, s), [&] { return sphere_certified_declined(r, s); });
    else
        return common_or_general(sphere_certified_common(r, s), [&] { return sphere_certified_checked_general(r, s); });
}

// The conservative answer by interval arithmetic per operation: what
// sphere_conservative_common declines (extreme exponents), out of line. The inputs are
// valid.
template <class T> [[gnu::noinline, gnu::cold]] Hit<T> sphere_conservative_general(const Ray<T>& r, const Sphere<T>& s) {
    const SphereQuadratic<T> q(r, s);
    if (!(q.a().lo > 0)) {
        // a = |d|² underflowed (|d| below about 2^-537): the interval formulas divide by
        // an interval holding 0. Rare enough to take the certified answer and widen each
        // faithfully rounded end by one step, which encloses the exact interval.
        Hit<T> h = sphere_certified_answer(r, s);
        if (h.verdict == Verdict::hit) {
            if (h.t_enter != r.t_min) h.t_enter = std::max(step_down(h.t_enter), r.t_min);
            if (h.t_exit != r.t_max) h.t_exit = std::min(step_up(h.t_exit), r.t_max);
        }
        return h;
    }
    Hit<T> h;
    const Interval<double> disc = q.discriminant();
    if (disc.hi < 0) return h;  // certainly no real root (NaN ends never decide a miss)
    const auto [t0, t1] = q.roots(disc);
    const double lo = std::isnan(t0.lo) ? double(r.t_min) : std::max(t0.lo, double(r.t_min));
    const double hi = std::isnan(t1.hi) ? double(r.t_max) : std::min(t1.hi, double(r.t_max));
    if (!(lo <= hi)) return h;
    h.verdict = Verdict::hit;
    h.t_enter = round_down_to<T>(lo);
    h.t_exit = round_up_to<T>(hi);
    return h;
}

// The conservative answer in the pbrt-v4 manner: one plain evaluation in double (for
// both scalar types) of the closest approach t* = -b/a and of D = r²a - |Δ × d|², the
// quadratic's discriminant b² - a(|Δ|² - r²) by Lagrange's identity (|Δ|²a - b² =
// |Δ × d|²), each widened by a bound derived for it. The exact answer is [t* - w, t* + w]
// with w = sqrt(D)/a when D >= 0, else empty, so with
//     |t*~ - t*| <= E1,  D <= D_hi,  W >= sqrt(D_hi)/a,
// D_hi < 0 proves a miss, and [t*~ - (W + E1), t*~ + (W + E1)] encloses the exact
// interval. One square root, of D_hi, and one division, 1/a, side by side: no chain of
// roots. No branch on the geometry (one on the range of the input).
// Bounds (u = 2^-53; Δ~_j = fl(o_j - c_j) = Δ_j(1 + ε), |ε| <= u; products in the
// subnormal range are off by at most 2^-1075 each; a~ in [2^-400, 2^1000] is checked, so
// inv = fl(1/a~) <= 2^400 and every such absolute error, over a, stays below 2^-670):
//   a~ = fl(Σ d_j²): |a~ - a| <= gamma(3)·a, so 1/a <= (1 + 4.01u)·inv and inv <=
//     (1 + 4.02u)/a.
//   b~ = fl(Σ d_j Δ~_j): |b~ - b| <= gamma(4)·Sb, Sb = Σ|d_j Δ_j| <= (1 + 3.1u)·Sb~ (the
//     same sum of the |products|, rounded alike), and |b~| <= Sb~; t*~ = fl(-b~·inv):
//     |t*~ - t*| <= |b~ - b|/a + |b~|·5.1u/a <= 9.3u·Sb~·inv + 2^-670.
//   The upper end fl(t*~ + H), H = fl(W + E1), is at least t*~ + (W + E1)(1 - 2u) -
//     u·|t*~| (the lower end likewise at most t*~ - (W + E1)(1 - 2u) + u·|t*~|), so the
//     ends enclose [t* - w, t* + w] when W·(1 - 2u) >= sqrt(D_hi)/a and E1·(1 - 2u) >=
//     |t*~ - t*| + u·|t*~|, where |t*~| <= (1 + 2u)·Sb~·inv: E1 must cover
//     10.31u·Sb~·inv + 2^-670. E1 = fl(12u·fl(Sb~·inv)) + 2^-600 is at least 12u·(1 -
//     3u)·Sb~·inv + 2^-601 after its own roundings (an underflowed product costs at most
//     2^-1075, far inside 2^-601), and 12u·(1 - 5u) > 10.31u.
//   r²a: ra~ = fl(fl(r·r)·a~). With r = 0 or r >= 2^-300 (checked), r·r >= 2^-600 and
//     ra~ >= 2^-1000 are normal, so ra~ = r²a(1 + θ_5) (a~'s three roundings, two more),
//     and r²a <= (1 + 5.01u)·ra~, ra~ <= (1 + 5.01u)·r²a.
//   |Δ × d|²: c~_k = fl(fl(Δ~_i d_j) - fl(Δ~_j d_i)) is c_k within gamma(3)·P_k + 2^-1073,
//     P_k = |Δ_i d_j| + |Δ_j d_i| <= (1 + 3.01u)·P~_k, P~_k the rounded sum of its two
//     |products|; P = Σ P_k <= (1 + 8u)·P~, P~ = fl(fl(P~_x + P~_y) + P~_z). ρ~ = fl(Σ
//     fl(c~_k²)) is 0 or at least 2^-968 (checked; a ρ~ in between goes to the general
//     path). When ρ~ = 0, |c|² >= 0 = ρ~. Otherwise some |c~_k| >= 2^-486, so P~ >= 2^-487,
//     and every absolute error below (2^-1073 in a c~_k, 2^-1075 in a subnormal square or
//     product) is under 2^-580·P~², inside the u²·P~² term. With |c~_k + c_k| <= 2|c~_k| +
//     3.01u·P_k, Σ|c~_k² - c_k²| = Σ|c~_k - c_k|·|c~_k + c_k| <= 6.02u·Σ P_k|c~_k| +
//     9.1u²·P², and Σ P_k|c~_k| <= (1 + 6.03u)·Q~, Q~ = fl(Σ fl(P~_k·|c~_k|)) (gamma(3),
//     and P_k's 3.01u); |ρ~ - Σ c~_k²| <= gamma(3)·Σ c~_k² <= 3.02u·ρ~. So
//       |ρ~ - |c|²| <= 3.02u·ρ~ + 6.06u·Q~ + 9.4u²·P~².
//     Q~ is what makes the bound follow the chord: at grazing |c~| is about r|d|², so Q~ is
//     about P~·r|d|², where a bound in P~² (P~ up to 2|Δ||d|) would grow with the
//     distance |Δ| of a small sphere.
//   disc = fl(ra~ - ρ~): ra~ - ρ~ <= disc + u|disc| (no underflow in a difference), and
//     u|disc| <= u(1 + u)·max(ra~, ρ~) <= 1.01u·(ra~ + ρ~). Hence
//       D = r²a - |c|² <= disc + 6.02u·ra~ + 4.03u·ρ~ + 6.06u·Q~ + 9.4u²·P~².
//   e_D = fl(8u·S), S = fl(fl(ra~ + ρ~) + fl(Q~ + fl(2^-51·fl(P~·P~)))) (2^-51 = 4u): S
//     is at least (1 - u)^4 of the exact sum of its four terms (P~² >= 2^-974 and 4u·P~²
//     are normal when ρ~ > 0, and that term is needed only then), and 8u·S (a power of
//     two times S) loses at most 2^-1075 to underflow, below 2^-25 of it, as S >=
//     2^-1000 whenever r > 0 or ρ~ > 0 (with both 0, D = -|c|² <= 0 = disc needs no
//     bound), so e_D >= 8u(1 - u)^4(1 - 2^-25)·(ra~ + ρ~ + Q~ + 4u·P~²) >= 7.99u·(ra~ +
//     ρ~ + Q~ + 4u·P~²). D_hi = fl(disc + e_D) loses at most u(|disc| + e_D) <= 1.01u·(ra~
//     + ρ~) + u·e_D to its rounding, so D_hi >= disc + 6.97u·(ra~ + ρ~) + 7.98u·Q~ +
//     31.9u²·P~² >= D. A D_hi that overflows to +inf is still >= D.
//   W = fl(fl(s·ik) + 2^-500), s = fl(sqrt(max(D_hi, 0))), ik = fl(inv·k), k = 1 + 12u
//     (exact; ik is ready before s): sqrt(D) <= s/(1 - u) and 1/a <= (1 + 4.01u)·inv, so
//     sqrt(D)/a <= (1 + 5.02u)·s·inv; and W·(1 - 2u) >= (s·inv·k(1 - u)² - 2^-1075 +
//     2^-500)(1 - u)(1 - 2u) >= (1 + 6.9u)·s·inv + 2^-501 (an underflowed product is off
//     by at most 2^-1075), which covers it.
// Contraction (detail/eft.hpp): the bounds are class C1 (a fused product-sum has one
// rounding fewer than counted, and the |products| summed for Sb~ and P~ are the rounded
// ones, within u of the exact ones' magnitudes, which the factors above allow); the
// products are nonetheless rounded() (class C3), so that the answer has the same bits
// wherever the compiler inlines the query (a batch loop or a single call).
// Range: every finite float input passes (|Δ|, |d|, r <= 2^129, a >= 2^-298, r = 0 or
// r >= 2^-149, ρ~ is 0 or at least 2^-596: Δ~ and d are multiples of 2^-149, so each
// c~_k is a multiple of 2^-298, and nothing overflows: ra~ <= 2^516, P~² <= 2^520). For
// double, a~ outside [2^-400, 2^1000] (|d| tiny or huge), a radius in (0, 2^-300), ρ~ in
// (0, 2^-968) (a tiny cross product) or any of E1, e_D, ρ~ not finite (an overflow) goes
// to sphere_conservative_general, out of line.
// Slack (what a caller spawning rays off the sphere must stay beyond; the render
// tracer's conservative spawn offset, tracer.cpp, derives its margin from these): in
// units of t, with R = r/|d|, λ = |Δ × d|/a (the line's distance from the centre over
// |d|) and M = P~/a, the upper end is at most t* + Et + sqrt(max(Rh² - λ², 0)), with
//     Et = 22.4u·Sb~·inv + 2^-498 (9.3u + E1's 12.01u + the ends' 1.1u, and W's 2^-500),
//     Rh² = (1 + 22.9u)²·(R²(1 + 14.1u) + 14.1u·M·λ + 85u²·M²)
// (D_hi <= (1 + u)(D + 14.06u·r²a + 12.04u·ρ~ + 14.07u·Q~ + 41.5u²·P~²) from the bounds
// above taken the other way, with ρ~ <= (1 + 3.02u)(|c| + 3.04u·P~)² and Q~ <= (1 +
// 3.01u)·P~·(|c| + 3.04u·P~) (Cauchy-Schwarz); so D_hi/a² <= (1 + u)(R²(1 + 14.06u) -
// λ²(1 - 12.05u) + 14.1u·M·λ + 85u²·M²); and W <= (1 + 20.1u)·sqrt(D_hi)/a + 2^-500(1 +
// u), the end's rounding (1 + 2.1u) and the (1 + u) folded in: (1 + k)·sqrt(x - y) <=
// sqrt((1 + k)²x - y) for y <= (1 + k)²(1 - 12.05u)λ²); and λ > Rh implies D_hi < 0, a
// proven miss. Rh grows with λ: a caller bounds it at λ's largest value. The lower end
// likewise at least t* - Et - sqrt(max(Rh² - λ², 0)).
template <class T>
RAYPROOF_ALWAYS_INLINE std::optional<Hit<T>> sphere_conservative_common(const Ray<T>& r, const Sphere<T>& s) {
    constexpr double u = unit_roundoff<double>, c_t = 12 * u, c_d = 8 * u, k = 1 + 12 * u;
    static_assert(0x1p-51 == 4 * u);
    static_assert(k - 1 == 12 * u);
    // Every product that a sum or difference takes goes through rounded(), so that no
    // compiler fuses it: the bounds hold fused or not (class C1), and rounded() makes the
    // answer the same bits wherever the query is inlined (a batch loop or a single call).
    const auto mul = [](double x, double y) RAYPROOF_INLINE_LAMBDA { return rounded(x * y); };
    const double d0 = r.direction[0], d1 = r.direction[1], d2 = r.direction[2], rad = s.radius;
    const double e0 = double(r.origin[0]) - double(s.center[0]), e1 = double(r.origin[1]) - double(s.center[1]),
                 e2 = double(r.origin[2]) - double(s.center[2]);
    const double a = (mul(d0, d0) + mul(d1, d1)) + mul(d2, d2);
    const double b0 = mul(d0, e0), b1 = mul(d1, e1), b2 = mul(d2, e2);
    const double b = (b0 + b1) + b2, sb = (std::abs(b0) + std::abs(b1)) + std::abs(b2);
    const double x0 = mul(e1, d2), x1 = mul(e2, d1), y0 = mul(e2, d0), y1 = mul(e0, d2), z0 = mul(e0, d1), z1 = mul(e1, d0);
    const double cx = x0 - x1, cy = y0 - y1, cz = z0 - z1;
    const double px = std::abs(x0) + std::abs(x1), py = std::abs(y0) + std::abs(y1), pz = std::abs(z0) + std::abs(z1);
    const double pm = (px + py) + pz;
    const double q = (mul(px, std::abs(cx)) + mul(py, std::abs(cy))) + mul(pz, std::abs(cz));
    const double rho = (mul(cx, cx) + mul(cy, cy)) + mul(cz, cz);
    const double ra = mul(mul(rad, rad), a);
    const double disc = ra - rho;
    const double inv = 1 / a, ik = mul(inv, k);
    const double ts = mul(-b, inv);
    const double e_t = mul(c_t, sb * inv) + 0x1p-600, e_d = mul(c_d, (ra + rho) + (q + mul(0x1p-51, mul(pm, pm))));
    const double d_hi = disc + e_d;
    // rho, a sum of squares, is +0, positive or NaN: its bits less one are below those of
    // 2^-968 less one exactly when 0 < rho < 2^-968 (one integer comparison; a NaN passes
    // here and fails the finiteness test below). Likewise r = 0 or r >= 2^-300 (a
    // negative or NaN radius passes here and fails below).
    constexpr std::uint64_t rho_floor = std::bit_cast<std::uint64_t>(0x1p-968) - 1,
                            rad_floor = std::bit_cast<std::uint64_t>(0x1p-300) - 1;
    // The same test vouches for the input (the query checks no validity before it): a~ in
    // [2^-400, 2^1000] means d finite and nonzero; a finite e_t means every Δ~_j = fl(o_j -
    // c_j) finite (a NaN or infinite one makes its |d_j Δ~_j| NaN or infinite, 0·inf
    // being NaN), hence o and c finite (inf - x is infinite, inf - inf NaN); a finite e_d
    // means a finite ra~ (a > 0), hence a finite radius; r >= 0 (false for NaN and -inf)
    // and valid_range do the rest. What it declines is validated in full (query, below).
    const bool ok = int(a >= 0x1p-400) & int(a <= 0x1p1000) & int(std::bit_cast<std::uint64_t>(rho) - 1 >= rho_floor) &
                    int(std::bit_cast<std::uint64_t>(rad) - 1 >= rad_floor) & int(e_t + e_d + rho < inf<double>) &
                    int(s.radius >= 0) & int(valid_range(r));
    if (!ok) [[unlikely]]
        return std::nullopt;
    // pick rather than ternaries: a jump on these comparisons is a coin toss.
    const double w = mul(std::sqrt(pick(d_hi > 0, d_hi, 0.0)), ik) + 0x1p-500;
    const double half = w + e_t;
    const double lo = ts - half, hi = ts + half;
    const OutwardEnds<T> ends = outward_to<T>(lo, hi, r.t_min, r.t_max);
    // The verdict on the enclosure itself (outward_to's meets), never on the rounded ends.
    return hit_when(bool(int(d_hi >= 0) & int(ends.meets)), ends.lo, ends.hi);
}

template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Hit<T> query(const R& ray, const PreparedSphere<T>& p, conservative_t) {
    // A prepared ray's validity is decided already; otherwise the straight-line path
    // vouches for the input where it answers (sphere_conservative_common), so prepare()'s
    // flag goes unread and unevaluated, and what it declines is validated in full.
    if constexpr (is_prepared_ray_v<R>)
        if (!p.ok || !valid(ray)) return invalid_hit<T>();
    const Ray<T>& r = ray_of(ray);
    return common_or_fallback(sphere_conservative_common(r, p.shape), [&, &s = p.shape] {
        return answer_if_valid(r, s, [&] { return sphere_conservative_general(r, s); });
    });
}

template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Hit<T> query(const R& ray, const PreparedSphere<T>& p, certified_t) {
    // A prepared ray's validity is decided already; otherwise the straight-line paths
    // vouch for the input where they answer (sphere_certified_answer), so prepare()'s
    // flag goes unread and unevaluated.
    if constexpr (is_prepared_ray_v<R>)
        if (!p.ok || !valid(ray)) return invalid_hit<T>();
    const Ray<T>& r = ray_of(ray);
    return sphere_certified_answer(r, p.shape);
}

// What the verdict filter declines: the full query's verdict, out of line.
template <class T> [[gnu::noinline, gnu::cold]] Verdict sphere_verdict_declined(const Ray<T>& r, const Sphere<T>& s) {
    return query(r, prepare(s), certified).verdict;
}

// The certified verdict: the filter's (which proves the input valid), else the full
// query's, which validates. The prepared flag is not consulted on the filter's path.
template <class R, class T>
    requires RayOrPrepared<R, T>
RAYPROOF_ALWAYS_INLINE Verdict verdict_query(const R& ray, const PreparedSphere<T>& p, certified_t) {
    const Ray<T>& r = ray_of(ray);
    return verdict_or(sphere_verdict_common(r, p.shape), [&, &s = p.shape] { return sphere_verdict_declined(r, s); });
}

}  // namespace rayproof::detail
