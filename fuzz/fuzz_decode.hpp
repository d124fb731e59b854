// fuzz_decode.hpp — the byte format of the ray/shape fuzz targets: fuzzer input bytes to a
// ray and a shape (Decoder), and a case back to bytes (encode, for the seed corpora).
//
// The decoder reads the input with FuzzedDataProvider (which takes integers from the END
// of the buffer) and is biased toward the values that break geometry code. Layout:
//
//   header byte   bit 0: scalar (0 float, 1 double)
//                 bits 1-2: t range: 0 [0, +inf)  1 (-inf, +inf)  2 [decoded, +inf)
//                           3 [decoded, decoded]
//                 bits 3-4: Obb axes: 0, 1 decoded one by one  2 integer rotation (exactly
//                           orthogonal, non-normalized)  3 signed permutation, scaled
//   fields        the shape's numbers, then origin, direction, t_min, t_max (those the
//                 t-range style decodes); each is one selector byte s, class s & 7 with
//                 parameter n = s >> 3 (0..31), then the bytes that class needs:
//                   0 small integer      n zig-zag decoded: 0, -1, 1, -2, ... -16, 15
//                   1 integer            a 16-bit two's complement integer
//                   2 special value      special_value<T>(n): ±0, denormals, the smallest
//                                        normal, the largest finite, 1 and its neighbours,
//                                        ±inf, NaN, ... (see the table)
//                   3 copy               a previous field (index byte), negated if n & 1,
//                                        moved by kCopySteps[n >> 1] ulps: the origin on a
//                                        slab plane, a radius equal to a coordinate, the
//                                        one-ulp neighbours of either
//                   4 raw bits           every bit pattern of T (NaN and inf included)
//                   5 dyadic             16-bit integer times 2^e, e over the whole
//                                        exponent range (rounded at under/overflow)
//                   6 derived            op n & 7 on two previous fields: a+b, a-b, a·b,
//                                        a/b, -a, (a+b)/2, the neighbour of a toward b, |a|
//                                        (a corner minus the origin aims at the corner)
//                   7 fraction           (8-bit int)/(8-bit int) times 2^(n-16): rounded,
//                                        inexact values (1/3, -5/7, ...)
//   constructs    (Plane and Sphere, when header bits 5-7 are all set) three bytes,
//                 what, amount and extra (and extra2 for the Plane), read after the
//                 fields; the construction is
//                 applied after the patches (Decoder::construct): a direction parallel to
//                 the plane but for a relative residual ε (n·d a cancellation), the case
//                 scaled to the overflow edge, the origin at distance r(1 + δ) from the
//                 centre or the line at that distance (near-tangent), a limit at the
//                 crossing or a root times (1 + δ), a limit whose product with the
//                 computed n·d overflows by a relative δ; δ, ε = ±2^-k from the bytes
//   patches       while bytes remain (at most 64 times): a field index byte, then one
//                 field as above that overwrites it (copies may then read any field, so
//                 any field can be equated to any other, in either direction)
//
// An empty input decodes to all zeros (an invalid, zero-direction ray). The format is
// fixed: the committed corpora and regressions depend on it; a change must re-encode them.
// Convex polyhedra (a variable number of planes) have a format of their own, built of the
// same field classes: see PolyDecoder at the end of this file.
#pragma once

#include <fuzzer/FuzzedDataProvider.h>  // clang's; copied into the build tree for g++ (targets.cmake)

#include <rayproof/rayproof.hpp>  // rayproof::detail::step_up / step_down
#include <rayproof/types.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>

