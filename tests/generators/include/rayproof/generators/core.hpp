// rayproof/generators/core.hpp — the building blocks of the case generators: a seeded
// RNG with portable draws, floating-point special values, exact integer geometry, and
// the exact transformations (power-of-two scaling, axis permutation) that the property
// suites use as oracle-free invariants.
//
// Everything here is plain C++ (no RapidCheck): the property suites, the fuzz targets,
// the benchmarks and the audit tool draw the same cases from the same seeds.
//
// Portability of the sequences: std::mt19937_64 is fully specified by the standard,
// but the std::*_distribution classes are not (libstdc++ and libc++ differ), so every
// draw below is derived from the raw 64-bit outputs by hand.
#pragma once

#include <rayproof/io.hpp>
#include <rayproof/rayproof.hpp>  // rayproof::detail::step_up / step_down
#include <rayproof/types.hpp>

#include <Eigen/Geometry>  // cross products

#include <array>
#include <bit>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <ostream>
#include <random>
#include <string_view>
#include <type_traits>

namespace rayproof::gen {

using Rng = std::mt19937_64;

// Every conversion to T of a value that may not be a T (a double, a large integer) goes
// through the kernel's narrow, which g++ < 13's SLP vectorizer cannot drop
// (docs/compiler-bugs.md).
using ::rayproof::detail::narrow;

// One generated input: the ray, the shape, and the name of the generator that made it.
template <class T, class Shape> struct Case {
    Ray<T> ray;
    Shape shape;
    std::string_view generator;
};

template <class T, class Shape> std::ostream& operator<<(std::ostream& os, const Case<T, Shape>& c) {
    return os << "Case{" << c.generator << ": " << c.ray << ' ' << c.shape << '}';
}

// The case c under another generator's name (a case of one generator made into another's).
template <class T, class Shape> Case<T, Shape> renamed(Case<T, Shape> c, std::string_view name) {
    c.generator = name;
    return c;
}

// FNV-1a of a name: portable per-generator seeds (std::hash differs between libraries).
constexpr std::uint64_t name_hash(std::string_view s) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (const char ch : s) h = (h ^ std::uint64_t(static_cast<unsigned char>(ch))) * 0x100000001b3ull;
    return h;
}

// ---------------------------------------------------------------------------------
// Portable draws.

// Uniform in [0, n), n > 0 (the modulo bias is below 2^-40 for the small n used here).
inline std::uint64_t below(Rng& rng, std::uint64_t n) { return rng() % n; }
// Uniform integer in [lo, hi].
inline std::int64_t uniform_int(Rng& rng, std::int64_t lo, std::int64_t hi) {
    return lo + std::int64_t(below(rng, std::uint64_t(hi - lo) + 1));
}
// True with probability num/den.
inline bool chance(Rng& rng, unsigned num, unsigned den) { return below(rng, den) < num; }
// Uniform in [0, 1) with 53 random bits.
inline double uniform01(Rng& rng) { return double(rng() >> 11) * 0x1p-53; }
// Uniform in [a, b] (rounded to T).
template <class T> T uniform(Rng& rng, double a, double b) { return narrow<T>(a + (b - a) * uniform01(rng)); }
// A random sign, +1 or -1.
inline int random_sign(Rng& rng) { return (rng() & 1) ? 1 : -1; }
// A uniform integer in [lo, hi] with a random sign (the sign drawn first).
//
// Note for every generator: the order in which function arguments (and the operands of
// most operators) are evaluated is unspecified, and g++ and clang differ. Two draws from
// one Rng never appear in the same full expression here (except in braced lists and
// declarator lists, which are sequenced left to right), so that a seed gives the same case
// under every compiler.
inline std::int64_t signed_int(Rng& rng, std::int64_t lo, std::int64_t hi) {
    const int s = random_sign(rng);
    return s * uniform_int(rng, lo, hi);
}

// ---------------------------------------------------------------------------------
// Floating-point structure.

template <class T> using Bits = std::conditional_t<std::is_same_v<T, float>, std::uint32_t, std::uint64_t>;
template <class T> inline constexpr int kMantissaBits = std::numeric_limits<T>::digits - 1;  // 23 / 52
template <class T> inline constexpr int kPrecision = std::numeric_limits<T>::digits;         // 24 / 53
template <class T> inline constexpr int kMaxBiasedExponent = std::is_same_v<T, float> ? 254 : 2046;
template <class T> inline constexpr T kInf = std::numeric_limits<T>::infinity();
template <class T> inline constexpr T kNaN = std::numeric_limits<T>::quiet_NaN();

