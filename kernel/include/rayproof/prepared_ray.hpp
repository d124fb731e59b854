// rayproof/prepared_ray.hpp — one ray prepared once, to be asked against many shapes (a
// BVH's boxes, a scene's objects).
//
// What is decided once: the ray's validity (the contract's rules, detail/validate.hpp),
// the reciprocal directions rinv_i = fl(1/d_i) computed in double (for float rays too:
// every finite nonzero float has a normal, finite double reciprocal), the sign of each
// d_i, and whether the reciprocals are usable by the straight-line filters:
//   - |fl(1/d_i) - 1/d_i| <= u|1/d_i| (u = 2^-53, one correctly rounded division)
//     holds while 1/d_i is normal and finite, i.e. |d_i| < 2^1022 and d_i != 0; the
//     flag reciprocals_normal() says so for all three axes at once;
//   - d_i = ±0 gives rinv_i = ±inf (the sign of the zero), which the slab code reads as
//     "parallel to slab i" and decides exactly on the origin, never through 0·inf.
// For the float packets (ray_aabb_packet.hpp) the same reciprocals rounded to float,
// finv_i = fl_float(1/d_i), are kept too: two roundings, |finv_i - 1/d_i| <= gamma_f(2)
// |1/d_i| (u_f = 2^-24, the double quotient then its rounding to float; no double
// rounding issue for the bound, which counts both), used by the fast lanes and by the
// certified packets' float filter, whose bound counts both roundings. Which arithmetic
// a packet's or a BVH node's filter may take the ray into is decided here too
// (reciprocals_usable_in<E>): each axis either parallel or with its reciprocal in E
// normal and finite; the packets used to decide it again for every packet. So are the
// parallel axes (parallel_axes), which the fast lanes would otherwise test per packet.
//
// Every query that takes a Ray also takes a PreparedRay and answers the same: in
// certified mode bit for bit (verdict, t_enter, t_exit, face); in conservative mode
// within the mode's contract; fast mode promises nothing (../docs/semantics.md). The
// prepared ray keeps its own copy of the ray: it may outlive the Ray it was made from.
// What the queries take from it (each shape's detail::query on a Ray or a PreparedRay,
// detail::RayOrPrepared below): every shape its validity, with no test per query; the
// Aabb its reciprocals, in the certified and conservative modes the double ones (the
// very values the Ray paths divide out per query, so the same decisions and the same
// bits, the straight-line path declining exactly what it declines for the Ray), in fast
// mode the ones rounded to T (for float one rounding more than T(1)/d_i).
// Decided in the default floating-point environment, whatever the caller's, as the
// certified and conservative queries answer (detail/fp_env.hpp).
#pragma once

#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/fp_env.hpp>
#include <rayproof/detail/validate.hpp>
#include <rayproof/types.hpp>

#include <cmath>
#include <concepts>
#include <limits>
#include <type_traits>