namespace rayproof::fuzz {

template <class T> using Bits = std::conditional_t<std::is_same_v<T, float>, std::uint32_t, std::uint64_t>;

enum class ShapeKind { aabb, obb, plane, sphere };

template <class T, class Shape> struct Input {
    Ray<T> ray;
    Shape shape;
};

// Header bits.
inline constexpr unsigned kDoubleBit = 1u;
inline constexpr unsigned kTRangeShift = 1u;
inline constexpr unsigned kAxesShift = 3u;
inline constexpr unsigned kConstructShift = 5u;  // bits 5-7 all set: a construction (Plane, Sphere)

// Field classes.
enum Class : unsigned { small_int = 0, int16 = 1, special = 2, copy = 3, raw = 4, dyadic = 5, derived = 6, fraction = 7 };

// Ulp moves of the copy class (parameter n >> 1): mostly the value itself or a neighbour.
inline constexpr int kCopySteps[16] = {0, 0, 0, 0, 1, -1, 1, -1, 2, -2, 3, -3, 16, -16, 1024, -1024};

// The neighbours of x towards +inf / -inf: the kernel's own.
using ::rayproof::detail::step_down;
using ::rayproof::detail::step_up;
template <class T> T nudged(T x, int steps) {
    if (std::isnan(x)) return x;
    for (; steps > 0; --steps) x = step_up(x);
    for (; steps < 0; ++steps) x = step_down(x);
    return x;
}

// The 32 special values of class 2.
template <class T> const std::array<T, 32>& special_values() {
    using L = std::numeric_limits<T>;
    constexpr int p = L::digits;
    static const std::array<T, 32> v = {
        T(0),                          -T(0),
        L::denorm_min(),               -L::denorm_min(),
        step_down(L::min()),           -step_down(L::min()),  // the largest denormal
        L::min(),                      -L::min(),
        L::max(),                      -L::max(),
        T(1),                          T(-1),
        step_up(T(1)),                 step_down(T(1)),
        L::epsilon(),                  T(0.5),
        T(2),                          L::infinity(),
        -L::infinity(),                L::quiet_NaN(),
        std::ldexp(T(1), L::max_exponent / 2),  // squares near the overflow threshold
        -std::ldexp(T(1), L::max_exponent / 2),
        std::ldexp(T(1), L::min_exponent / 2),  // squares near the underflow threshold
        -std::ldexp(T(1), L::min_exponent / 2),
        step_down(L::max()),           T(3),
        T(1) / T(3),                   T(-0.5),
        std::ldexp(T(1), -p),          // half an ulp of 1
        std::ldexp(T(1), p),           // the first integer whose ulp is 2
        step_up(std::ldexp(T(1), p)),  L::denorm_min() * T(3),
    };
    return v;
}

template <class T> T from_bits(Bits<T> b) { return std::bit_cast<T>(b); }
template <class T> Bits<T> to_bits(T x) { return std::bit_cast<Bits<T>>(x); }

// Exponent range of the dyadic class: enough to reach below the smallest denormal and
// beyond the largest finite value with a 16-bit mantissa.
template <class T> inline constexpr int kDyadicMinExp = std::numeric_limits<T>::min_exponent - std::numeric_limits<T>::digits - 20;
template <class T> inline constexpr int kDyadicMaxExp = std::numeric_limits<T>::max_exponent + 2;

// Number of numeric fields of each shape.
template <class Shape> inline constexpr int kShapeFields = 0;
template <class T> inline constexpr int kShapeFields<Aabb<T>> = 6;
template <class T> inline constexpr int kShapeFields<Obb<T>> = 15;
template <class T> inline constexpr int kShapeFields<Plane<T>> = 4;
template <class T> inline constexpr int kShapeFields<Sphere<T>> = 4;
inline constexpr int kRayFields = 8;
inline constexpr int kMaxPatches = 64;

// The fields of an input, in decoding order: the shape's numbers, then origin, direction,
// t_min, t_max.
template <class T, class Shape> std::array<T*, kShapeFields<Shape> + kRayFields> fields(Input<T, Shape>& in) {
    std::array<T*, kShapeFields<Shape> + kRayFields> f{};
    int k = 0;
    auto add3 = [&](Vec3<T>& v) {
        for (int i = 0; i < 3; ++i) f[k++] = &v[i];
    };
    if constexpr (std::is_same_v<Shape, Aabb<T>>) {
        add3(in.shape.lo);
        add3(in.shape.hi);
    } else if constexpr (std::is_same_v<Shape, Obb<T>>) {
        add3(in.shape.center);
        for (int i = 0; i < 9; ++i) f[k++] = in.shape.axes.data() + i;  // column-major: column by column
        add3(in.shape.half_extent);
    } else if constexpr (std::is_same_v<Shape, Plane<T>>) {
        add3(in.shape.normal);
        f[k++] = &in.shape.offset;
    } else {
        add3(in.shape.center);
        f[k++] = &in.shape.radius;
    }
    add3(in.ray.origin);
    add3(in.ray.direction);
    f[k++] = &in.ray.t_min;
    f[k++] = &in.ray.t_max;
    return f;
}

// Reads the header byte: true when the input is a double case.
inline bool is_double(const std::uint8_t* data, std::size_t size) {
    FuzzedDataProvider p(data, size);
    return p.ConsumeIntegral<std::uint8_t>() & kDoubleBit;
}

// The number classes every decoder shares: one selector byte and what its class needs
// (the table above), read from the provider; copies and derived values read the fields
// decoded so far (done_).
// Fields is an indexable sequence of T* (std::array or std::vector), which gives T.
class FieldReader {
protected:
    FieldReader(const std::uint8_t* data, std::size_t size) : p_(data, size) {}