template <class T> T from_bits(Bits<T> b) { return std::bit_cast<T>(b); }
template <class T> Bits<T> to_bits(T x) { return std::bit_cast<Bits<T>>(x); }

// The neighbours of x towards +inf / -inf: the kernel's own.
using ::rayproof::detail::step_down;
using ::rayproof::detail::step_up;
// x moved by `steps` representable values (positive: up).
template <class T> T nudge(T x, int steps) {
    for (; steps > 0; --steps) x = step_up(x);
    for (; steps < 0; ++steps) x = step_down(x);
    return x;
}
// x moved by one ulp either way (the sign drawn).
template <class T> void nudge_ulp(T& x, Rng& rng) { x = nudge(x, random_sign(rng)); }
// The two one-ulp neighbours of x.
template <class T> std::array<T, 2> one_ulp_neighbours(T x) { return {step_down(x), step_up(x)}; }

// The special values of T: signed zeros, the smallest and largest denormals, the smallest
// normal, the largest finite, 1 and its neighbours, epsilon, each with both signs.
template <class T> const std::array<T, 22>& special_values() {
    using L = std::numeric_limits<T>;
    static const std::array<T, 22> values = {
        T(0),           -T(0),           L::denorm_min(), -L::denorm_min(),
        step_down(L::min()), -step_down(L::min()),  // largest denormal
        L::min(),       -L::min(),       L::max(),        -L::max(),
        T(1),           T(-1),           step_up(T(1)),   step_down(T(1)),
        -step_up(T(1)), -step_down(T(1)), L::epsilon(),   -L::epsilon(),
        T(0.5),         T(2),            step_down(L::max()), std::ldexp(T(1), L::max_exponent / 2),
    };
    return values;
}
template <class T> T special_value(Rng& rng) {
    const auto& v = special_values<T>();
    return v[below(rng, v.size())];
}

// Log-uniform over the whole exponent range of T, denormals and zero included: a random
// biased exponent (0 = zero/denormal, up to the largest finite one), random mantissa
// bits, random sign. Every finite T has positive probability; NaN and inf never occur.
template <class T> T log_uniform(Rng& rng) {
    const Bits<T> exponent = Bits<T>(below(rng, kMaxBiasedExponent<T> + 1));
    const Bits<T> mantissa = Bits<T>(rng()) & ((Bits<T>(1) << kMantissaBits<T>) - 1);
    const Bits<T> sign = Bits<T>(rng() & 1) << (sizeof(T) * 8 - 1);
    return from_bits<T>(sign | (exponent << kMantissaBits<T>) | mantissa);
}
// Log-uniform, with a special value one time in eight.
template <class T> T wide_value(Rng& rng) { return chance(rng, 1, 8) ? special_value<T>(rng) : log_uniform<T>(rng); }
// Log-uniform magnitude between 2^lo and 2^hi (a random mantissa), random sign if asked.
template <class T> T magnitude(Rng& rng, int lo_exp, int hi_exp, bool signed_ = true) {
    const T m = T(1) + narrow<T>(uniform01(rng));  // [1, 2]
    const T x = std::ldexp(m, int(uniform_int(rng, lo_exp, hi_exp)));
    return signed_ ? narrow<T>(random_sign(rng)) * x : x;
}

// ---------------------------------------------------------------------------------
// Exact integer geometry (int64, then converted to T only when representable).

