// rayproof/intersect.hpp — the public entry points: one ray or a batch of rays against
// one shape, in one of the three modes. The scalar and the batch forms share one code
// path (detail::query on a prepared shape, declared by the shape headers included
// below), so they cannot disagree.
//
// In the certified and conservative modes every entry point answers in the default
// floating-point environment whatever the caller's (detail/fp_env.hpp): it reads the
// control state once per call (once per batch), and only when that differs from the
// default does it switch, answer and restore the caller's state (a scalar query inline,
// a batch out of line). The scalar forms also take an FpEnvScope as their last argument
// (fp_env_scope.hpp): the scope has established the environment, and they do not read it.
#pragma once

#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/fp_env.hpp>
#include <rayproof/detail/ray_aabb_batch.hpp>
#include <rayproof/detail/ray_plane_batch.hpp>
#include <rayproof/fp_env_scope.hpp>
#include <rayproof/prepared_ray.hpp>
#include <rayproof/ray_aabb.hpp>
#include <rayproof/ray_obb.hpp>
#include <rayproof/ray_plane.hpp>
#include <rayproof/ray_polyhedron.hpp>
#include <rayproof/ray_sphere.hpp>
#include <rayproof/types.hpp>

#include <concepts>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <stdexcept>
#include <type_traits>