    // One field; the fields [0, avail) may be copied (those decoded so far: done_).
    template <class Fields, class T = std::remove_pointer_t<typename Fields::value_type>>
    T value(const Fields& f, int avail) {
        const unsigned s = p_.ConsumeIntegral<std::uint8_t>();
        const unsigned n = s >> 3;
        switch (s & 7u) {
            case small_int: return T((n & 1u) ? -int(n + 1) / 2 : int(n / 2));
            case int16: return T(std::int16_t(p_.ConsumeIntegral<std::uint16_t>()));
            case special: return special_values<T>()[n];
            case copy: {
                const T src = pick(f, avail);
                const T v = nudged(src, kCopySteps[n >> 1]);
                return (n & 1u) ? -v : v;
            }
            case raw: return from_bits<T>(p_.ConsumeIntegral<Bits<T>>());
            case dyadic: {
                const T m = T(std::int16_t(p_.ConsumeIntegral<std::uint16_t>()));
                const int e = kDyadicMinExp<T> + int(p_.ConsumeIntegral<std::uint16_t>() %
                                                     unsigned(kDyadicMaxExp<T> - kDyadicMinExp<T> + 1));
                return scale(m, e);
            }
            case derived: {
                const T a = pick(f, avail), b = pick(f, avail);
                switch (n & 7u) {
                    case 0: return a + b;
                    case 1: return a - b;
                    case 2: return a * b;
                    case 3: return a / b;  // IEEE: ±inf or NaN for b == 0 (an invalid input)
                    case 4: return -a;
                    case 5: return (a + b) / 2;
                    case 6: return std::nextafter(a, b);
                    default: return std::fabs(a);
                }
            }
            default: {  // fraction
                const T a = T(std::int8_t(p_.ConsumeIntegral<std::uint8_t>()));
                const int b = std::int8_t(p_.ConsumeIntegral<std::uint8_t>());
                return scale(a / T(b == 0 ? 1 : b), int(n) - 16);
            }
        }
    }

    // A previous field (0 when there is none).
    template <class Fields, class T = std::remove_pointer_t<typename Fields::value_type>>
    T pick(const Fields& f, int avail) {
        const unsigned i = p_.ConsumeIntegral<std::uint8_t>();
        const int limit = avail < done_ ? avail : done_;
        return limit > 0 ? *f[i % unsigned(limit)] : T(0);
    }

    // x·2^e in steps that each stay exact until the final rounding (std::ldexp).
    template <class T> static T scale(T x, int e) { return std::ldexp(x, e); }

