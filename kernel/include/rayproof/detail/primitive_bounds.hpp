// rayproof/detail/primitive_bounds.hpp — a box that contains a primitive exactly, for
// the bounding volumes of a BVH.
//
// Question:  enclosing_box(p): an Aabb B with S ⊆ B, S the exact solid of p (the
//            contract's meaning, every input number exact). B need not be tight: an
//            acceleration structure only needs never to cull a primitive the ray meets.
// Answer:    std::nullopt when no finite box is given: planes (unbounded), invalid
//            primitives, and any primitive whose box would overflow to infinity. A BVH
//            keeps those beside its tree and tests them on every ray, still correct.
// Rounding:  every computed bound is rounded outward by the derivation at its code; the
//            exact bound lies inside the returned one.
#pragma once

#include <rayproof/detail/entry_order.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/detail/validate.hpp>
#include <rayproof/types.hpp>

#include <cmath>
#include <optional>
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

// Not boxed here: kept beside the tree (still answered exactly by their own queries).
template <class T> std::optional<Aabb<T>> box_of(const Obb<T>&) { return std::nullopt; }
template <class T> std::optional<Aabb<T>> box_of(const ConvexPolyhedron<T>&) { return std::nullopt; }

// A plane is unbounded.
template <class T> std::optional<Aabb<T>> box_of(const Plane<T>&) { return std::nullopt; }

template <class T> std::optional<Aabb<T>> enclosing_box(const Primitive<T>& p) {
    return std::visit([](const auto& shape) { return box_of(shape); }, p);
}

}  // namespace rayproof::detail