namespace rayproof {

namespace detail {
// A batch form's precondition failed (out.size() != rays.size()): throws
// std::invalid_argument(what) when exceptions are enabled; compiled with them disabled
// (-fno-exceptions, no __cpp_exceptions), prints `what` on stderr and calls std::abort.
[[noreturn]] inline void batch_size_mismatch(const char* what) {
#if defined(__cpp_exceptions)
    throw std::invalid_argument(what);
#else
    std::fputs(what, stderr);
    std::fputc('\n', stderr);
    std::abort();
#endif
}
}  // namespace detail

// True when the kernel answers this combination: every shape, scalar type and mode the
// contract names.
template <class T, class Shape, class Mode>
concept Answerable = is_scalar_v<T> && is_shape_v<Shape, T> && is_mode_v<Mode> &&
    requires(const Ray<T>& r, const Shape& s, Mode m) {
        { detail::query(r, detail::prepare(s), m) } -> std::same_as<Hit<T>>;
    };

namespace detail {
// The verdict alone, for shapes and modes without a verdict path of their own: the full
// query's verdict (the rest of its answer is dead code the compiler drops where it can).
// R is a Ray or a PreparedRay.
template <class R, class Prepared, class Mode>
    requires requires(const R& r, const Prepared& p, Mode mode) { query(r, p, mode); }
RAYPROOF_ALWAYS_INLINE Verdict verdict_query(const R& r, const Prepared& p, Mode mode) noexcept {
    return query(r, p, mode).verdict;
}

// The shape's query path takes the ray R itself (always, for a Ray; for a PreparedRay
// where the shape has a prepared path, else the prepared ray's copy of its Ray is asked).
template <class R, class Shape, class Mode>
concept DirectPath = requires(const R& r, const Shape& s, Mode m) { query(r, prepare(s), m); };
template <class T, class Shape, class Mode> concept PreparedPath = DirectPath<PreparedRay<T>, Shape, Mode>;

// What every scalar entry point below computes once the environment is in place: the
// guarded forms run it inside their guard, the FpEnvScope forms inside the scope's
// environment. Code that already holds the default environment for a whole loop (a
// packet's scalar lanes, the BVH, the brute-force closest hit) calls these directly, so
// its per-item answers are the entry points' bit for bit without a read per item.
template <class R, class Shape, class Mode>
[[nodiscard]] RAYPROOF_ALWAYS_INLINE auto query_in_env(const R& ray, const Shape& shape, Mode mode) noexcept {
    if constexpr (DirectPath<R, Shape, Mode>)
        return query(ray, prepare(shape), mode);
    else
        return query(ray.ray(), prepare(shape), mode);
}
template <class R, class Shape, class Mode>
[[nodiscard]] RAYPROOF_ALWAYS_INLINE Verdict verdict_in_env(const R& ray, const Shape& shape, Mode mode) noexcept {
    if constexpr (DirectPath<R, Shape, Mode>)
        return verdict_query(ray, prepare(shape), mode);
    else
        return verdict_query(ray.ray(), prepare(shape), mode);
}

// An entry point's body: Q (query_in_env or verdict_in_env, as a functor) under the
// guard, in the scope, or plain for the fast mode.
struct QueryInEnv {
    template <class R, class Shape, class Mode>
    RAYPROOF_ALWAYS_INLINE auto operator()(const R& r, const Shape& s, Mode m) const noexcept {
        return query_in_env(r, s, m);
    }
};
struct VerdictInEnv {
    template <class R, class Shape, class Mode>
    RAYPROOF_ALWAYS_INLINE Verdict operator()(const R& r, const Shape& s, Mode m) const noexcept {
        return verdict_in_env(r, s, m);
    }
};
template <class Q, class R, class Shape, class Mode>
[[nodiscard]] RAYPROOF_ALWAYS_INLINE auto guarded_entry(const R& ray, const Shape& shape, Mode mode) noexcept {
    if constexpr (fp_env_guarded<Mode>)
        return in_default_fp_env_inline(
            [](const R& r, const Shape& s) RAYPROOF_INLINE_LAMBDA { return Q{}(r, s, Mode{}); }, ray, shape);
    else
        return Q{}(ray, shape, mode);
}
template <class Q, class R, class Shape, class Mode>
[[nodiscard]] RAYPROOF_ALWAYS_INLINE auto scoped_entry(const R& ray, const Shape& shape, Mode mode) noexcept {
    if constexpr (fp_env_guarded<Mode>)
        return in_fp_env_scope([](const R& r, const Shape& s) RAYPROOF_INLINE_LAMBDA { return Q{}(r, s, Mode{}); },
                               ray, shape);
    else
        return Q{}(ray, shape, mode);
}
}  // namespace detail

// R is Ray or PreparedRay in every form below (and in the batch and run-time forms).
// A PreparedRay (prepared_ray.hpp) gets the same answers as its Ray: in certified mode bit
// for bit, in conservative mode within the mode's contract. Each shape's query path
// takes the prepared ray itself (detail::query on a PreparedRay: no validation per
// query, the Aabb's reciprocals as prepared); a shape without such a path answers through
// its Ray path on the prepared ray's copy.
//
// Inlined into the caller: the Hit then reaches the caller's variable field by field
// (a Hit returned through memory and copied whole stalls on store-to-load forwarding).
template <template <class> class R, class T, class Shape, class Mode>
    requires detail::RayOrPrepared<R<T>, T> && Answerable<T, Shape, Mode>
[[nodiscard]] RAYPROOF_ALWAYS_INLINE Hit<T> intersect(const R<T>& ray, const Shape& shape, Mode mode) noexcept {
    return detail::guarded_entry<detail::QueryInEnv>(ray, shape, mode);
}

// The verdict alone: verdict(ray, shape, mode) == intersect(ray, shape, mode).verdict
// for every input, in every mode (a certified verdict is the exact one). It asks the
// question CGAL's do_intersect answers, and where a shape has a verdict path of its own
// (the certified Aabb, plane and sphere) it skips what only the full answer needs: the
// winning slabs, the face, the roots and the rounding of t. Each such path answers only
// what its proven bounds decide (the Aabb's on the full query's own lanes) and hands the
// rest to the full query's stages, so the two cannot disagree.
template <template <class> class R, class T, class Shape, class Mode>
    requires detail::RayOrPrepared<R<T>, T> && Answerable<T, Shape, Mode>
[[nodiscard]] RAYPROOF_ALWAYS_INLINE Verdict verdict(const R<T>& ray, const Shape& shape, Mode mode) noexcept {
    return detail::guarded_entry<detail::VerdictInEnv>(ray, shape, mode);
}

// --- In an FpEnvScope (fp_env_scope.hpp) ------------------------------------------------
// The same answers as the forms above, bit for bit in every mode, without the per-call
// read of the control state: the scope has established the default environment (and,
// checked where RAYPROOF_CHECK_FP_ENV_SCOPE is defined or NDEBUG is not, still finds it).
template <template <class> class R, class T, class Shape, class Mode>
    requires detail::RayOrPrepared<R<T>, T> && Answerable<T, Shape, Mode>
[[nodiscard]] RAYPROOF_ALWAYS_INLINE Hit<T> intersect(const R<T>& ray, const Shape& shape, Mode mode,
                                                      const FpEnvScope&) noexcept {
    return detail::scoped_entry<detail::QueryInEnv>(ray, shape, mode);
}

template <template <class> class R, class T, class Shape, class Mode>
    requires detail::RayOrPrepared<R<T>, T> && Answerable<T, Shape, Mode>
[[nodiscard]] RAYPROOF_ALWAYS_INLINE Verdict verdict(const R<T>& ray, const Shape& shape, Mode mode,
                                                     const FpEnvScope&) noexcept {
    return detail::scoped_entry<detail::VerdictInEnv>(ray, shape, mode);
}

// --- Batch forms ------------------------------------------------------------------------
// out[i] = intersect(rays[i], shape, mode), or verdict(...), for rays of Ray<T> or of
// PreparedRay<T> (R). The shape is validated and prepared once. Precondition, checked:
// out.size() == rays.size(); otherwise it throws std::invalid_argument, or, built without
// exceptions, prints a message on stderr and aborts (detail::batch_size_mismatch). A
// shape without a prepared-ray path answers each prepared ray through its Ray form. Where
// it pays (the certified Aabb, detail/ray_aabb_batch.hpp, and the certified plane,
// detail/ray_plane_batch.hpp: its enclosure for float rays, its verdict filter for double
// rays; with SSE2 or AVX2) the batch runs W rays at a time in SIMD lanes
// (batch::lane_batch), with each ray's scalar answer bit for bit. Every batch loop asks
// for its rays' cache lines some way ahead (batch::prefetch_ahead): a batch streams its
// rays from memory once.
namespace detail {
template <class R, class T, class Shape, class Mode, class Out, class Query>
void batch_of(std::span<const R> rays, const Shape& shape, std::span<Out> out, const char* mismatch, Query query_one) {
    if (out.size() != rays.size()) batch_size_mismatch(mismatch);
    if constexpr (!DirectPath<R, Shape, Mode>) {
        for (std::size_t i = 0; i < rays.size(); ++i) {
            batch::prefetch_ahead(rays, i, 1);
            out[i] = query_one(rays[i].ray(), shape);
        }
    } else {
        const auto batch = [](std::span<const R> r, const Shape& s, std::span<Out> o) noexcept {
            const auto prepared = prepare(s);
            // A shape with a lane path for this mode (detail/ray_*_batch.hpp) answers
            // W rays at a time, with the scalar answers bit for bit.
            if constexpr (requires { batch::lane_batch(r, prepared, o, Mode{}); }) {
                batch::lane_batch(r, prepared, o, Mode{});
                return;
            }
            for (std::size_t i = 0; i < r.size(); ++i) {
                batch::prefetch_ahead(r, i, 1);
                if constexpr (std::is_same_v<Out, Verdict>)
                    o[i] = verdict_query(r[i], prepared, Mode{});
                else
                    o[i] = query(r[i], prepared, Mode{});
            }
        };
        if constexpr (fp_env_guarded<Mode>)
            if (!fp_env_is_default()) [[unlikely]]
                return in_established_fp_env(batch, rays, shape, out);
        batch(rays, shape, out);
    }
}
}  // namespace detail

template <template <class> class R, class T, class Shape, class Mode>
    requires detail::RayOrPrepared<R<T>, T> && Answerable<T, Shape, Mode>
void intersect(std::span<const R<T>> rays, const Shape& shape, Mode mode, std::span<Hit<T>> out) {
    static_cast<void>(mode);  // the tag's type is all the batch needs
    detail::batch_of<R<T>, T, Shape, Mode>(rays, shape, out, "rayproof::intersect: out.size() must equal rays.size()",
                                           [](const Ray<T>& r, const Shape& s) { return intersect(r, s, Mode{}); });
}

template <template <class> class R, class T, class Shape, class Mode>
    requires detail::RayOrPrepared<R<T>, T> && Answerable<T, Shape, Mode>
void verdict(std::span<const R<T>> rays, const Shape& shape, Mode mode, std::span<Verdict> out) {
    static_cast<void>(mode);
    detail::batch_of<R<T>, T, Shape, Mode>(rays, shape, out, "rayproof::verdict: out.size() must equal rays.size()",
                                           [](const Ray<T>& r, const Shape& s) { return verdict(r, s, Mode{}); });
}

// The same ray traversed backwards: the set { o + s·(-d) : s in [-t_max, -t_min] }.
// Its interval against a shape is [-t_exit, -t_enter] of the original, and its entry
// face is the original's exit face (negation is exact, so no accuracy is lost).
template <class T> [[nodiscard]] Ray<T> reversed(const Ray<T>& r) noexcept {
    return Ray<T>{r.origin, -r.direction, -r.t_max, -r.t_min};
}

// --- The mode chosen at run time --------------------------------------------------------
// Each form below dispatches to the same form with the tag of that name, so its answer
// is the tag's, bit for bit. A RuntimeMode outside the three enumerators is invalid
// input: Verdict::invalid (every element, in the batch forms).

// True when the kernel answers this combination in every mode.
template <class T, class Shape>
concept AnswerableAtRunTime = Answerable<T, Shape, fast_t> && Answerable<T, Shape, conservative_t> &&
                              Answerable<T, Shape, certified_t>;

template <template <class> class R, class T, class Shape>
    requires detail::RayOrPrepared<R<T>, T> && AnswerableAtRunTime<T, Shape>
[[nodiscard]] Hit<T> intersect(const R<T>& ray, const Shape& shape, RuntimeMode mode) noexcept {
    return with_mode(
        mode, [&](auto tag) { return intersect(ray, shape, tag); }, [] { return detail::invalid_hit<T>(); });
}

template <template <class> class R, class T, class Shape>
    requires detail::RayOrPrepared<R<T>, T> && AnswerableAtRunTime<T, Shape>
[[nodiscard]] Verdict verdict(const R<T>& ray, const Shape& shape, RuntimeMode mode) noexcept {
    return with_mode(mode, [&](auto tag) { return verdict(ray, shape, tag); }, [] { return Verdict::invalid; });
}

template <template <class> class R, class T, class Shape>
    requires detail::RayOrPrepared<R<T>, T> && AnswerableAtRunTime<T, Shape>
[[nodiscard]] Hit<T> intersect(const R<T>& ray, const Shape& shape, RuntimeMode mode, const FpEnvScope& scope) noexcept {
    return with_mode(
        mode, [&](auto tag) { return intersect(ray, shape, tag, scope); }, [] { return detail::invalid_hit<T>(); });
}

template <template <class> class R, class T, class Shape>
    requires detail::RayOrPrepared<R<T>, T> && AnswerableAtRunTime<T, Shape>
[[nodiscard]] Verdict verdict(const R<T>& ray, const Shape& shape, RuntimeMode mode, const FpEnvScope& scope) noexcept {
    return with_mode(mode, [&](auto tag) { return verdict(ray, shape, tag, scope); }, [] { return Verdict::invalid; });
}

// Batch forms; the same precondition, checked the same way, as the tag forms.
template <template <class> class R, class T, class Shape>
    requires detail::RayOrPrepared<R<T>, T> && AnswerableAtRunTime<T, Shape>
void intersect(std::span<const R<T>> rays, const Shape& shape, RuntimeMode mode, std::span<Hit<T>> out) {
    with_mode(
        mode, [&](auto tag) { intersect(rays, shape, tag, out); },
        [&] {
            if (out.size() != rays.size())
                detail::batch_size_mismatch("rayproof::intersect: out.size() must equal rays.size()");
            for (Hit<T>& h : out) h = detail::invalid_hit<T>();
        });
}

template <template <class> class R, class T, class Shape>
    requires detail::RayOrPrepared<R<T>, T> && AnswerableAtRunTime<T, Shape>
void verdict(std::span<const R<T>> rays, const Shape& shape, RuntimeMode mode, std::span<Verdict> out) {
    with_mode(
        mode, [&](auto tag) { verdict(rays, shape, tag, out); },
        [&] {
            if (out.size() != rays.size())
                detail::batch_size_mismatch("rayproof::verdict: out.size() must equal rays.size()");
            for (Verdict& v : out) v = Verdict::invalid;
        });
}

}  // namespace rayproof
