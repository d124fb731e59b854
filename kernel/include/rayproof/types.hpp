// rayproof/types.hpp — the public value types, the verdict and the mode tags.
//
// The names and their meaning are fixed by the contract (docs/semantics.md):
//   Ray    o + t·d for real t in [t_min, t_max]
//   Aabb   the closed box lo <= p <= hi (a flat box, lo == hi on an axis, is valid)
//   Obb    the closed solid { p : |(p - center)·a_i| <= half_extent_i }, a_i the
//          i-th column of `axes` exactly as stored (never re-normalized)
//   Plane  the surface normal·p == offset
//   Sphere the closed ball |p - center| <= radius (radius 0 is a point)
//   ConvexPolyhedron  the closed solid { p : n_k·p <= offset_k for every plane k }
//          (normals point out; no planes: all of space; an infeasible set: empty)
// Every input number is taken as the exact real number its value denotes (-0 is 0).
#pragma once

#include <rayproof/detail/fp_model.hpp>

#include <Eigen/Core>

#include <limits>
#include <optional>
#include <span>
#include <ostream>
#include <string_view>
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

// Does not own its planes: the caller's array outlives every query on it.
template <class T> struct ConvexPolyhedron {
    std::span<const Plane<T>> planes;
};

enum class Verdict { miss, hit, invalid };

template <class T> struct Hit {
    Verdict verdict = Verdict::miss;
    T t_enter = 0, t_exit = 0;  // meaningful when verdict == hit
    int face = -1;              // boxes: entry face 2*axis + side (0: lo / -axis, 1: hi / +axis);
                                // polyhedra: index of the entry plane; -1 otherwise
    [[nodiscard]] explicit operator bool() const noexcept { return verdict == Verdict::hit; }
};

// The three modes chosen at run time: intersect(ray, shape, RuntimeMode) and
// verdict(...) (intersect.hpp) dispatch to the tag of the same name below, with the
// tag's answer bit for bit. A value outside the three enumerators is answered
// Verdict::invalid. (Declared before the tags: g++ -Wshadow takes an enumerator declared
// after a namespace-scope variable of the same name for a shadowing declaration.)
enum class RuntimeMode { fast, conservative, certified };

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
    std::is_same_v<S, Sphere<T>> || std::is_same_v<S, ConvexPolyhedron<T>>;

[[nodiscard]] constexpr const char* to_string(Verdict v) noexcept {
    switch (v) {
        case Verdict::miss: return "miss";
        case Verdict::hit: return "hit";
        case Verdict::invalid: return "invalid";
    }
    return "?";
}
[[nodiscard]] constexpr const char* mode_name(fast_t) noexcept { return "fast"; }
[[nodiscard]] constexpr const char* mode_name(conservative_t) noexcept { return "conservative"; }
[[nodiscard]] constexpr const char* mode_name(certified_t) noexcept { return "certified"; }

// The one dispatch from a RuntimeMode to its tag: f(tag) for the three enumerators,
// on_invalid() for any other value (both must return the same type). The run-time forms
// of intersect and verdict, and the tracer and the Python bindings, all go through it.
template <class F, class G>
constexpr decltype(auto) with_mode(RuntimeMode mode, F&& f, G&& on_invalid) {
    switch (mode) {
        case RuntimeMode::fast: return f(fast);
        case RuntimeMode::conservative: return f(conservative);
        case RuntimeMode::certified: return f(certified);
    }
    return on_invalid();
}

// The tag's name ("fast", "conservative", "certified"); "?" outside the three.
[[nodiscard]] constexpr const char* to_string(RuntimeMode m) noexcept {
    return with_mode(m, [](auto tag) { return mode_name(tag); }, [] { return "?"; });
}
[[nodiscard]] constexpr const char* mode_name(RuntimeMode m) noexcept { return to_string(m); }

// The mode of that exact name (as to_string prints it, case-sensitive), else nullopt.
[[nodiscard]] constexpr std::optional<RuntimeMode> parse_mode(std::string_view name) noexcept {
    for (const RuntimeMode m : {RuntimeMode::fast, RuntimeMode::conservative, RuntimeMode::certified})
        if (name == to_string(m)) return m;
    return std::nullopt;
}

inline std::ostream& operator<<(std::ostream& os, Verdict v) { return os << to_string(v); }
inline std::ostream& operator<<(std::ostream& os, RuntimeMode m) { return os << to_string(m); }

}  // namespace rayproof
