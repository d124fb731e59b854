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
// rounding issue for the bound, which counts both), used only by fast-mode lanes.
//
// Every query that takes a Ray also takes a PreparedRay and answers the same: in
// certified mode bit for bit (verdict, t_enter, t_exit, face); in conservative mode
// within the mode's contract; fast mode promises nothing (../docs/semantics.md). The
// prepared ray keeps its own copy of the ray: it may outlive the Ray it was made from.
#pragma once

#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/validate.hpp>
#include <rayproof/types.hpp>

#include <cmath>
#include <limits>

namespace rayproof {

template <class T> class PreparedRay {
    static_assert(is_scalar_v<T>, "PreparedRay<T>: T is float or double");

public:
    explicit PreparedRay(const Ray<T>& ray) noexcept : ray_(ray), valid_(detail::valid(ray)) {
        bool normal = true;
        for (int i = 0; i < 3; ++i) {
            const double d = double(ray.direction[i]);
            // 1/±0 is ±inf, the sign of the zero: IEEE division, no trap in the default
            // environment.
            rinv_[i] = 1.0 / d;
            finv_[i] = T(rinv_[i]);
            negative_[i] = std::signbit(ray.direction[i]);
            const double a = std::abs(rinv_[i]);
            normal &= bool(int(a >= std::numeric_limits<double>::min()) & int(a <= std::numeric_limits<double>::max()));
        }
        normal_ = normal & valid_;
    }

    [[nodiscard]] const Ray<T>& ray() const noexcept { return ray_; }
    // The contract's validity of the ray (an invalid ray is answered Verdict::invalid by
    // every query that takes it).
    [[nodiscard]] bool valid() const noexcept { return valid_; }
    // fl(1/d_i) in double; ±inf for d_i = ±0.
    [[nodiscard]] double rinv(int i) const noexcept { return rinv_[i]; }
    [[nodiscard]] const double* rinv() const noexcept { return rinv_; }
    // fl_T(1/d_i): the double reciprocal rounded to T (T = double: the same value).
    [[nodiscard]] T inv(int i) const noexcept { return finv_[i]; }
    [[nodiscard]] const T* inv() const noexcept { return finv_; }
    // The sign bit of d_i (1 for -0 too).
    [[nodiscard]] bool negative(int i) const noexcept { return negative_[i]; }
    // The ray is valid and every fl(1/d_i) is normal and finite: the relative bound u
    // above holds on all three axes.
    [[nodiscard]] bool reciprocals_normal() const noexcept { return normal_; }

private:
    Ray<T> ray_;
    double rinv_[3];
    T finv_[3];
    bool negative_[3];
    bool valid_;
    bool normal_;
};

template <class T> PreparedRay(const Ray<T>&) -> PreparedRay<T>;

}  // namespace rayproof