    FuzzedDataProvider p_;
    int done_ = 0;  // fields decoded so far (copies read only those during the first pass)
};

template <class T, class Shape> class Decoder : FieldReader {
public:
    static constexpr int kFields = kShapeFields<Shape> + kRayFields;
    static constexpr int kTMinField = kFields - 2;
    static constexpr int kTMaxField = kFields - 1;
    static constexpr int kAxesFirst = 3, kAxesLast = 11;  // Obb: the 9 axes fields

    Decoder(const std::uint8_t* data, std::size_t size) : FieldReader(data, size) {}

    Input<T, Shape> decode() {
        Input<T, Shape> in{};
        auto f = fields(in);
        const unsigned header = p_.ConsumeIntegral<std::uint8_t>();
        const unsigned t_style = (header >> kTRangeShift) & 3u;
        const unsigned axes_style = (header >> kAxesShift) & 3u;
        constexpr T inf = std::numeric_limits<T>::infinity();
        for (int k = 0; k < kFields; ++k) {
            if (k == kTMinField && t_style <= 1) {
                *f[k] = t_style == 0 ? T(0) : -inf;
            } else if (k == kTMaxField && t_style <= 2) {
                *f[k] = inf;
            } else if (std::is_same_v<Shape, Obb<T>> && k == kAxesFirst && axes_style >= 2) {
                constructed_axes(f, axes_style);
                k = kAxesLast;
            } else {
                *f[k] = value(f, k);
            }
            done_ = k + 1;
        }
        constexpr bool constructible = std::is_same_v<Shape, Plane<T>> || std::is_same_v<Shape, Sphere<T>>;
        const bool constructed = constructible && (header >> kConstructShift) == 7u;
        unsigned what = 0, amount = 0, extra = 0, extra2 = 0;
        if (constructed) {
            what = p_.ConsumeIntegral<std::uint8_t>();
            amount = p_.ConsumeIntegral<std::uint8_t>();
            extra = p_.ConsumeIntegral<std::uint8_t>();
            if (std::is_same_v<Shape, Plane<T>>) extra2 = p_.ConsumeIntegral<std::uint8_t>();
        }
        for (int i = 0; i < kMaxPatches && p_.remaining_bytes() > 0; ++i) {
            const int dst = int(p_.ConsumeIntegral<std::uint8_t>() % unsigned(kFields));
            *f[dst] = value(f, kFields);
        }
        if constexpr (constructible) {
            if (constructed) construct(in, what, amount, extra, extra2);
        }
        return in;
    }

private:
    using Fields = std::array<T*, kFields>;

    // Obb axes built exactly: an integer rotation or a scaled signed permutation.
    void constructed_axes(const Fields& f, unsigned style) {
        Mat3<T> a = Mat3<T>::Zero();
        if (style == 2) {
            // The rotation matrix of the integer quaternion (w, x, y, z), times its squared
            // norm: integer entries below 2^17, exactly orthogonal columns of equal norm;
            // each column then scaled by 2^k (exact unless it under- or overflows).
            std::int64_t q[4];
            for (auto& c : q) c = std::int8_t(p_.ConsumeIntegral<std::uint8_t>()) / 8;  // [-16, 15]
            const std::int64_t w = q[0], x = q[1], y = q[2], z = q[3];
            const std::int64_t m[3][3] = {
                {w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)},
                {2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)},
                {2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z},
            };
            for (int c = 0; c < 3; ++c) {
                const int k = int(std::int8_t(p_.ConsumeIntegral<std::uint8_t>()));
                for (int r = 0; r < 3; ++r) a(r, c) = scale(T(m[r][c]), k);
            }
        } else {
            // Column c is s_c times the unit vector of axis perm[c].
            static constexpr int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
            const unsigned pi = p_.ConsumeIntegral<std::uint8_t>() % 6u;
            for (int c = 0; c < 3; ++c) a(perms[pi][c], c) = value(f, kAxesFirst);
        }
        for (int i = 0; i < 9; ++i) *f[kAxesFirst + i] = a.data()[i];
    }

    // Constructions: cases random bytes almost never build, computed in long double and
    // rounded to T (so each lands within rounding of its aim, the hard region). δ =
    // ±2^-k, k = (amount >> 1) mod 72, 0 for k = 71: from a relative 1/2 down to below
    // the rounding of T.
    using LD = long double;
    static LD relative(unsigned amount) {
        const int k = int((amount >> 1) % 72u);
        if (k == 71) return 0;
        const LD d = std::ldexp(LD(1), -k);
        return (amount & 1u) ? -d : d;
    }
    static LD dot(const Vec3<T>& a, const Vec3<T>& b) {
        return LD(a[0]) * LD(b[0]) + LD(a[1]) * LD(b[1]) + LD(a[2]) * LD(b[2]);
    }
    static bool all_finite(const Input<T, Shape>& in) {
        return in.ray.origin.allFinite() && in.ray.direction.allFinite() && std::isfinite(in.ray.t_min) &&
               std::isfinite(in.ray.t_max) && shape_finite(in.shape);
    }
    static bool shape_finite(const Plane<T>& p) { return p.normal.allFinite() && std::isfinite(p.offset); }
    static bool shape_finite(const Sphere<T>& s) { return s.center.allFinite() && std::isfinite(s.radius); }
    template <class S> static bool shape_finite(const S&) { return true; }
    // A limit set to x (bit 3 of what: t_max, else t_min), the other one opened when the
    // range would be empty.
    static void set_limit(Ray<T>& r, unsigned what, LD x) {
        constexpr T inf = std::numeric_limits<T>::infinity();
        const T v = T(x);
        if (!std::isfinite(v)) return;
        if (what & 8u) {
            r.t_max = v;
            if (r.t_min > v) r.t_min = -inf;
        } else {
            r.t_min = v;
            if (r.t_max < v) r.t_max = inf;
        }
    }
    // Plane, what: bit 0 the direction made parallel to the plane but for a relative
    // residual ε = relative(extra) (d minus (1 - ε) times its component along n, so n·d
    // is ε times the old n·d, a cancellation of much larger terms: near ε = 2^-50 the
    // computed n·d is just above its error bound and may be off by half its value); bit
    // 1 the offset and the origin scaled by a power of two so that the largest term of
    // N = offset - n·o lies within a factor 2^(1 + (what >> 6)) of the overflow
    // threshold; bit 2 a limit at the crossing t = N/D times (1 + δ), δ =
    // relative(amount), bit 3 choosing which limit; bit 4 (instead of bit 2) that limit
    // set to ±2^emax/D~·(1 + δ) (sign: bit 5), D~ = n·d computed in double as the
    // kernel's filters compute it, so that limit·D~ overflows by a relative δ or just
    // fails to, and the offset set so that the crossing lies at limit·(1 +
    // relative(extra2)): the overflow of limit·n·d, on either side of the crossing.
    static void construct(Input<T, Plane<T>>& in, unsigned what, unsigned amount, unsigned extra, unsigned extra2) {
        if (!all_finite(in)) return;
        Plane<T>& p = in.shape;
        Ray<T>& r = in.ray;
        const LD nn = dot(p.normal, p.normal);
        if (!(nn > 0) || !std::isfinite(nn)) return;
        if (what & 1u) {
            const LD k = dot(p.normal, r.direction) / nn * (1 - relative(extra));
            for (int j = 0; j < 3; ++j) r.direction[j] = T(LD(r.direction[j]) - k * LD(p.normal[j]));
        }
        if (what & 2u) {
            LD m = std::fabs(LD(p.offset));
            for (int j = 0; j < 3; ++j) m = std::max(m, std::fabs(LD(p.normal[j]) * LD(r.origin[j])));
            if (m > 0 && std::isfinite(m)) {
                const int e = std::numeric_limits<T>::max_exponent - 1 - int(what >> 6) - std::ilogb(m);
                p.offset = std::ldexp(p.offset, e);
                for (int j = 0; j < 3; ++j) r.origin[j] = std::ldexp(r.origin[j], e);
            }
        }
        if (what & 16u) {
            double Dd = 0;  // ((n_0 d_0 + n_1 d_1) + n_2 d_2) in double
            for (int j = 0; j < 3; ++j) Dd = Dd + double(p.normal[j]) * double(r.direction[j]);
            const LD D = dot(p.normal, r.direction);
            if (Dd != 0 && std::isfinite(Dd) && D != 0) {
                const LD edge = std::ldexp(LD(1), std::numeric_limits<double>::max_exponent) / std::fabs(LD(Dd));
                const LD lim = ((what & 32u) ? -edge : edge) * (1 + relative(amount));
                set_limit(r, what, lim);
                p.offset = T(dot(p.normal, r.origin) + LD(what & 8u ? r.t_max : r.t_min) * D * (1 + relative(extra2)));
            }
        } else if (what & 4u) {
            const LD D = dot(p.normal, r.direction), N = LD(p.offset) - dot(p.normal, r.origin);
            if (D != 0) set_limit(r, what, N / D * (1 + relative(amount)));
        }
    }
    // Sphere, what: bit 0 the origin moved across the line so that the line passes at
    // distance r(1 + δ) from the centre (near-tangent); bit 1 the origin moved along
    // its ray from the centre to distance r(1 + δ) (an end of the range near the
    // surface), δ = relative(amount); bit 2 a limit at a root of |o + t·d - c| = r (bit
    // 4: the larger one) times (1 + relative(extra)), bit 3 choosing which limit.
    static void construct(Input<T, Sphere<T>>& in, unsigned what, unsigned amount, unsigned extra, unsigned) {
        if (!all_finite(in)) return;
        Sphere<T>& s = in.shape;
        Ray<T>& r = in.ray;
        const LD rad = LD(s.radius) * (1 + relative(amount)), dd = dot(r.direction, r.direction);
        if (!(dd > 0) || !std::isfinite(dd) || !(s.radius > 0)) return;
        auto w = [&] {
            Eigen::Matrix<LD, 3, 1> v;
            for (int j = 0; j < 3; ++j) v[j] = LD(r.origin[j]) - LD(s.center[j]);
            return v;
        };
        if (what & 1u) {
            const Eigen::Matrix<LD, 3, 1> v = w();
            Eigen::Matrix<LD, 3, 1> d;
            for (int j = 0; j < 3; ++j) d[j] = LD(r.direction[j]);
            const LD along = v.dot(d) / dd;
            const Eigen::Matrix<LD, 3, 1> perp = v - along * d;
            const LD pn = perp.norm();
            if (pn > 0 && std::isfinite(pn))
                for (int j = 0; j < 3; ++j) r.origin[j] = T(LD(s.center[j]) + along * d[j] + perp[j] * (rad / pn));
        }
        if (what & 2u) {
            const Eigen::Matrix<LD, 3, 1> v = w();
            const LD vn = v.norm();
            if (vn > 0 && std::isfinite(vn))
                for (int j = 0; j < 3; ++j) r.origin[j] = T(LD(s.center[j]) + v[j] * (rad / vn));
        }
        if (what & 4u) {
            const Eigen::Matrix<LD, 3, 1> v = w();
            LD b = 0;
            for (int j = 0; j < 3; ++j) b += v[j] * LD(r.direction[j]);
            const LD disc = b * b - dd * (v.squaredNorm() - LD(s.radius) * LD(s.radius));
            if (disc >= 0 && std::isfinite(disc)) {
                const LD t = ((what & 16u) ? -b + std::sqrt(disc) : -b - std::sqrt(disc)) / dd;
                set_limit(r, what, t * (1 + relative(extra)));
            }
        }
    }

};

