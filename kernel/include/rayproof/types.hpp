// rayproof/types.hpp — the public value types, the verdict and the mode tags.
//
// The names and their meaning are fixed by the contract (docs/semantics.md):
//   Ray    o + t·d for real t in [t_min, t_max]
//   Aabb   the closed box lo <= p <= hi (a flat box, lo == hi on an axis, is valid)
//   Obb    the closed solid { p : |(p - center)·a_i| <= half_extent_i }, a_i the
//          i-th column of `axes` exactly as stored (never re-normalized)
//   Plane  the surface normal·p == offset
//   Sphere the closed ball |p - center| <= radius (radius 0 is a point)
// Every input number is taken as the exact real number its value denotes (-0 is 0).
#pragma once

#include <Eigen/Core>

#include <limits>
#include <ostream>
#include <type_traits>

namespace rayproof {

template <class T> using Vec3 = Eigen::Matrix<T, 3, 1>;
template <class T> using Mat3 = Eigen::Matrix<T, 3, 3>;

template <class T> struct Ray {
    Vec3<T> origin;
    Vec3<T> direction;
    T t_min = 0;
    T t_max = std::numeric_limits<T>::infinity();
};

template <class T> struct Aabb {
    Vec3<T> lo;
    Vec3<T> hi;
};

template <class T> struct Obb {
    Vec3<T> center;
    Eigen::Matrix<T, 3, 3> axes;  // one box axis per column, used exactly as stored
    Vec3<T> half_extent;
};

template <class T> struct Plane {
    Vec3<T> normal;
    T offset;  // the points p with normal·p == offset
};

template <class T> struct Sphere {
    Vec3<T> center;
    T radius;
};

enum class Verdict { miss, hit, invalid };

template <class T> struct Hit {
    Verdict verdict = Verdict::miss;
    T t_enter = 0, t_exit = 0;  // meaningful when verdict == hit
    int face = -1;              // boxes: entry face 2*axis + side (0: lo / -axis, 1: hi / +axis); -1 otherwise
    explicit operator bool() const { return verdict == Verdict::hit; }
};

// Mode tags. `fast`: plain floating point, no promise (error rate measured).
// `conservative`: never misses an exact hit, [t_enter, t_exit] encloses the exact interval.
// `certified`: verdict and face exact, t_enter and t_exit faithfully rounded.
inline constexpr struct fast_t {} fast;
inline constexpr struct conservative_t {} conservative;
inline constexpr struct certified_t {} certified;

template <class T> inline constexpr bool is_scalar_v = std::is_same_v<T, float> || std::is_same_v<T, double>;
template <class M> inline constexpr bool is_mode_v =
    std::is_same_v<M, fast_t> || std::is_same_v<M, conservative_t> || std::is_same_v<M, certified_t>;
template <class S, class T> inline constexpr bool is_shape_v =
    std::is_same_v<S, Aabb<T>> || std::is_same_v<S, Obb<T>> || std::is_same_v<S, Plane<T>> ||
    std::is_same_v<S, Sphere<T>>;

inline const char* to_string(Verdict v) {
    switch (v) {
        case Verdict::miss: return "miss";
        case Verdict::hit: return "hit";
        case Verdict::invalid: return "invalid";
    }
    return "?";
}
inline const char* mode_name(fast_t) { return "fast"; }
inline const char* mode_name(conservative_t) { return "conservative"; }
inline const char* mode_name(certified_t) { return "certified"; }

inline std::ostream& operator<<(std::ostream& os, Verdict v) { return os << to_string(v); }

}  // namespace rayproof