using I3 = std::array<std::int64_t, 3>;
inline I3 add(const I3& a, const I3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline I3 sub(const I3& a, const I3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline I3 mul(std::int64_t s, const I3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline std::int64_t dot(const I3& a, const I3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline I3 cross(const I3& a, const I3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline bool is_zero(const I3& a) { return a[0] == 0 && a[1] == 0 && a[2] == 0; }
inline std::int64_t det3(const I3& c0, const I3& c1, const I3& c2) { return dot(c0, cross(c1, c2)); }
inline I3 random_i3(Rng& rng, std::int64_t lo, std::int64_t hi) {
    return {uniform_int(rng, lo, hi), uniform_int(rng, lo, hi), uniform_int(rng, lo, hi)};
}
inline I3 random_nonzero_i3(Rng& rng, std::int64_t r) {
    for (;;) {
        const I3 v = random_i3(rng, -r, r);
        if (!is_zero(v)) return v;
    }
}

// True when the integer is exactly representable in T.
template <class T> bool representable(std::int64_t v) {
    const std::int64_t a = v < 0 ? -v : v;
    if (a <= (std::int64_t(1) << kPrecision<T>)) return true;
    return std::int64_t(narrow<T>(v)) == v;  // |v| < 2^63, so the conversion back is defined
}
template <class T> bool representable(const I3& v) {
    return representable<T>(v[0]) && representable<T>(v[1]) && representable<T>(v[2]);
}
template <class T> Vec3<T> to_vec(const I3& v) { return Vec3<T>(narrow<T>(v[0]), narrow<T>(v[1]), narrow<T>(v[2])); }

// A Pythagorean quadruple (a, b, c, n): a² + b² + c² = n², n > 0, from four small
// integers (every primitive quadruple arises this way: Carmichael's parametrization).
struct Quadruple {
    I3 v;
    std::int64_t n;
};
inline Quadruple pythagorean_quadruple(Rng& rng, std::int64_t r = 4) {
    for (;;) {
        const std::int64_t m = uniform_int(rng, -r, r), n = uniform_int(rng, -r, r), p = uniform_int(rng, -r, r),
                           q = uniform_int(rng, -r, r);
        const std::int64_t len = m * m + n * n + p * p + q * q;
        if (len == 0) continue;
        return {{m * m + n * n - p * p - q * q, 2 * (m * q + n * p), 2 * (n * q - m * p)}, len};
    }
}

// An integer 3x3 matrix with orthogonal columns of equal norm n (the rotation of the
// integer quaternion (w, x, y, z) times n = w² + x² + y² + z²).
struct IMat3 {
    std::array<I3, 3> col;
};
inline IMat3 integer_rotation(Rng& rng, std::int64_t r = 3) {
    for (;;) {
        const std::int64_t w = uniform_int(rng, -r, r), x = uniform_int(rng, -r, r), y = uniform_int(rng, -r, r),
                           z = uniform_int(rng, -r, r);
        if (w == 0 && x == 0 && y == 0 && z == 0) continue;
        IMat3 m;
        m.col[0] = {w * w + x * x - y * y - z * z, 2 * (x * y + w * z), 2 * (x * z - w * y)};
        m.col[1] = {2 * (x * y - w * z), w * w - x * x + y * y - z * z, 2 * (y * z + w * x)};
        m.col[2] = {2 * (x * z + w * y), 2 * (y * z - w * x), w * w - x * x - y * y + z * z};
        return m;
    }
}
// Integer box axes with det != 0: a permuted, scaled identity; a scaled integer
// rotation (orthogonal, non-normalized); or a general (sheared) integer matrix.
inline IMat3 integer_axes(Rng& rng) {
    IMat3 m;
    for (;;) {
        const auto kind = below(rng, 3);
        if (kind == 0) {
            std::array<int, 3> perm = {0, 1, 2};
            for (int i = 2; i > 0; --i) std::swap(perm[i], perm[below(rng, i + 1)]);
            for (int i = 0; i < 3; ++i) {
                m.col[i] = {0, 0, 0};
                m.col[i][perm[i]] = signed_int(rng, 1, 4);
            }
        } else if (kind == 1) {
            m = integer_rotation(rng);
            for (auto& c : m.col) c = mul(signed_int(rng, 1, 3), c);
        } else {
            for (auto& c : m.col) c = random_i3(rng, -4, 4);
        }
        if (det3(m.col[0], m.col[1], m.col[2]) != 0) return m;
    }
}
template <class T> Mat3<T> to_mat(const IMat3& m) {
    Mat3<T> a;
    for (int i = 0; i < 3; ++i) a.col(i) = to_vec<T>(m.col[i]);
    return a;
}

// A translation of integer geometry that keeps every sum exact in T: zero half the
// time, otherwise up to 2^(precision - 10) in each coordinate (far from the origin).
template <class T> I3 random_translation(Rng& rng) {
    if (chance(rng, 1, 2)) return {0, 0, 0};
    I3 t;
    for (auto& x : t) {
        const std::int64_t m = std::int64_t(1) << uniform_int(rng, 0, kPrecision<T> - 10);
        x = uniform_int(rng, -m, m);
    }
    return t;
}

// The ray from the integer point origin along d, or false (r untouched) when the point
// is not exact in T.
template <class T> bool ray_from_integers(const I3& origin, const Vec3<T>& d, Ray<T>& r) {
    if (!representable<T>(origin)) return false;
    r.origin = to_vec<T>(origin);
    r.direction = d;
    return true;
}

// A small direction or offset vector with random signed zeros in place of zeros.
template <class T> Vec3<T> to_vec_signed_zeros(const I3& v, Rng& rng) {
    Vec3<T> r = to_vec<T>(v);
    for (int i = 0; i < 3; ++i)
        if (v[i] == 0 && (rng() & 1)) r[i] = -T(0);
    return r;
}

// A nonzero T vector with components drawn by `draw`.
template <class T, class F> Vec3<T> nonzero_vec(Rng& rng, F draw) {
    for (;;) {
        const T x = draw(rng), y = draw(rng), z = draw(rng);
        const Vec3<T> v(x, y, z);
        if (v[0] != 0 || v[1] != 0 || v[2] != 0) return v;
    }
}

// A nonzero T vector of wide values.
template <class T> Vec3<T> nonzero_wide_vec(Rng& rng) {
    return nonzero_vec<T>(rng, [](Rng& g) { return wide_value<T>(g); });
}

// ---------------------------------------------------------------------------------
// Ray parameter ranges.

// [0, inf) mostly; sometimes the whole line, a finite range, or [0, b].
template <class T> void random_t_range(Ray<T>& r, Rng& rng, double scale = 16) {
    const auto k = below(rng, 10);
    if (k < 6) {
        r.t_min = 0;
        r.t_max = kInf<T>;
    } else if (k == 6) {
        r.t_min = -kInf<T>;
        r.t_max = kInf<T>;
    } else if (k == 7) {
        r.t_min = 0;
        r.t_max = uniform<T>(rng, 0, scale);
    } else {
        T a = uniform<T>(rng, -scale, scale), b = uniform<T>(rng, -scale, scale);
        if (b < a) std::swap(a, b);
        r.t_min = a;
        r.t_max = b;
    }
}
// The end of a log-uniform ray: a nonzero direction of wide values, then, one time in
// four, a sorted range of wide values whose ends are each made infinite one time in four.
template <class T> void wide_direction_and_range(Ray<T>& r, Rng& rng) {
    r.direction = nonzero_wide_vec<T>(rng);
    if (chance(rng, 1, 4)) {
        T a = wide_value<T>(rng), b = wide_value<T>(rng);
        if (b < a) std::swap(a, b);
        r.t_min = chance(rng, 1, 4) ? -kInf<T> : a;
        r.t_max = chance(rng, 1, 4) ? kInf<T> : b;
    }
}
// A range for a constructed case where the special point is at the exact parameter s:
// [0, inf), [s, inf) (t_min exactly at the point), [-inf, s] / [0, s] (t_max exactly at
// it), [s, s], or the whole line.
template <class T> void special_t_range(Ray<T>& r, Rng& rng, T s) {
    switch (below(rng, 8)) {
        case 0: r.t_min = s; r.t_max = kInf<T>; break;
        case 1: r.t_min = -kInf<T>; r.t_max = s; break;
        case 2: r.t_min = s; r.t_max = s; break;
        case 3: r.t_min = -kInf<T>; r.t_max = kInf<T>; break;
        case 4: r.t_min = std::min(T(0), s); r.t_max = s < 0 ? T(0) : s; break;
        default: r.t_min = 0; r.t_max = kInf<T>; break;
    }
}
// Where an on_boundary case meets its boundary point: at the origin half the time
// (s = 0), else at the integer parameter s drawn in [lo, hi].
struct BoundaryParameter {
    bool at_origin;
    std::int64_t s;
};
inline BoundaryParameter boundary_parameter(Rng& rng, std::int64_t lo, std::int64_t hi) {
    const bool at_origin = chance(rng, 1, 2);
    return {at_origin, at_origin ? 0 : uniform_int(rng, lo, hi)};
}
// The range of an on_boundary case: `origin_range(r, rng)` when the point is at the
// origin, with a t_max below t_min made +inf; special_t_range at s otherwise.
template <class T, std::invocable<Ray<T>&, Rng&> OriginRange>
void on_boundary_t_range(Ray<T>& r, Rng& rng, BoundaryParameter at, OriginRange origin_range) {
    if (at.at_origin) {
        origin_range(r, rng);
        if (r.t_max < r.t_min) r.t_max = kInf<T>;
    } else {
        special_t_range(r, rng, narrow<T>(at.s));
    }
}
// The same with the usual range at the origin: random_t_range, t_min made 0 half the time.
template <class T> void on_boundary_t_range(Ray<T>& r, Rng& rng, BoundaryParameter at, double scale) {
    on_boundary_t_range(r, rng, at, [scale](Ray<T>& q, Rng& g) {
        random_t_range(q, g, scale);
        if (chance(g, 1, 2)) q.t_min = 0;
    });
}

// ---------------------------------------------------------------------------------
// Exact transformations.

namespace detail {
// x·2^k if that is exact (finite, no bits lost to underflow); x itself is finite or inf.
template <class T> bool scaled(T x, int k, T& out) {
    if (!std::isfinite(x)) {
        out = x;
        return !std::isnan(x);
    }
    const T y = std::ldexp(x, k);
    if (!std::isfinite(y) || std::ldexp(y, -k) != x) return false;
    out = y;
    return true;
}
template <class T> bool scaled(const Vec3<T>& v, int k, Vec3<T>& out) {
    return scaled(v[0], k, out[0]) && scaled(v[1], k, out[1]) && scaled(v[2], k, out[2]);
}
template <class T> bool scale_ray(const Ray<T>& r, int kp, int kd, Ray<T>& out) {
    return scaled(r.origin, kp, out.origin) && scaled(r.direction, kd, out.direction) &&
           scaled(r.t_min, kp - kd, out.t_min) && scaled(r.t_max, kp - kd, out.t_max);
}
template <class T> bool scale_shape(const Aabb<T>& b, int kp, int, Aabb<T>& o) {
    return scaled(b.lo, kp, o.lo) && scaled(b.hi, kp, o.hi);
}
template <class T> bool scale_shape(const Obb<T>& b, int kp, int ka, Obb<T>& o) {
    for (int i = 0; i < 9; ++i)
        if (!scaled(b.axes.data()[i], ka, o.axes.data()[i])) return false;
    return scaled(b.center, kp, o.center) && scaled(b.half_extent, kp + ka, o.half_extent);
}
template <class T> bool scale_shape(const Plane<T>& p, int kp, int ka, Plane<T>& o) {
    return scaled(p.normal, ka, o.normal) && scaled(p.offset, kp + ka, o.offset);
}
template <class T> bool scale_shape(const Sphere<T>& s, int kp, int, Sphere<T>& o) {
    return scaled(s.center, kp, o.center) && scaled(s.radius, kp, o.radius);
}
}  // namespace detail

// Scales every position by 2^kp, the direction by 2^kd and the shape's own vectors (Obb
// axes, plane normal) by 2^ka, with t_min and t_max scaled by 2^(kp-kd) so that the ray
// covers the same points. The exact answer is unchanged except that t_enter and t_exit
// are multiplied by 2^(kp-kd) (so kp == kd leaves t unchanged). Returns false, leaving
// `c` untouched, when some number would not be scaled exactly (overflow, or bits lost
// below the denormal range). Only meaningful for valid inputs (NaN is refused).
template <class T, class Shape> bool exact_scale(Case<T, Shape>& c, int kp, int kd, int ka = 0) {
    Case<T, Shape> out = c;
    if (!detail::scale_ray(c.ray, kp, kd, out.ray) || !detail::scale_shape(c.shape, kp, ka, out.shape)) return false;
    c = out;
    return true;
}

// With probability 1/2, an exact power-of-two rescaling of the case anywhere in the
// exponent range of T (falling back to smaller exponents when the first draw would not
// be exact): the same geometry at every magnitude, denormals included.
template <class T, class Shape> void random_exact_scaling(Case<T, Shape>& c, Rng& rng) {
    if (chance(rng, 1, 2)) return;
    const int e = std::numeric_limits<T>::max_exponent - std::numeric_limits<T>::min_exponent + kPrecision<T>;
    int kp = int(uniform_int(rng, -e / 2, e / 2)), kd = int(uniform_int(rng, -e / 2, e / 2)),
        ka = int(uniform_int(rng, -e / 4, e / 4));
    if (chance(rng, 1, 2)) kd = kp;  // keep t
    for (int attempt = 0; attempt < 8; ++attempt, kp /= 2, kd /= 2, ka /= 2)
        if (exact_scale(c, kp, kd, ka)) return;
}

// Applies the axis permutation perm (new axis i is old axis perm[i]) to a Vec3.
template <class T> Vec3<T> permuted(const Vec3<T>& v, const std::array<int, 3>& perm) {
    return Vec3<T>(v[perm[0]], v[perm[1]], v[perm[2]]);
}
// ... and to the origin and direction of a ray (its range stays).
template <class T> Ray<T> permuted(const Ray<T>& r, const std::array<int, 3>& perm) {
    Ray<T> o = r;
    o.origin = permuted(r.origin, perm);
    o.direction = permuted(r.direction, perm);
    return o;
}
// The same case with the box axes renamed: Aabb, Sphere, Plane permute the coordinates of
// every vector; Obb permutes the columns of `axes` and the half extents (its coordinates
// stay). The exact verdict and interval are unchanged; an entry face on old axis j is
// on new axis i with perm[i] == j (up to the lowest-index tie rule).
template <class T> Case<T, Aabb<T>> permute_axes(const Case<T, Aabb<T>>& c, const std::array<int, 3>& p) {
    Case<T, Aabb<T>> o = c;
    o.ray = permuted(c.ray, p);
    o.shape.lo = permuted(c.shape.lo, p);
    o.shape.hi = permuted(c.shape.hi, p);
    return o;
}
template <class T> Case<T, Obb<T>> permute_axes(const Case<T, Obb<T>>& c, const std::array<int, 3>& p) {
    Case<T, Obb<T>> o = c;
    for (int i = 0; i < 3; ++i) o.shape.axes.col(i) = c.shape.axes.col(p[i]);
    o.shape.half_extent = permuted(c.shape.half_extent, p);
    return o;
}
template <class T> Case<T, Plane<T>> permute_axes(const Case<T, Plane<T>>& c, const std::array<int, 3>& p) {
    Case<T, Plane<T>> o = c;
    o.ray = permuted(c.ray, p);
    o.shape.normal = permuted(c.shape.normal, p);
    return o;
}
template <class T> Case<T, Sphere<T>> permute_axes(const Case<T, Sphere<T>>& c, const std::array<int, 3>& p) {
    Case<T, Sphere<T>> o = c;
    o.ray = permuted(c.ray, p);
    o.shape.center = permuted(c.shape.center, p);
    return o;
}

// ---------------------------------------------------------------------------------
// Invalid inputs: one class per rule of the contract.

enum class RayFault { nan_origin, inf_origin, nan_direction, inf_direction, nan_t_min, nan_t_max, t_min_plus_inf,
                      t_max_minus_inf, t_min_above_t_max, zero_direction, count };

// NaN, or +inf or -inf, with equal chance.
template <class T> T non_finite(Rng& rng) { return chance(rng, 1, 2) ? kNaN<T> : narrow<T>(random_sign(rng)) * kInf<T>; }
// A non_finite value put, with equal chance, in x or in a drawn component of v.
template <class T> void make_non_finite(T& x, Vec3<T>& v, Rng& rng) {
    const T bad = non_finite<T>(rng);
    if (chance(rng, 1, 2))
        x = bad;
    else
        v[below(rng, 3)] = bad;
}

// Makes r invalid in the given way (r is assumed valid).
template <class T> void break_ray(Ray<T>& r, RayFault f, Rng& rng) {
    const int i = int(below(rng, 3));
    switch (f) {
        case RayFault::nan_origin: r.origin[i] = kNaN<T>; break;
        case RayFault::inf_origin: r.origin[i] = narrow<T>(random_sign(rng)) * kInf<T>; break;
        case RayFault::nan_direction: r.direction[i] = kNaN<T>; break;
        case RayFault::inf_direction: r.direction[i] = narrow<T>(random_sign(rng)) * kInf<T>; break;
        case RayFault::nan_t_min: r.t_min = kNaN<T>; break;
        case RayFault::nan_t_max: r.t_max = kNaN<T>; break;
        case RayFault::t_min_plus_inf: r.t_min = kInf<T>; break;
        case RayFault::t_max_minus_inf: r.t_max = -kInf<T>; break;
        case RayFault::t_min_above_t_max: {
            const T a = chance(rng, 1, 2) ? uniform<T>(rng, -8, 8) : wide_value<T>(rng);
            r.t_max = a;
            r.t_min = step_up(a);
            if (chance(rng, 1, 2)) r.t_min = std::max(r.t_min, a + T(1));
            break;
        }
        case RayFault::zero_direction:
            for (int k = 0; k < 3; ++k) r.direction[k] = (rng() & 1) ? T(0) : -T(0);
            break;
        case RayFault::count: break;
    }
}

// ---------------------------------------------------------------------------------
// The frames the shapes' generators share (each shape file fills in its geometry).

// A constructed case: `build(c)` draws integer geometry into a fresh case named `name`
// and returns false when some number would not be exact in T; then a fresh case is
// drawn. The case built is rescaled by random_exact_scaling.
template <class T, class Shape, class Build> Case<T, Shape> constructed(std::string_view name, Rng& rng, Build build) {
    for (;;) {
        Case<T, Shape> c{{}, {}, name};
        if (!build(c)) continue;
        random_exact_scaling(c, rng);
        return c;
    }
}

// A near_grazing case from a grazing one: an axis i drawn, `nudge_one(c, i)` moving one
// number of the case by an ulp or so, and the direction kept nonzero (a nudge may turn
// its only nonzero component into zero).
template <class T, class Shape, class Nudge>
Case<T, Shape> near_grazing_from(Case<T, Shape> grazing, Rng& rng, Nudge nudge_one) {
    Case<T, Shape> c = renamed(grazing, "near_grazing");
    const int i = int(below(rng, 3));
    nudge_one(c, i);
    if (c.ray.direction.isZero()) c.ray.direction[i] = std::numeric_limits<T>::denorm_min();
    return c;
}

// The near_grazing case of most shapes: k drawn in [0, 6); `first(c, i, rng)` when
// k == 0, `second(c, i, rng)` when k == 1, else direction component i moved by one ulp.
template <class T, class Shape, class First, class Second>
Case<T, Shape> near_grazing_from(Case<T, Shape> c, Rng& rng, First first, Second second) {
    return near_grazing_from(c, rng, [&](Case<T, Shape>& x, int i) {
        const auto k = below(rng, 6);
        if (k == 0)
            first(x, i, rng);
        else if (k == 1)
            second(x, i, rng);
        else
            nudge_ulp(x.ray.direction[i], rng);
    });
}
// Origin coordinate i moved by one ulp (a `first` or `second` of near_grazing_from).
inline constexpr auto nudge_origin = [](auto& c, int i, Rng& rng) { nudge_ulp(c.ray.origin[i], rng); };

// Whether an invalid generator draws an axis (after the fault, before breaking anything).
enum class FaultAxis { none, drawn };

// An invalid case from a valid one (a general or a grazing case, drawn with equal
// chance): one fault among the ray's RayFault::count and the shape's `shape_faults`,
// drawn uniformly; a ray fault is applied by break_ray, shape fault k (0-based) by
// `break_shape(c, k, axis)`, axis -1 unless FaultAxis::drawn.
template <class T, class Shape, class BreakShape>
Case<T, Shape> invalid_from(Case<T, Shape> (*general)(Rng&), Case<T, Shape> (*grazing)(Rng&), Rng& rng,
                            unsigned shape_faults, FaultAxis axis, BreakShape break_shape) {
    Case<T, Shape> c = renamed(chance(rng, 1, 2) ? general(rng) : grazing(rng), "invalid");
    const auto k = below(rng, unsigned(RayFault::count) + shape_faults);
    const int i = axis == FaultAxis::drawn ? int(below(rng, 3)) : -1;
    if (k < unsigned(RayFault::count))
        break_ray(c.ray, RayFault(k), rng);
    else
        break_shape(c, unsigned(k) - unsigned(RayFault::count), i);
    return c;
}

}  // namespace rayproof::gen