namespace rayproof {

template <class T> class PreparedRay {
    static_assert(is_scalar_v<T>, "PreparedRay<T>: T is float or double");

public:
    // Decided in the default floating-point environment whatever the caller's (as the
    // guarded queries answer, detail/fp_env.hpp): a directed rounding mode would round
    // the reciprocals otherwise, and denormals-are-zero would read a subnormal d_i as 0.
    explicit PreparedRay(const Ray<T>& ray) noexcept
        : ray_(ray), k_(detail::fp_env_is_default() ? decide(ray) : detail::in_established_fp_env(&decide, ray)) {}

    [[nodiscard]] const Ray<T>& ray() const noexcept { return ray_; }
    // The contract's validity of the ray (an invalid ray is answered Verdict::invalid by
    // every query that takes it).
    [[nodiscard]] bool valid() const noexcept { return k_.valid; }
    // fl(1/d_i) in double; ±inf for d_i = ±0.
    [[nodiscard]] double rinv(int i) const noexcept { return k_.rinv[i]; }
    [[nodiscard]] const double* rinv() const noexcept { return k_.rinv; }
    // fl_T(1/d_i): the double reciprocal rounded to T (T = double: the same value).
    [[nodiscard]] T inv(int i) const noexcept { return k_.finv[i]; }
    [[nodiscard]] const T* inv() const noexcept { return k_.finv; }
    // The sign bit of d_i (1 for -0 too).
    [[nodiscard]] bool negative(int i) const noexcept { return k_.negative[i]; }
    // The ray is valid and every fl(1/d_i) is normal and finite: the relative bound u
    // above holds on all three axes.
    [[nodiscard]] bool reciprocals_normal() const noexcept { return k_.normal; }
    // Bit i set when d_i = ±0 (the ray parallel to slab i): the box packets' fast lanes
    // test no axis for it when none is.
    [[nodiscard]] unsigned parallel_axes() const noexcept { return k_.parallel; }
    // Each axis either parallel (d_i = ±0) or with its reciprocal in E normal and finite: in
    // double rinv_i, in float fl_float(rinv_i) (= inv(i) for a float ray; double: |d| <
    // 2^1022, float: 2^-128 <= |d| <= 2^126, up to the roundings of the reciprocal). The
    // box packets' and the BVH's filters in E take the ray into their lanes only then
    // (ray_aabb_packet.hpp: the relative bound of the reciprocal holds on every axis that
    // is not parallel). Independent of the range and of the origin. Decided here once,
    // not per packet (measured, certified float W = 8 on shuffled pairs: 1.67 ns a box
    // test with three per-axis tests in every call, 1.33 with this flag).
    template <class E> [[nodiscard]] bool reciprocals_usable_in() const noexcept {
        static_assert(is_scalar_v<E>, "reciprocals_usable_in<E>: E is float or double");
        if constexpr (std::is_same_v<E, double>) return k_.usable_double;
        else return k_.usable_float;
    }

    // The same ray on [t_min, t_max] instead: the reciprocals and the origin's and
    // direction's checks kept, validity re-decided for the new range (valid_range:
    // comparisons only, exact in every floating-point environment). Equal, in every
    // field, to PreparedRay(Ray{origin, direction, t_min, t_max}): what a BVH traversal
    // uses to test its nodes on a range it narrows as hits are found.
    [[nodiscard]] PreparedRay with_range(T t_min, T t_max) const noexcept {
        PreparedRay r(*this);
        r.ray_.t_min = t_min;
        r.ray_.t_max = t_max;
        r.k_.valid = k_.valid_apart_from_range & detail::valid_range(r.ray_);
        r.k_.normal = k_.normal_apart_from_range & r.k_.valid;
        return r;
    }

private:
    struct Decided {
        double rinv[3];
        T finv[3];
        bool negative[3];
        bool valid;
        bool normal;
        bool valid_apart_from_range;   // the origin finite, the direction finite and nonzero
        bool normal_apart_from_range;  // every fl(1/d_i) normal and finite
        bool usable_double, usable_float;  // reciprocals_usable_in<double>, <float>
        unsigned char parallel;            // parallel_axes()
    };
    static Decided decide(const Ray<T>& ray) noexcept {
        Decided k;
        k.valid = detail::valid(ray);
        const T* dir = ray.direction.data();
        k.valid_apart_from_range = bool(int(detail::finite_probe(ray.origin.data()) == 0) &
                                        int(detail::finite_probe(dir) == 0) & int(detail::nonzero3(dir)));
        bool normal = true, usable_float = true, usable_double = true;
        unsigned parallel_axes = 0;
        for (int i = 0; i < 3; ++i) {
            const double d = double(ray.direction[i]);
            // 1/±0 is ±inf, the sign of the zero: IEEE division, no trap in the default
            // environment.
            k.rinv[i] = 1.0 / d;
            k.finv[i] = T(k.rinv[i]);
            k.negative[i] = std::signbit(ray.direction[i]);
            const double a = std::abs(k.rinv[i]);
            const float af = std::abs(float(k.rinv[i]));
            const bool normal_i =
                bool(int(a >= std::numeric_limits<double>::min()) & int(a <= std::numeric_limits<double>::max()));
            const bool parallel = d == 0;
            parallel_axes |= unsigned(parallel) << i;
            normal &= normal_i;
            usable_double &= parallel | normal_i;
            usable_float &= parallel | bool(int(af >= std::numeric_limits<float>::min()) &
                                            int(af <= std::numeric_limits<float>::max()));
        }
        k.usable_double = usable_double;
        k.usable_float = usable_float;
        k.parallel = static_cast<unsigned char>(parallel_axes);
        k.normal_apart_from_range = normal & k.valid_apart_from_range;
        k.normal = normal & k.valid;
        return k;
    }

    Ray<T> ray_;
    Decided k_;
};

template <class T> PreparedRay(const Ray<T>&) -> PreparedRay<T>;

namespace detail {
// The shapes' query paths take either a Ray or a PreparedRay (R below): ray_of(r) is the
// ray itself, valid(r) its validity (for a PreparedRay the one decided at preparation,
// no test per query), and each path reads from a PreparedRay what it decided (the Aabb's
// reciprocals, ray_aabb.hpp) instead of computing it again: the same values, so the same
// answers.
template <class R, class T> concept RayOrPrepared = std::same_as<R, Ray<T>> || std::same_as<R, PreparedRay<T>>;
template <class T> RAYPROOF_ALWAYS_INLINE const Ray<T>& ray_of(const Ray<T>& r) noexcept { return r; }
template <class T> RAYPROOF_ALWAYS_INLINE const Ray<T>& ray_of(const PreparedRay<T>& r) noexcept { return r.ray(); }
template <class T> RAYPROOF_ALWAYS_INLINE bool valid(const PreparedRay<T>& r) noexcept { return r.valid(); }
template <class R> inline constexpr bool is_prepared_ray_v = false;
template <class T> inline constexpr bool is_prepared_ray_v<PreparedRay<T>> = true;
}  // namespace detail

}  // namespace rayproof
