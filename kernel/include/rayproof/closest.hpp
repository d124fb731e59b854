// rayproof/closest.hpp — one ray against many primitives: the closest hit and any hit,
// by brute force over every primitive. The reference every acceleration structure
// (bvh.hpp) must equal.
//
// Question:  among the primitives prims[0..n) (Aabb, Obb, Sphere, ConvexPolyhedron,
//            Plane), the one the ray enters first, and whether the ray meets any.
// Meaning (docs/semantics.md, "Closest hit over many primitives"):
//   closest_hit, certified: the primitive with the smallest EXACT t_enter, ties to the
//            lowest index; its Hit is the primitive's own certified Hit. Faithfully
//            rounded values cannot always order two entries (equal or adjacent floats):
//            those pairs are decided exactly (detail/entry_order.hpp).
//   closest_hit, fast / conservative: the smallest t_enter as that mode computes it, ties
//            to the lowest index (conservative: never a miss when some primitive is hit
//            exactly, since no primitive's own answer misses then).
//   any_hit:  hit iff some primitive is hit in the mode (certified: exactly); index = the
//            lowest primitive hit, its own Hit in the mode.
// Algorithm: one pass in index order keeping the best hit so far; a later primitive
//            replaces it only when strictly closer (so ties stay with the lower index):
//            certified by compare_entry (the faithful floats' filter, else the exact entries
//            compared with Shewchuk expansions or BigDyadic8), the other modes by their
//            computed t_enter. any_hit stops at the first primitive hit.
// Degenerate cases: an invalid primitive is never hit (it is skipped); the ray alone
//            decides Verdict::invalid (index -1). No primitives: a miss.
// Error bound: none of its own; every t is the primitive's own answer in the mode.
#pragma once

#include <rayproof/detail/entry_order.hpp>
#include <rayproof/detail/fp_env.hpp>
#include <rayproof/intersect.hpp>
#include <rayproof/prepared_ray.hpp>
#include <rayproof/types.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>
#include <variant>

namespace rayproof {

template <class T> struct ClosestHit {
    Verdict verdict = Verdict::miss;  // invalid only when the ray is invalid
    std::int64_t index = -1;          // the primitive hit, -1 otherwise
    Hit<T> hit;                       // that primitive's own answer in the mode
    [[nodiscard]] explicit operator bool() const noexcept { return verdict == Verdict::hit; }
};

// The primitives' span, not a deduced parameter: T comes from the ray, so a
// std::vector<Primitive<T>> or an array converts to it.
template <class T> using PrimitiveSpan = std::span<const Primitive<std::type_identity_t<T>>>;

namespace detail {

// The primitive's own answer in the mode (an invalid primitive answers Verdict::invalid,
// and so does a variant left valueless by an exception), in the environment the caller
// holds (closest_hit and any_hit here, the BVH's traversal in bvh.hpp): intersect()'s
// query without its per-call read (query_in_env, intersect.hpp). A switch over the
// alternatives rather than std::visit, so that it inlines into the traversal loop.
template <class T, class Mode>
RAYPROOF_ALWAYS_INLINE Hit<T> intersect_primitive(const PreparedRay<T>& ray, const Primitive<T>& p, Mode mode) noexcept {
    static_assert(std::variant_size_v<Primitive<T>> == 5, "one case per alternative of Primitive");
    switch (p.index()) {
        case 0: return query_in_env(ray, *std::get_if<0>(&p), mode);
        case 1: return query_in_env(ray, *std::get_if<1>(&p), mode);
        case 2: return query_in_env(ray, *std::get_if<2>(&p), mode);
        case 3: return query_in_env(ray, *std::get_if<3>(&p), mode);
        case 4: return query_in_env(ray, *std::get_if<4>(&p), mode);
        default: return invalid_hit<T>();  // valueless: not a primitive
    }
}

template <class T> ClosestHit<T> invalid_closest() {
    ClosestHit<T> c;
    c.verdict = Verdict::invalid;
    c.hit = invalid_hit<T>();
    return c;
}

template <class T, class Mode>
ClosestHit<T> closest_hit_brute(const PreparedRay<T>& ray, std::span<const Primitive<T>> prims) {
    if (!ray.valid()) return invalid_closest<T>();
    ClosestHit<T> best;
    for (std::size_t i = 0; i < prims.size(); ++i) {
        const Hit<T> h = intersect_primitive(ray, prims[i], Mode{});
        if (h.verdict != Verdict::hit) continue;  // a miss, or an invalid primitive: skipped
        bool better = best.index < 0;
        if (!better) {
            if constexpr (std::is_same_v<Mode, certified_t>)
                better = compare_entry(ray, prims[i], h, prims[std::size_t(best.index)], best.hit) < 0;
            else
                better = h.t_enter < best.hit.t_enter;  // strict: ties stay with the lower index
        }
        if (better) {
            best.verdict = Verdict::hit;
            best.index = std::int64_t(i);
            best.hit = h;
        }
    }
    return best;
}

template <class T, class Mode>
ClosestHit<T> any_hit_brute(const PreparedRay<T>& ray, std::span<const Primitive<T>> prims) {
    if (!ray.valid()) return invalid_closest<T>();
    for (std::size_t i = 0; i < prims.size(); ++i) {
        const Hit<T> h = intersect_primitive(ray, prims[i], Mode{});
        if (h.verdict == Verdict::hit) return ClosestHit<T>{Verdict::hit, std::int64_t(i), h};
    }
    return ClosestHit<T>{};
}

}  // namespace detail

// closest_hit / any_hit: see the header comment. The certified and conservative forms
// answer in the default floating-point environment whatever the caller's (detail/fp_env.hpp).
template <class T, class Mode>
    requires(is_scalar_v<T> && is_mode_v<Mode>)
[[nodiscard]] ClosestHit<T> closest_hit(const PreparedRay<T>& ray, PrimitiveSpan<T> prims, Mode mode) {
    static_cast<void>(mode);
    if constexpr (detail::fp_env_guarded<Mode>)
        return detail::in_default_fp_env(
            [](const PreparedRay<T>& r, const std::span<const Primitive<T>>& p) { return detail::closest_hit_brute<T, Mode>(r, p); },
            ray, prims);
    else
        return detail::closest_hit_brute<T, Mode>(ray, prims);
}

template <class T, class Mode>
    requires(is_scalar_v<T> && is_mode_v<Mode>)
[[nodiscard]] ClosestHit<T> any_hit(const PreparedRay<T>& ray, PrimitiveSpan<T> prims, Mode mode) {
    static_cast<void>(mode);
    if constexpr (detail::fp_env_guarded<Mode>)
        return detail::in_default_fp_env(
            [](const PreparedRay<T>& r, const std::span<const Primitive<T>>& p) { return detail::any_hit_brute<T, Mode>(r, p); },
            ray, prims);
    else
        return detail::any_hit_brute<T, Mode>(ray, prims);
}

template <class T, class Mode>
    requires(is_scalar_v<T> && is_mode_v<Mode>)
[[nodiscard]] ClosestHit<T> closest_hit(const Ray<T>& ray, PrimitiveSpan<T> prims, Mode mode) {
    return closest_hit(PreparedRay<T>(ray), prims, mode);
}

template <class T, class Mode>
    requires(is_scalar_v<T> && is_mode_v<Mode>)
[[nodiscard]] ClosestHit<T> any_hit(const Ray<T>& ray, PrimitiveSpan<T> prims, Mode mode) {
    return any_hit(PreparedRay<T>(ray), prims, mode);
}

}  // namespace rayproof
