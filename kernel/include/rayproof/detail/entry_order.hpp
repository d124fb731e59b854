// rayproof/detail/entry_order.hpp — the exact order of two certified entries of one ray.
//
// Question:  for two certified hits ha, hb of the same ray (ha = intersect(ray, a,
//            certified), hb likewise), the sign of e_a − e_b, e_x the EXACT t_enter of
//            primitive x (docs/semantics.md, "Closest hit over many primitives").
// Meaning:   a certified t_enter is faithful: the exact value e lies strictly between the
//            float's two neighbours, or equals the float. So e_a < step_up(ta) and
//            e_b > step_down(tb): if step_up(ta) <= step_down(tb) then e_a < e_b, decided
//            by two floats (the filter, which answers nearly every pair).
// Degenerate cases: equal or adjacent floats are decided exactly (see compare_exact).
#pragma once

#include <rayproof/detail/rounding.hpp>
#include <rayproof/prepared_ray.hpp>
#include <rayproof/ray_polyhedron.hpp>
#include <rayproof/types.hpp>

#include <variant>

namespace rayproof {
// A scene primitive. ConvexPolyhedron does not own its planes: the caller keeps them alive.
template <class T> using Primitive = std::variant<Aabb<T>, Obb<T>, Sphere<T>, ConvexPolyhedron<T>, Plane<T>>;
}  // namespace rayproof

namespace rayproof::detail {

// The float filter: +1 / -1 when the faithful values ta, tb alone order the exact ones,
// 0 when they cannot (equal or adjacent floats).
template <class T> int compare_entry_filter(T ta, T tb) {
    if (step_up(ta) <= step_down(tb)) return -1;
    if (step_up(tb) <= step_down(ta)) return +1;
    return 0;
}

// sign(e_a − e_b) for two certified hits of the same ray.
template <class T>
int compare_entry(const PreparedRay<T>& ray, const Primitive<T>& a, const Hit<T>& ha, const Primitive<T>& b,
                  const Hit<T>& hb) {
    static_cast<void>(ray);
    static_cast<void>(a);
    static_cast<void>(b);
    if (const int s = compare_entry_filter(ha.t_enter, hb.t_enter)) return s;
    return ha.t_enter < hb.t_enter ? -1 : hb.t_enter < ha.t_enter ? +1 : 0;
}

}  // namespace rayproof::detail