template <class T, class Shape> Input<T, Shape> decode(const std::uint8_t* data, std::size_t size) {
    return Decoder<T, Shape>(data, size).decode();
}

// ---------------------------------------------------------------------------------------
// Encoding (the seed corpora): a case back to bytes that decode to it bit for bit.
// FuzzedDataProvider reads integers from the end of the buffer, most significant byte
// first; the encoder records the integers in reading order and lays them out reversed.

class Encoder {
public:
    template <class U> void put(U v) {
        for (int i = int(sizeof(U)) - 1; i >= 0; --i) order_.push_back(std::uint8_t(std::uint64_t(v) >> (8 * i)));
    }
    std::vector<std::uint8_t> bytes() const { return {order_.rbegin(), order_.rend()}; }

private:
    std::vector<std::uint8_t> order_;
};

// One field, in the most compact class that reproduces its bits.
template <class T> void encode_value(Encoder& e, T x) {
    const Bits<T> bits = to_bits(x);
    for (unsigned n = 0; n < 32; ++n) {
        const T v = T((n & 1u) ? -int(n + 1) / 2 : int(n / 2));
        if (to_bits(v) == bits) return e.put(std::uint8_t(n << 3 | small_int));
    }
    const auto& sv = special_values<T>();
    for (unsigned n = 0; n < 32; ++n)
        if (to_bits(sv[n]) == bits) return e.put(std::uint8_t(n << 3 | special));
    if (std::isfinite(x) && x == std::trunc(x) && std::fabs(x) <= 32767 && to_bits(T(std::int16_t(x))) == bits) {
        e.put(std::uint8_t(int16));
        return e.put(std::uint16_t(std::int16_t(x)));
    }
    e.put(std::uint8_t(raw));
    e.put(bits);
}

// The bytes of a case: t range [decoded, decoded] (or [0, +inf) when it is that range),
// Obb axes decoded one by one, every field in its most compact class, no patches.
template <class T, class Shape> std::vector<std::uint8_t> encode(const Ray<T>& ray, const Shape& shape) {
    Input<T, Shape> in{ray, shape};
    auto f = fields(in);
    const bool default_range = to_bits(ray.t_min) == to_bits(T(0)) && ray.t_max == std::numeric_limits<T>::infinity();
    Encoder e;
    e.put(std::uint8_t((std::is_same_v<T, double> ? kDoubleBit : 0u) | ((default_range ? 0u : 3u) << kTRangeShift)));
    const int n = int(f.size()) - (default_range ? 2 : 0);
    for (int k = 0; k < n; ++k) encode_value(e, *f[k]);
    return e.bytes();
}

// ---------------------------------------------------------------------------------------
// Convex polyhedra (ray_polyhedron_fuzz): a variable number of planes, owned here.
//
//   header byte   bit 0 scalar, bits 1-2 t range, as for the other shapes (the other bits
//                 are unused)
//   plane count   one byte b: b mod 65 planes (0 to 64; none is all of space)
//   fields        per plane its normal (x, y, z) then its offset, plane by plane; then
//                 origin, direction, t_min, t_max (those the t range decodes); each one
//                 number of the classes above (copies read any earlier field: a plane
//                 equal to another, a normal copied and negated for a flat slab)
//   patches       as above, over all the fields

inline constexpr int kMaxPlanes = 64;

template <class T> struct PolyInput {
    Ray<T> ray;
    std::vector<Plane<T>> planes;
    ConvexPolyhedron<T> shape() const { return ConvexPolyhedron<T>{std::span<const Plane<T>>(planes)}; }
};

// The fields of a polyhedron input, in decoding order.
template <class T> std::vector<T*> poly_fields(PolyInput<T>& in) {
    std::vector<T*> f;
    f.reserve(4 * in.planes.size() + kRayFields);
    for (Plane<T>& q : in.planes) {
        for (int i = 0; i < 3; ++i) f.push_back(&q.normal[i]);
        f.push_back(&q.offset);
    }
    for (int i = 0; i < 3; ++i) f.push_back(&in.ray.origin[i]);
    for (int i = 0; i < 3; ++i) f.push_back(&in.ray.direction[i]);
    f.push_back(&in.ray.t_min);
    f.push_back(&in.ray.t_max);
    return f;
}

template <class T> class PolyDecoder : FieldReader {
public:
    PolyDecoder(const std::uint8_t* data, std::size_t size) : FieldReader(data, size) {}

    PolyInput<T> decode() {
        PolyInput<T> in{};
        const unsigned header = p_.ConsumeIntegral<std::uint8_t>();
        const unsigned t_style = (header >> kTRangeShift) & 3u;
        in.planes.resize(p_.ConsumeIntegral<std::uint8_t>() % unsigned(kMaxPlanes + 1),
                         Plane<T>{Vec3<T>(0, 0, 0), T(0)});
        in.ray.origin = in.ray.direction = Vec3<T>(0, 0, 0);
        const std::vector<T*> f = poly_fields(in);
        const int n = int(f.size()), t_min_field = n - 2, t_max_field = n - 1;
        constexpr T inf = std::numeric_limits<T>::infinity();
        for (int k = 0; k < n; ++k) {
            if (k == t_min_field && t_style <= 1)
                *f[k] = t_style == 0 ? T(0) : -inf;
            else if (k == t_max_field && t_style <= 2)
                *f[k] = inf;
            else
                *f[k] = value(f, k);
            done_ = k + 1;
        }
        for (int i = 0; i < kMaxPatches && p_.remaining_bytes() > 0; ++i) {
            const int dst = int(p_.ConsumeIntegral<std::uint8_t>() % unsigned(n));
            *f[dst] = value(f, n);
        }
        return in;
    }
};

template <class T> PolyInput<T> decode_polyhedron(const std::uint8_t* data, std::size_t size) {
    return PolyDecoder<T>(data, size).decode();
}

// The bytes of a polyhedron case (at most kMaxPlanes planes): t range [decoded, decoded]
// (or [0, +inf) when it is that range), every field in its most compact class, no patches.
template <class T> std::vector<std::uint8_t> encode_polyhedron(const Ray<T>& ray, std::span<const Plane<T>> planes) {
    PolyInput<T> in{ray, {planes.begin(), planes.end()}};
    const std::vector<T*> f = poly_fields(in);
    const bool default_range = to_bits(ray.t_min) == to_bits(T(0)) && ray.t_max == std::numeric_limits<T>::infinity();
    Encoder e;
    e.put(std::uint8_t((std::is_same_v<T, double> ? kDoubleBit : 0u) | ((default_range ? 0u : 3u) << kTRangeShift)));
    e.put(std::uint8_t(planes.size()));
    const std::size_t n = f.size() - (default_range ? 2 : 0);
    for (std::size_t k = 0; k < n; ++k) encode_value(e, *f[k]);
    return e.bytes();
}

}  // namespace rayproof::fuzz
