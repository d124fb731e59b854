// rayproof/bvh.hpp — a wide bounding volume hierarchy over a scene of primitives that
// never loses a hit: the closest hit, any hit, and the candidates of one ray.
//
// Answers:   closest_hit(ray, mode) and any_hit(ray, mode) mean exactly what the brute
//            force over every primitive (closest.hpp) means, and answer the same:
//            certified — identical to brute force bit for bit: the primitive whose exact
//              t_enter is the smallest (exact ties to the lowest index) and its own
//              certified Hit; any_hit is a hit exactly when some primitive is met.
//            conservative — a hit whenever some primitive is met exactly, and then a
//              t_enter no larger than the exact closest entry (so at most the certified
//              closest t_enter); the Hit is the chosen primitive's own conservative Hit.
//            fast — no promise beyond the ray's validity; its agreement is measured.
//            for_each_candidate(ray, mode, t_limit, f) calls f(index) for every primitive
//            the ray may meet on [t_min, t_limit] (every primitive kept beside the tree
//            included): in the certified and conservative modes never skipping one the
//            ray meets there exactly, whatever f does to t_limit meanwhile.
//            An invalid ray is answered Verdict::invalid (closest_hit, any_hit) or with no
//            candidate (for_each_candidate); an invalid primitive is never hit.
// Structure: W-wide nodes (W = 4 or 8), each an AabbPacket<T, W> of its children's boxes
//            (ray_aabb_packet.hpp) beside W child references, in one flat vector; a
//            child is an inner node or a leaf, a range of at most leaf_size primitives in
//            an index array. A node's lane box is the exact union (min and max, no
//            rounding) of the boxes below it, and each primitive's box is
//            detail::enclosing_box (primitive_bounds.hpp): a box that contains the
//            primitive exactly. Unused lanes are empty slots (lo = +inf > hi = -inf).
//            Primitives with no enclosing box (planes, unbounded or invalid primitives,
//            empty polyhedra) are kept in a list beside the tree and visited by every
//            query. The primitives are copied and stored in leaf order, the tree's first,
//            then those beside it (so a leaf's primitives share cache lines); the indices
//            answered are positions in the given order (index_of maps a stored position
//            to it). A ConvexPolyhedron's planes stay the caller's. The tree's balls are
//            copied once more, as bare Spheres by position, which the leaves read (a
//            variant's tag lies on another cache line than a ball's values).
// Build:     top-down binned SAH (the surface area heuristic of MacDonald & Booth, "Heuristics
//            for ray tracing using space subdivision", Visual Computer 1990; binned over the
//            centroids as in Wald, "On fast construction of SAH-based bounding volume
//            hierarchies", IRT 2007), with binary splits collapsed into W-wide nodes the
//            way Embree's wide BVH builders do (Wald et al., "Embree: a kernel framework for
//            efficient CPU ray tracing", SIGGRAPH 2014): a node takes its range, then splits
//            its largest child (by surface area) until it has W children or none is left
//            to split, children too big for one node of leaves first, then only children
//            whose primitives fit in the lanes left (so the lowest nodes are full, not
//            many nodes of two or three lanes). Where the bins cannot
//            separate the centroids (all equal, or every cost infinite), and below depth
//            bvh_sah_depth, the split is the object median on the widest centroid axis:
//            every split leaves both sides nonempty, and the depth is at most
//            bvh_sah_depth + 33 (each median level halves the range, fewer than 2^32
//            primitives in the tree), which bounds the traversal stack. The build runs in
//            the default floating-point environment (detail/fp_env.hpp): min and max of
//            subnormals under denormals-are-zero would otherwise give a box too small.
// Traversal: one stack, near children first. Each node is answered by one packet
//            query on the current range [t_min, t_limit] (PreparedRay::with_range, the
//            reciprocals kept): fast mode its fast packet's lanes (without the packet's
//            checks, bvh_node_fast, where no axis is parallel); the conservative and certified
//            modes the slabs with the reciprocal scaled by 1 - c and 1 + c (bvh_node_scaled,
//            where the ray's reciprocals and the tree's extent keep every product finite)
//            or else the conservative packet's filter (bvh_node_conservative): either
//            mask contains every lane the exact ray meets on that range, and the lane's
//            entry bound (kept in double) lies at or below its exact entry.
//            The nearest hit lane is answered next; the other hit lanes are pushed far
//            first by that t_enter (their nodes or leaf primitives prefetched), and a
//            popped lane whose t_enter exceeds the current t_limit is skipped. Which
//            filter (scaled, float, double, or the scalar query for reciprocals none can
//            use) is decided once per ray. (The certified packet is exact, but pays a scalar
//            query for its undecided lanes; the primitives' own certified queries decide
//            the answer either way, so the conservative packet, which never culls less
//            than the exact test would keep, suffices.)
//            closest_hit lowers t_limit as it finds hits: certified, to next_up(b), b the
//            best hit's faithfully rounded t_enter; conservative and fast, to b.
//            Candidates are compared with detail::compare_entry (certified: the exact
//            order, decided exactly where the rounded values cannot) or by t_enter
//            (conservative, fast), ties to the lowest index.
// Completeness (certified; the contract in ../docs/semantics.md, "BVH"): let p be a
//            primitive whose exact t_enter E satisfies E <= E_best, the exact entry of the
//            best hit so far (so p wins or ties). The faithful b lies within one float
//            of E_best, so E <= E_best < next_up(b) = t_limit; the point o + E·d lies in
//            p, hence in p's enclosing box, hence in every lane box above p (unions,
//            exact). So every node packet on [t_min, t_limit] has that lane's bit set
//            (the conservative packet never misses an exact meeting), and its t_enter,
//            a lower bound of the lane's exact entry, is at most E <= t_limit: the lane
//            is never skipped on the stack either. Every primitive that could win is
//            therefore asked, with the caller's prepared ray (so its Hit is the very one
//            brute force gets), and the total order (exact t_enter, then index) makes the
//            winner independent of the visiting order. any_hit asks until the first hit,
//            on [t_min, t_max] throughout.
// Degenerate cases: no primitives, or only ones beside the tree (no node: every query
//            answers from the list); a single primitive (a root with one leaf lane);
//            many primitives with equal centroids (median splits); invalid primitives
//            (beside the tree, never hit); t_limit below t_min or NaN in
//            for_each_candidate (nothing in the tree can be met: no further candidate
//            from it); t_limit above t_max (the ray's own range). -inf entries (t_min =
//            -inf on a plane) have next_up(-inf) = the lowest float, still above E_best.
// Environment: certified and conservative closest_hit and any_hit answer in the default
//            floating-point environment whatever the caller's (detail/fp_env.hpp), as the
//            brute force does: compare_entry and the primitives' comparisons assume it.
//            for_each_candidate runs its callback in the caller's environment; its node
//            tests answer in the default one (reading the control state per node, or,
//            given an FpEnvScope, not at all: the scope holds it), and the traversal
//            itself only compares
//            (under denormals-are-zero x > y may answer false where it is true, never the
//            reverse, so a child is then kept, never lost) and selects the narrowed range
//            end and steps next_up by their bits, never by min or arithmetic.
// No exception on any primitive or ray: bad primitives are kept beside the tree and
// answered invalid by their own queries; an empty Bvh answers miss.
#pragma once

#include <rayproof/closest.hpp>
#include <rayproof/detail/entry_order.hpp>
#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/fp_env.hpp>
#include <rayproof/detail/primitive_bounds.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/detail/validate.hpp>
#include <rayproof/intersect.hpp>
#include <rayproof/prepared_ray.hpp>
#include <rayproof/ray_aabb_packet.hpp>
#include <rayproof/types.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace rayproof {

// leaf_size: the most primitives in one leaf (clamped to [1, 255]); bins: the SAH bins
// per axis (clamped to [2, 256]).
struct BvhOptions {
    int leaf_size = 1;
    int bins = 16;
};

// primitives: as given; nodes: W-wide nodes; leaves: leaf lanes; outside: primitives
// kept beside the tree; depth: node levels (0 without a tree, 1 for a root alone);
// bytes: the memory the Bvh holds (nodes, index arrays, the primitives' copies and the
// balls' compact ones).
// Every primitive is in exactly one leaf or beside the tree.
struct BvhStats {
    std::size_t primitives = 0, nodes = 0, leaves = 0, outside = 0;
    int depth = 0;
    std::size_t bytes = 0;
};

// The node width that answers fastest for T with the vector registers the build targets:
// 8, but 4 for double where the native backend is SSE2 or portable (eight double lanes
// would take four SSE2 registers). Certified closest hits on 100,000 balls, camera rays,
// per ray: Bvh<double, 4> took 2.9-3.1 µs against 6.3-6.6 µs for Bvh<double, 8> in the
// default x86-64 build, and 2.4-2.5 µs against 2.2-2.4 µs in an AVX2 build; float's two
// widths were within the measurement's noise of each other in both. Every width gives
// the same answers; the default template argument stays 8 whatever the build targets,
// so that translation units built for different targets name the same type.
#if defined(RAYPROOF_SIMD_AVX2)
template <class T> inline constexpr int bvh_native_width = 8;
#else
template <class T> inline constexpr int bvh_native_width = std::is_same_v<T, double> ? 4 : 8;
#endif

namespace detail {

// Below this node depth the split is binned SAH, from it on the object median (see the
// header comment); bvh_max_depth bounds every tree's depth.
inline constexpr int bvh_sah_depth = 32;
inline constexpr int bvh_max_depth = bvh_sah_depth + 34;

// One node: the children's boxes in lanes, and per lane either an inner child (count
// 0, first = its node index) or a leaf (count > 0 primitives, positions first ..
// first + count - 1 of the index array). An empty slot has count 0 and an empty box.
template <class T, int W> struct BvhNode {
    AabbPacket<T, W> box;
    std::uint32_t first[std::size_t(W)];
    std::uint32_t count[std::size_t(W)];
};

// x's successor among the floats, by its bits alone (no comparison or arithmetic on the
// value, so denormals-are-zero cannot change it): +inf and NaN stay, ±0 gives the
// smallest subnormal, -min_subnormal gives -0.
template <class T> RAYPROOF_ALWAYS_INLINE T bvh_next_up(T x) noexcept {
    using U = FloatBits<T>;
    constexpr U sign = U(1) << (sizeof(T) * 8 - 1);
    const U inf_bits = std::bit_cast<U>(std::numeric_limits<T>::infinity());
    const U b = std::bit_cast<U>(x);
    const U mag = b & ~sign;
    if (mag > inf_bits || b == inf_bits) return x;  // NaN, +inf
    if (mag == 0) return std::numeric_limits<T>::denorm_min();
    return std::bit_cast<T>((b & sign) ? U(b - 1) : U(b + 1));
}

// a when take_a, else b, selected by the bits (no min instruction, which would read
// subnormals as zero under denormals-are-zero).
template <class T> RAYPROOF_ALWAYS_INLINE T bvh_select(bool take_a, T a, T b) noexcept {
    using U = FloatBits<T>;
    const U m = U(0) - U(take_a);
    return std::bit_cast<T>(U((std::bit_cast<U>(a) & m) | (std::bit_cast<U>(b) & U(~m))));
}

// The box a Bvh files a primitive under: enclosing_box, and only when every bound is
// finite with lo <= hi (anything else is kept beside the tree, which is always safe).
template <class T> std::optional<Aabb<T>> bvh_box(const Primitive<T>& p) {
    if (p.valueless_by_exception()) return std::nullopt;
    const std::optional<Aabb<T>> b = enclosing_box(p);
    if (!b || !valid(*b)) return std::nullopt;
    return b;
}

// The certified packet's filter in E (float or double, ray_aabb_packet.hpp), bounded once
// at m, the largest of the computed entries and t_min, and M, the smallest of the
// computed exits and t_max (certified_filter_in): its enclosures [lo(m), hi(m)] of the
// exact latest entry and [lo(M), hi(M)] of the exact earliest exit (the entry's lower
// end raised to t_min and the exit's upper end lowered to t_max: still bounds, the exact
// entry being at least t_min and the exit at most t_max) leave a lane a possible hit
// unless the exit's upper end lies below the entry's lower end (the certified filter's
// proven miss): the same enclosures, so the same guarantee. Both ends of an enclosure increase
// with the value bounded, so max(t_min, lo(m)) is the largest of the per-axis lower entry
// bounds and min(t_max, hi(M)) the smallest of the upper exit bounds: on the lanes with
// every value finite, the conservative packet's very decisions and entry bounds, with two
// enclosures per lane instead of six. Overflowing lanes take the scalar query.
template <class E, class B, class T, int W>
RAYPROOF_ALWAYS_INLINE std::uint32_t bvh_node_filter(const PreparedRay<T>& pr, const AabbPacket<T, W>& b,
                                                     double (&t)[std::size_t(W)]) noexcept {
    using V = simd::Vec<E, W, B>;
    const packet::Filtered<E, B, T, W> f = packet::filter<E, B, false, W>(pr, b, 0);
    const V K = V::splat(packet::Bound<E>::K), eta = V::splat(packet::Bound<E>::eta);
    const V bm = abs(f.m) * K + eta, bM = abs(f.M_) * K + eta;
    const V e_lo = max(f.m - bm, V::splat(E(pr.ray().t_min))), x_hi = min(f.M_ + bM, V::splat(E(pr.ray().t_max)));
    std::uint32_t mask = (f.ok & f.finite & (e_lo <= x_hi)).bits();
    e_lo.store_widened(t);
    for (std::uint32_t u = simd::and_not(f.ok, f.finite).bits(); u != 0; u &= u - 1) {
        const int i = std::countr_zero(u);
        const Hit<T> h = query_in_env(pr, b.box(i), conservative);  // in the node test's environment
        mask |= std::uint32_t(h.verdict == Verdict::hit) << i;
        t[i] = double(h.t_enter);
    }
    return mask;
}

// The scaled node test (BvhFilter::scaled) of the conservative and certified modes: on a
// tree's lane boxes (each finite with lo <= hi, or an empty slot lo = +inf, hi = -inf),
// in T, for a valid ray that bvh_scaled_usable admits. Per axis, with s_lo = fl(r(1 - c))
// and s_hi = fl(r(1 + c)) (r = rinv = fl(1/d) in double, rounded to T; c = 8u, u the unit
// roundoff of T), the exact entry a = (near - o)/d and exit b = (far - o)/d are bounded by
//   a >= min(fl(x·s_lo), fl(x·s_hi)) - eta,  b <= max(fl(y·s_lo), fl(y·s_hi)) + eta,
// x = fl(near - o), y = fl(far - o), eta = 2^-150 (float) or 2^-1075 (double), half the
// smallest subnormal (the product's rounding is absolute where it underflows).
// Derivation, for the product p = x·s with x·r >= 0 and s = s_lo:
// fl(x·s_lo) is at most |x_e|(1 + u)·|r|(1 + u_d)^2(1 - c)(1 + u)·(1 + u), x_e = near - o
// (x's, the reciprocal's (double, then the product by 1 - c), s_lo's rounding to T and
// the product's), and (1 + u)^3 (1 + u_d)^2 (1 - c) <= 1 for c = 8u, so it is at most
// |a|; for x·r < 0, fl(x·s_hi) <= -|x_e||r|(1 - u)^3(1 - u_d)^2(1 + c) <= a likewise.
// One of the two is a valid lower bound in either case, hence so is their min, whatever
// the signs (the exit: the max, by the mirror argument). Where the product underflows,
// its rounding is absolute, at most eta: hence the - eta. The ranges bvh_scaled_usable
// checks keep s_lo and s_hi normal and every |x·s| below T's largest finite value; x
// itself is exact when subnormal, and an empty slot's x is ±inf with a finite nonzero
// s, so its entry is +inf and its exit -inf on every axis (never a hit, never NaN).
// The mask needs no eta: the exact products before their last rounding, z = x·s
// (entries) and w = y·s (exits), already bound a from below and b from above (c covers
// every other rounding), and rounding is monotone, so an exact hit, t_min <= b_j and a_i
// <= t_max and a_i <= b_j for all axes i, j, gives fl(z_i) <= fl(w_j), t_min <= fl(w_j)
// and fl(z_i) <= t_max: with e = max(t_min, entry bounds) and X = min(t_max, exit
// bounds) as computed, e <= X (an overflow to ±inf keeps the order too). The lane's entry
// bound t = fl(e - 2eta) (2eta = T's smallest subnormal) lies at or below the exact
// entry: where e came from an underflowed product, |e| <= 2^-126 (float; 2^-1022 double)
// and the subtraction is exact; elsewhere e itself bounds the entry and fl(e - 2eta) <= e.
// Compared with bvh_node_filter (the certified packet's filter), the bound is folded into
// two products per slab instead of an absolute value, a product and a sum after the
// slabs, and no finiteness probe is needed, which shortens the chain a traversal waits on
// at every node.
template <class T> inline constexpr double bvh_scaled_c = 8 * unit_roundoff<T>;
template <class B, class T, int W>
RAYPROOF_ALWAYS_INLINE std::uint32_t bvh_node_scaled(const PreparedRay<T>& pr, const AabbPacket<T, W>& b,
                                                     double (&t)[std::size_t(W)]) noexcept {
    using V = simd::Vec<T, W, B>;
    const Ray<T>& r = pr.ray();
    const V eta2 = V::splat(std::numeric_limits<T>::denorm_min());
    V enter = V::splat(r.t_min), leave = V::splat(r.t_max);  // e and X
    RAYPROOF_UNROLL3
    for (int i = 0; i < 3; ++i) {
        const bool neg = pr.negative(i);
        const V o = V::splat(r.origin[i]);
        const V s_lo = V::splat(T(pr.rinv(i) * (1 - bvh_scaled_c<T>))), s_hi = V::splat(T(pr.rinv(i) * (1 + bvh_scaled_c<T>)));
        const V x = V::load(neg ? b.hi[i] : b.lo[i]) - o, y = V::load(neg ? b.lo[i] : b.hi[i]) - o;
        enter = max(min(x * s_lo, x * s_hi), enter);
        leave = min(max(y * s_lo, y * s_hi), leave);
    }
    (enter - eta2).store_widened(t);
    return (enter <= leave).bits();
}

// Which node filter a traversal uses. The conservative and certified modes: the scaled
// filter (bvh_node_scaled) where bvh_scaled_usable admits the ray on the tree; otherwise
// float trees the float filter (twice the lanes per register, K = 2·gamma_f(4), eta =
// 2^-126) where every reciprocal is a normal float; otherwise, and for double trees, the
// double filter where every double reciprocal is normal; else the scalar conservative
// query per lane. Fast mode has its own two: lean (bvh_node_fast) where every reciprocal
// in T is normal and finite (no axis parallel), else the fast packet's general lanes
// (scalar). The choice depends on the ray's origin and reciprocals (and the tree's
// extent) alone, which PreparedRay::with_range keeps, so it is made once per traversal.
enum class BvhFilter : unsigned char { in_float, in_double, scalar, lean, scaled };

// Whether bvh_node_scaled can answer for the prepared ray on a tree whose finite box
// coordinates are at most `extent` in magnitude: per axis, |rinv| in [2^-120, 2^120]
// (float; [2^-1000, 2^1000] double), so that s_lo and s_hi are normal in T, and (extent
// + |o|)·|rinv| at most 2^125 (float; 2^1021 double), so that |x·s| <= 2(extent +
// |o|)|rinv| stays below T's largest finite value (the factor 2 covers (1 + c) and the
// roundings). A zero component (rinv infinite) or a NaN fails the comparisons.
template <class T> RAYPROOF_ALWAYS_INLINE bool bvh_scaled_usable(const PreparedRay<T>& pr, double extent) noexcept {
    constexpr bool f = std::is_same_v<T, float>;
    constexpr double small = f ? 0x1p-120 : 0x1p-1000, big = f ? 0x1p120 : 0x1p1000, large = f ? 0x1p125 : 0x1p1021;
    bool ok = true;
    for (int i = 0; i < 3; ++i) {
        const double a = std::abs(pr.rinv(i));
        ok &= (small <= a) & (a <= big) & ((extent + std::abs(double(pr.ray().origin[i]))) * a <= large);
    }
    return ok;
}
template <class T> RAYPROOF_ALWAYS_INLINE BvhFilter bvh_filter_for(const PreparedRay<T>& pr) noexcept {
    if constexpr (std::is_same_v<T, float>)
        if (pr.template reciprocals_usable_in<float>()) return BvhFilter::in_float;
    return pr.template reciprocals_usable_in<double>() ? BvhFilter::in_double : BvhFilter::scalar;
}
template <class T> RAYPROOF_ALWAYS_INLINE BvhFilter bvh_fast_filter_for(const PreparedRay<T>& pr) noexcept {
    // No axis parallel and every reciprocal in T normal and finite.
    return pr.parallel_axes() == 0 && pr.template reciprocals_usable_in<T>() ? BvhFilter::lean : BvhFilter::scalar;
}

// The fast node test of a valid ray whose reciprocals in T are all normal and finite
// (bvh_fast_filter_for: lean), on a tree's lane boxes, each finite with lo <= hi or an
// empty slot (lo = +inf, hi = -inf): the fast packet's lanes (packet::fast_lanes, the
// same slab values (near - o)·inv and (far - o)·inv, clamped by max and min in the same
// order) without its checks, which such boxes and reciprocals make redundant. A slab
// value is a finite or infinite difference times a finite nonzero reciprocal, so never
// NaN; an empty slot's entry is +inf and its exit -inf on every axis, so it is never
// hit. Where no slab value overflows, the mask and the entries (in t) are fast_lanes'
// own (bvh_test checks it); where one does, a lane fast_lanes drops may be kept here
// (an entry of -inf or an exit of +inf leaves the clamp as it is): fast promises nothing
// there, and a kept lane only costs a visit.
template <class B, class T, int W>
RAYPROOF_ALWAYS_INLINE std::uint32_t bvh_node_fast(const PreparedRay<T>& pr, const AabbPacket<T, W>& b,
                                                   T (&t)[std::size_t(W)]) noexcept {
    using V = simd::Vec<T, W, B>;
    const Ray<T>& r = pr.ray();
    V enter = V::splat(r.t_min), exit = V::splat(r.t_max);
    RAYPROOF_UNROLL3
    for (int i = 0; i < 3; ++i) {
        const bool neg = pr.negative(i);
        const V o = V::splat(r.origin[i]), inv = V::splat(pr.inv(i));
        enter = max((V::load(neg ? b.hi[i] : b.lo[i]) - o) * inv, enter);
        exit = min((V::load(neg ? b.lo[i] : b.hi[i]) - o) * inv, exit);
    }
    enter.store(t);
    return (enter <= exit).bits();
}

// The conservative node test: the conservative packet's filter (ray_aabb_packet.hpp,
// the same decisions as its mask, so it never drops a lane the exact ray meets on the
// prepared ray's range) with the lower end of each hit lane's entry enclosure,
// max(t_min, lo(m)) <= the lane's exact entry, kept in double in t[i] (no rounding to T,
// no other field). Lanes whose values overflow, and rays whose reciprocals the filter
// cannot use, take the scalar conservative query, whose t_enter is such a bound too.
// which: bvh_filter_for(pr). Needs the default floating-point environment (the caller
// establishes or checks it).
template <class B, class T, int W>
RAYPROOF_ALWAYS_INLINE std::uint32_t bvh_node_conservative(const PreparedRay<T>& pr, const AabbPacket<T, W>& b,
                                                           BvhFilter which, double (&t)[std::size_t(W)]) noexcept {
    if (!pr.valid()) return 0;
    if (which == BvhFilter::scalar) [[unlikely]] {
        std::uint32_t mask = 0;
        for (int i = 0; i < W; ++i)
            if (valid(b.box(i))) {
                const Hit<T> h = query_in_env(pr, b.box(i), conservative);  // in the node test's environment
                mask |= std::uint32_t(h.verdict == Verdict::hit) << i;
                t[i] = double(h.t_enter);
            }
        return mask;
    }
    if constexpr (std::is_same_v<T, float>)
        if (which == BvhFilter::in_float) [[likely]]
            return bvh_node_filter<float, B>(pr, b, t);
    return bvh_node_filter<double, B>(pr, b, t);
}

}  // namespace detail

template <class T, int W = 8> class Bvh {
    static_assert(is_scalar_v<T> && (W == 4 || W == 8), "Bvh<T, W>: T float or double, W 4 or 8");

public:
    Bvh() = default;

    // Copies the primitives and builds the tree (see the header comment). Never throws on
    // a bad primitive (it is kept beside the tree); only memory exhaustion throws.
    explicit Bvh(std::span<const Primitive<T>> prims, BvhOptions opt = {}) : prims_(prims.begin(), prims.end()) {
        const detail::FpEnvGuard guard;
        build(opt);
    }

    // The primitives held, and the copies as stored: the tree's in leaf order
    // (leaf_indices()), then those beside it (outside()), so that a leaf's primitives
    // lie together in memory. stored()[p] is the primitive of index index_of(p).
    [[nodiscard]] std::size_t size() const noexcept { return prims_.size(); }
    [[nodiscard]] std::span<const Primitive<T>> stored() const noexcept { return prims_; }
    [[nodiscard]] std::size_t index_of(std::size_t position) const noexcept {
        return position < order_.size() ? std::size_t(order_[position]) : outside_[position - order_.size()];
    }

    [[nodiscard]] BvhStats stats() const noexcept {
        BvhStats s;
        s.primitives = prims_.size();
        s.nodes = nodes_.size();
        s.outside = outside_.size();
        s.depth = depth_;
        for (const Node& n : nodes_)
            for (int i = 0; i < W; ++i) s.leaves += std::size_t(n.count[i] > 0);
        s.bytes = sizeof(*this) + nodes_.capacity() * sizeof(Node) + order_.capacity() * sizeof(std::uint32_t) +
                  outside_.capacity() * sizeof(std::size_t) + prims_.capacity() * sizeof(Primitive<T>) +
                  balls_.capacity() * sizeof(Sphere<T>);
        return s;
    }

    // The tree as built, for inspection (tests, tools): nodes()[0] is the root (none
    // without a tree); a leaf lane's primitives are leaf_indices()[first .. first +
    // count - 1]; outside() lists the primitives kept beside the tree, ascending.
    [[nodiscard]] std::span<const detail::BvhNode<T, W>> nodes() const noexcept { return nodes_; }
    [[nodiscard]] std::span<const std::uint32_t> leaf_indices() const noexcept { return order_; }
    [[nodiscard]] std::span<const std::size_t> outside() const noexcept { return outside_; }

    // The brute force's answer (closest.hpp) in the mode's sense: see the header comment.
    // The certified and conservative forms answer in the default floating-point
    // environment whatever the caller's, as the brute force does (detail/fp_env.hpp):
    // compare_entry and the comparisons of t assume it.
    template <class Mode>
        requires is_mode_v<Mode>
    [[nodiscard]] ClosestHit<T> closest_hit(const PreparedRay<T>& ray, Mode mode) const noexcept {
        if constexpr (detail::fp_env_guarded<Mode>)
            return detail::in_default_fp_env(
                [this](const PreparedRay<T>& r) noexcept { return closest_in_env(r, Mode{}); }, ray);
        else
            return closest_in_env(ray, mode);
    }
    template <class Mode>
        requires is_mode_v<Mode>
    [[nodiscard]] ClosestHit<T> closest_hit(const Ray<T>& ray, Mode mode) const noexcept {
        return closest_hit(PreparedRay<T>(ray), mode);
    }

    // Some primitive hit (its own Hit in the mode), the first one met; see the header
    // comment for what each mode promises. Environment as closest_hit.
    template <class Mode>
        requires is_mode_v<Mode>
    [[nodiscard]] ClosestHit<T> any_hit(const PreparedRay<T>& ray, Mode mode) const noexcept {
        if constexpr (detail::fp_env_guarded<Mode>)
            return detail::in_default_fp_env([this](const PreparedRay<T>& r) noexcept { return any_in_env(r, Mode{}); },
                                             ray);
        else
            return any_in_env(ray, mode);
    }
    template <class Mode>
        requires is_mode_v<Mode>
    [[nodiscard]] ClosestHit<T> any_hit(const Ray<T>& ray, Mode mode) const noexcept {
        return any_hit(PreparedRay<T>(ray), mode);
    }

    // f(std::size_t index) -> bool for every primitive the ray may meet on [t_min,
    // t_limit] (the primitives beside the tree first, then the tree's, near leaves
    // first); f may lower t_limit and returns false to stop. Certified and conservative:
    // never skips a primitive the ray meets on [t_min, t_limit] exactly, for the
    // t_limit of the moment. f runs in the caller's floating-point environment; the
    // node tests answer in the default one, and the traversal itself only compares.
    template <class Mode, class F>
        requires is_mode_v<Mode>
    void for_each_candidate(const PreparedRay<T>& ray, Mode mode, T& t_limit, F&& f) const {
        auto by_index = [this, &f](std::size_t position) { return f(index_of(position)); };
        candidates<false>(ray, mode, t_limit, by_index);
    }
    // The same in an FpEnvScope (fp_env_scope.hpp): f runs in the scope's environment,
    // the default one, and the node tests do not read the control state per node.
    template <class Mode, class F>
        requires is_mode_v<Mode>
    void for_each_candidate(const PreparedRay<T>& ray, Mode mode, T& t_limit, F&& f, const FpEnvScope&) const {
        detail::fp_env_scope_check();
        auto by_index = [this, &f](std::size_t position) { return f(index_of(position)); };
        candidates<true>(ray, mode, t_limit, by_index);
    }

private:
    using Node = detail::BvhNode<T, W>;

    // f(position) for every candidate, by its position in prims_ (stored()).
    template <bool Known, class Mode, class F>
    void candidates(const PreparedRay<T>& ray, Mode mode, T& t_limit, F& f) const {
        if (!ray.valid()) return;
        for (std::size_t j = 0; j < outside_.size(); ++j)
            if (!f(order_.size() + j)) return;
        if (nodes_.empty()) return;
        traverse<Known>(ray, mode, t_limit, f);
    }

    template <class Mode> ClosestHit<T> closest_in_env(const PreparedRay<T>& ray, Mode mode) const noexcept {
        ClosestHit<T> best;
        if (!ray.valid()) return invalid_answer();
        const T t_max = ray.ray().t_max;
        T limit = t_max;
        std::size_t best_at = 0;  // the best's position in prims_
        auto consider = [&](std::size_t p) noexcept {
            const Hit<T> h = hit_at(ray, p, mode);
            if (h.verdict != Verdict::hit) return true;
            const auto idx = std::int64_t(index_of(p));
            bool take = best.index < 0;
            if (!take) {
                if constexpr (std::is_same_v<Mode, certified_t>) {
                    const int c = detail::compare_entry(ray, prims_[p], h, prims_[best_at], best.hit);
                    take = c < 0 || (c == 0 && idx < best.index);
                } else {
                    take = h.t_enter < best.hit.t_enter || (!(best.hit.t_enter < h.t_enter) && idx < best.index);
                }
            }
            if (take) {
                best.verdict = Verdict::hit;
                best.index = idx;
                best.hit = h;
                best_at = p;
                // Certified: the exact entry of the best lies below next_up(b) (faithful
                // b); a primitive that wins or ties is met there (the header comment).
                const T next = std::is_same_v<Mode, certified_t> ? detail::bvh_next_up(h.t_enter) : h.t_enter;
                limit = detail::bvh_select(next < t_max, next, t_max);
            }
            return true;
        };
        candidates<detail::fp_env_guarded<Mode>>(ray, mode, limit, consider);
        return best;
    }

    template <class Mode> ClosestHit<T> any_in_env(const PreparedRay<T>& ray, Mode mode) const noexcept {
        ClosestHit<T> best;
        if (!ray.valid()) return invalid_answer();
        T limit = ray.ray().t_max;
        auto consider = [&](std::size_t p) noexcept {
            const Hit<T> h = hit_at(ray, p, mode);
            if (h.verdict != Verdict::hit) return true;
            best.verdict = Verdict::hit;
            best.index = std::int64_t(index_of(p));
            best.hit = h;
            return false;
        };
        candidates<detail::fp_env_guarded<Mode>>(ray, mode, limit, consider);
        return best;
    }

    static ClosestHit<T> invalid_answer() noexcept {
        ClosestHit<T> r;
        r.verdict = Verdict::invalid;
        r.hit = detail::invalid_hit<T>();
        return r;
    }

    // The node test in the mode: the lanes' mask and, per hit lane, its t_enter (a lower
    // bound of the lane's exact entry in the conservative and certified modes). Fast: the
    // fast packet's lanes (which: lean or general). Conservative and certified: the
    // scaled test (detail::bvh_node_scaled) or the conservative packet's own filter
    // (detail::bvh_node_conservative), which need the default environment: Known says
    // the caller established it, else it is checked per node.
    // A node test's entries: fast mode's in T as computed (no widening of lanes that
    // missed), the others' lower bounds in double (the filter may compute them so).
    template <class Mode> using TEntry = std::conditional_t<std::is_same_v<Mode, fast_t>, T, double>;
    template <bool Known, class Mode>
    static RAYPROOF_ALWAYS_INLINE std::uint32_t node_test(const PreparedRay<T>& r, const Node& n, Mode,
                                                          detail::BvhFilter which,
                                                          TEntry<Mode> (&t)[std::size_t(W)]) noexcept {
        if constexpr (std::is_same_v<Mode, fast_t>) {
            if (which == detail::BvhFilter::lean) [[likely]]
                return detail::bvh_node_fast<detail::simd::native>(r, n.box, t);
            // The fast packet's lanes (ray_aabb_packet.hpp; r is valid), without face codes.
            const auto l = detail::packet::fast_lanes<detail::simd::native, false>(r, n.box);
            l.enter.store(t);
            return l.ok.bits();
        } else {
            if (Known || detail::fp_env_is_default()) [[likely]] {
                if (which == detail::BvhFilter::scaled) [[likely]]
                    return detail::bvh_node_scaled<detail::simd::native>(r, n.box, t);
                return detail::bvh_node_conservative<detail::simd::native>(r, n.box, which, t);
            }
            const PacketHit<T, W> h = rayproof::intersect(r, n.box, conservative);
            for (int i = 0; i < W; ++i) t[i] = double(h.t_enter[i]);
            return h.mask;
        }
    }

    struct Entry {
        std::uint32_t first, count;  // as a node lane: count 0 an inner node
        double t;                    // the lane's t_enter (conservative, certified: a lower bound)
    };
    // A deferred lane's memory: its node, or its leaf's primitives (their compact balls
    // where there are any).
    RAYPROOF_ALWAYS_INLINE void prefetch(const Entry& e) const noexcept {
        if (e.count == 0) detail::prefetch(&nodes_[e.first], sizeof(Node));
        else if (e.first < balls_.size()) detail::prefetch(&balls_[e.first], e.count * sizeof(Sphere<T>));
        else detail::prefetch(&prims_[e.first], e.count * sizeof(Primitive<T>));
    }

    // A node's balls, fetched while the node is tested: its lane 0 starts the node's range
    // of positions (the build splits a range into [begin, s) kept in lane 0 and [s, end)
    // appended), so where lane 0 is a leaf of balls the W balls from there are the
    // node's own when its lanes are all single-ball leaves (the lowest nodes) and its
    // neighbours otherwise. A hint: no effect on any answer.
    RAYPROOF_ALWAYS_INLINE void prefetch_balls(const Node& n) const noexcept {
        const std::size_t p = n.first[0];
        if (n.count[0] != 0 && p < balls_.size())
            detail::prefetch(&balls_[p], std::min(std::size_t(W), balls_.size() - p) * sizeof(Sphere<T>));
    }

    // The stored primitive p's answer in the mode: from its compact copy in balls_ when
    // it is a ball (the same values, so the very Hit), else from prims_. Called only
    // inside closest_in_env and any_in_env, whose callers hold the environment.
    template <class Mode>
    RAYPROOF_ALWAYS_INLINE Hit<T> hit_at(const PreparedRay<T>& ray, std::size_t p, Mode mode) const noexcept {
        if (p < balls_.size()) {
            const Sphere<T>& b = balls_[p];
            if (!std::isnan(b.radius)) [[likely]]
                return detail::query_in_env(ray, b, mode);
        }
        return detail::intersect_primitive(ray, prims_[p], mode);
    }
    static constexpr std::size_t stack_capacity = std::size_t(detail::bvh_max_depth + 1) * std::size_t(W);

    // Known: the default floating-point environment is established (closest_hit,
    // any_hit), so the node filter runs without checking it.
    template <bool Known, class Mode, class F>
    void traverse(const PreparedRay<T>& ray, Mode mode, T& t_limit, F& f) const {
        const T t_min = ray.ray().t_min, t_max = ray.ray().t_max;
        // The node ray on [t_min, min(t_limit, t_max)], selected by the bits; invalid
        // (t_limit below t_min, or NaN) means nothing more can be met.
        T limit = t_limit;
        auto narrowed = [&](T lim) noexcept {
            const bool keep = (lim < t_max) | (lim != lim);  // NaN: an invalid range
            return ray.with_range(t_min, detail::bvh_select(keep, lim, t_max));
        };
        PreparedRay<T> nr = narrowed(limit);
        if (!nr.valid()) return;
        double cut = double(nr.ray().t_max);
        // nr's reciprocals are ray's
        const detail::BvhFilter which = std::is_same_v<Mode, fast_t>         ? detail::bvh_fast_filter_for(ray)
                                        : detail::bvh_scaled_usable(ray, extent_) ? detail::BvhFilter::scaled
                                                                                  : detail::bvh_filter_for(ray);

        // cur: the lane being answered; the stack holds the lanes deferred, nearest on
        // top. A hit lane of a node test on the current range has its t_enter bound at
        // most that range's end (its mask says the entry does not lie beyond the exit),
        // so the nearest hit lane is answered at once; only popped lanes, deferred while
        // the range may have shrunk, are checked against it.
        std::array<Entry, stack_capacity> stack;
        std::size_t sp = 0;
        Entry cur{0, 0, -detail::inf<double>};
        for (;;) {
            if (cur.count > 0) {
                for (std::uint32_t k = cur.first; k < cur.first + cur.count; ++k) {
                    if (!f(std::size_t(k))) return;
                    if (!(t_limit == limit)) {  // f moved the limit (bits differ or NaN)
                        limit = t_limit;
                        nr = narrowed(limit);
                        if (!nr.valid()) return;
                        cut = double(nr.ray().t_max);
                    }
                }
            } else {
                const Node& n = nodes_[cur.first];
                prefetch_balls(n);
                TEntry<Mode> t[std::size_t(W)];
                std::uint32_t mask = node_test<Known>(nr, n, mode, which, t);
                if (mask != 0) {
                    const int i = std::countr_zero(mask);
                    mask &= mask - 1;
                    const Entry a{n.first[i], n.count[i], double(t[i])};
                    if (mask == 0) {  // one hit lane: answered next, no stack
                        cur = a;
                        continue;
                    }
                    const int j = std::countr_zero(mask);
                    mask &= mask - 1;
                    const Entry b{n.first[j], n.count[j], double(t[j])};
                    if (mask == 0) {  // two: the farther deferred (ties: the lower lane first)
                        const bool a_first = !(b.t < a.t);
                        const Entry& far = a_first ? b : a;
                        prefetch(far);
                        stack[sp++] = far;
                        cur = a_first ? a : b;
                        continue;
                    }
                    // More: sorted by t_enter, descending (ties: the lower lane last, so
                    // answered first), all but the nearest deferred.
                    Entry hits[std::size_t(W)];
                    hits[0] = a;
                    int m = 1;
                    auto insert = [&](const Entry& c) {
                        int k = m++;
                        for (; k > 0 && hits[k - 1].t <= c.t; --k) hits[k] = hits[k - 1];
                        hits[k] = c;
                    };
                    insert(b);
                    for (std::uint32_t u = mask; u != 0; u &= u - 1) {
                        const int l = std::countr_zero(u);
                        insert(Entry{n.first[l], n.count[l], double(t[l])});
                    }
                    for (int k = 0; k + 1 < m; ++k) {
                        prefetch(hits[k]);  // fetched while the nearest is answered
                        stack[sp++] = hits[k];
                    }
                    cur = hits[m - 1];
                    continue;
                }
            }
            // The next deferred lane whose entry does not lie beyond the range.
            do {
                if (sp == 0) return;
                cur = stack[--sp];
            } while (cur.t > cut);
        }
    }

    // --- build ---------------------------------------------------------------------------
    struct Ref {
        T lo[3], hi[3];
        double c[3];  // the centroid, lo/2 + hi/2 (no overflow)
        std::uint32_t index;
    };
    struct Range {
        std::uint32_t begin, end;
        T lo[3], hi[3];
        std::uint32_t size() const { return end - begin; }
    };

    static double half_area(const T* lo, const T* hi) {
        const double x = double(hi[0]) - double(lo[0]), y = double(hi[1]) - double(lo[1]),
                     z = double(hi[2]) - double(lo[2]);
        return x * y + y * z + z * x;
    }

    Range make_range(std::uint32_t b, std::uint32_t e) const {
        Range r{b, e, {}, {}};
        for (int a = 0; a < 3; ++a) {
            r.lo[a] = detail::inf<T>;
            r.hi[a] = -detail::inf<T>;
        }
        for (std::uint32_t k = b; k < e; ++k)
            for (int a = 0; a < 3; ++a) {
                r.lo[a] = std::min(r.lo[a], refs_[k].lo[a]);
                r.hi[a] = std::max(r.hi[a], refs_[k].hi[a]);
            }
        return r;
    }

    // Splits r's references in place into two nonempty halves; returns the split position.
    std::uint32_t split(const Range& r, int depth, int bins) {
        double clo[3], chi[3];
        for (int a = 0; a < 3; ++a) {
            clo[a] = detail::inf<double>;
            chi[a] = -detail::inf<double>;
        }
        for (std::uint32_t k = r.begin; k < r.end; ++k)
            for (int a = 0; a < 3; ++a) {
                clo[a] = std::min(clo[a], refs_[k].c[a]);
                chi[a] = std::max(chi[a], refs_[k].c[a]);
            }
        // Halved, so that the extent cannot overflow; not > 0 (equal, or subnormals
        // halved to equal values) marks an axis the bins cannot use.
        double ext[3];
        for (int a = 0; a < 3; ++a) ext[a] = chi[a] * 0.5 - clo[a] * 0.5;
        auto bin_of = [&](const Ref& ref, int a) {
            const double t = (ref.c[a] * 0.5 - clo[a] * 0.5) / ext[a] * double(bins);
            return int(std::min(double(bins - 1), std::max(0.0, t)));  // NaN -> 0
        };
        if (depth < detail::bvh_sah_depth) {
            double best_cost = detail::inf<double>;
            int best_axis = -1, best_bin = -1;
            struct Bin {
                T lo[3], hi[3];
                std::uint32_t n;
            };
            std::vector<Bin> bin(static_cast<std::size_t>(bins));
            std::vector<double> right_cost(static_cast<std::size_t>(bins));
            for (int a = 0; a < 3; ++a) {
                if (!(ext[a] > 0)) continue;
                for (Bin& b : bin) {
                    b.n = 0;
                    for (int i = 0; i < 3; ++i) {
                        b.lo[i] = detail::inf<T>;
                        b.hi[i] = -detail::inf<T>;
                    }
                }
                for (std::uint32_t k = r.begin; k < r.end; ++k) {
                    Bin& b = bin[std::size_t(bin_of(refs_[k], a))];
                    ++b.n;
                    for (int i = 0; i < 3; ++i) {
                        b.lo[i] = std::min(b.lo[i], refs_[k].lo[i]);
                        b.hi[i] = std::max(b.hi[i], refs_[k].hi[i]);
                    }
                }
                // right_cost[j]: area · count of bins j .. bins-1.
                Bin acc{{detail::inf<T>, detail::inf<T>, detail::inf<T>}, {-detail::inf<T>, -detail::inf<T>, -detail::inf<T>}, 0};
                for (int j = bins - 1; j >= 1; --j) {
                    const Bin& b = bin[std::size_t(j)];
                    acc.n += b.n;
                    for (int i = 0; i < 3; ++i) {
                        acc.lo[i] = std::min(acc.lo[i], b.lo[i]);
                        acc.hi[i] = std::max(acc.hi[i], b.hi[i]);
                    }
                    right_cost[std::size_t(j)] = acc.n ? half_area(acc.lo, acc.hi) * double(acc.n) : 0.0;
                }
                acc = Bin{{detail::inf<T>, detail::inf<T>, detail::inf<T>}, {-detail::inf<T>, -detail::inf<T>, -detail::inf<T>}, 0};
                for (int j = 0; j + 1 < bins; ++j) {
                    const Bin& b = bin[std::size_t(j)];
                    acc.n += b.n;
                    for (int i = 0; i < 3; ++i) {
                        acc.lo[i] = std::min(acc.lo[i], b.lo[i]);
                        acc.hi[i] = std::max(acc.hi[i], b.hi[i]);
                    }
                    if (acc.n == 0 || acc.n == r.size()) continue;
                    const double cost = half_area(acc.lo, acc.hi) * double(acc.n) + right_cost[std::size_t(j + 1)];
                    if (cost < best_cost) {
                        best_cost = cost;
                        best_axis = a;
                        best_bin = j;
                    }
                }
            }
            if (best_axis >= 0) {
                const auto mid = std::partition(refs_.begin() + r.begin, refs_.begin() + r.end,
                                                [&](const Ref& ref) { return bin_of(ref, best_axis) <= best_bin; });
                const auto s = std::uint32_t(mid - refs_.begin());
                if (s > r.begin && s < r.end) return s;
            }
        }
        // The object median on the widest centroid axis (any axis when none is wide).
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (ext[a] > ext[axis]) axis = a;
        const std::uint32_t s = r.begin + r.size() / 2;
        std::nth_element(refs_.begin() + r.begin, refs_.begin() + s, refs_.begin() + r.end,
                         [axis](const Ref& x, const Ref& y) {
                             return x.c[axis] < y.c[axis] || (!(y.c[axis] < x.c[axis]) && x.index < y.index);
                         });
        return s;
    }

    void build(BvhOptions opt) {
        const auto leaf_size = std::uint32_t(std::clamp(opt.leaf_size, 1, 255));
        const int bins = std::clamp(opt.bins, 2, 256);
        // Primitives beyond 2^32 - 2 are kept beside the tree (uint32 indices in it).
        constexpr std::size_t max_in_tree = std::numeric_limits<std::uint32_t>::max() - 1;
        for (std::size_t i = 0; i < prims_.size(); ++i) {
            const std::optional<Aabb<T>> b = i < max_in_tree ? detail::bvh_box(prims_[i]) : std::nullopt;
            if (!b) {
                outside_.push_back(i);
                continue;
            }
            Ref r;
            for (int a = 0; a < 3; ++a) {
                r.lo[a] = b->lo[a];
                r.hi[a] = b->hi[a];
                r.c[a] = double(r.lo[a]) * 0.5 + double(r.hi[a]) * 0.5;
            }
            r.index = std::uint32_t(i);
            refs_.push_back(r);
        }
        if (refs_.empty()) {
            finish();
            return;
        }
        struct Task {
            std::uint32_t parent;  // node index; unused for the root
            int lane;              // -1: the root
            Range range;
            int depth;
        };
        std::vector<Task> tasks;
        tasks.push_back(Task{0, -1, make_range(0, std::uint32_t(refs_.size())), 1});
        while (!tasks.empty()) {
            const Task task = tasks.back();
            tasks.pop_back();
            const auto id = std::uint32_t(nodes_.size());
            if (task.lane >= 0) nodes_[task.parent].first[task.lane] = id;
            depth_ = std::max(depth_, task.depth);
            // The node's children: the range, then a child split until W children or
            // none is left to split: the largest (by surface area) of those too big for
            // one node of leaves (more than W·leaf_size primitives) while there are
            // such, then the largest whose primitives all fit as leaves in the lanes
            // left (ceil(size / leaf_size) - 1 <= W - n), so that small ranges fill this
            // node instead of spreading over nodes of a few lanes each. The node's own
            // range is always split (it is either too big or fits all W lanes), so every
            // inner child's range is strictly smaller than the node's.
            Range child[std::size_t(W)];
            int n = 1;
            child[0] = task.range;  // lane 0 keeps the range's begin (prefetch_balls)
            const std::uint32_t node_cap = std::uint32_t(W) * leaf_size;
            while (n < W) {
                bool big = false;
                for (int i = 0; i < n; ++i) big |= child[i].size() > node_cap;
                int pick = -1;
                double pick_area = -1;
                for (int i = 0; i < n; ++i) {
                    if (child[i].size() <= leaf_size) continue;
                    const std::uint32_t leaves = (child[i].size() + leaf_size - 1) / leaf_size;
                    if (big ? child[i].size() <= node_cap : leaves - 1 > std::uint32_t(W - n)) continue;
                    const double area = half_area(child[i].lo, child[i].hi);
                    // NaN or inf areas still count (>= keeps the first such child).
                    if (pick < 0 || area > pick_area) {
                        pick = i;
                        pick_area = area;
                    }
                }
                if (pick < 0) break;
                const Range c = child[pick];
                const std::uint32_t s = split(c, task.depth, bins);
                child[pick] = make_range(c.begin, s);
                child[n++] = make_range(s, c.end);
            }
            Node node;
            for (int i = 0; i < W; ++i) {
                for (int a = 0; a < 3; ++a) {
                    node.box.lo[a][i] = detail::inf<T>;
                    node.box.hi[a][i] = -detail::inf<T>;
                }
                node.first[i] = 0;
                node.count[i] = 0;
            }
            for (int i = 0; i < n; ++i) {
                for (int a = 0; a < 3; ++a) {
                    node.box.lo[a][i] = child[i].lo[a];
                    node.box.hi[a][i] = child[i].hi[a];
                }
                if (child[i].size() <= leaf_size) {
                    node.first[i] = child[i].begin;
                    node.count[i] = child[i].size();
                }
            }
            nodes_.push_back(node);
            for (int i = n - 1; i >= 0; --i)
                if (child[i].size() > leaf_size) tasks.push_back(Task{id, i, child[i], task.depth + 1});
        }
        finish();
    }

    void finish() {
        order_.resize(refs_.size());
        for (std::size_t k = 0; k < refs_.size(); ++k) order_[k] = refs_[k].index;
        refs_.clear();
        refs_.shrink_to_fit();
        // The copies into stored order (position p takes the primitive index_of(p), a
        // permutation), in place, one cycle at a time.
        std::vector<bool> placed(prims_.size(), false);
        for (std::size_t p = 0; p < prims_.size(); ++p) {
            if (placed[p]) continue;
            Primitive<T> first = std::move(prims_[p]);
            std::size_t q = p;
            for (;;) {
                placed[q] = true;
                const std::size_t from = index_of(q);
                if (from == p) {
                    prims_[q] = std::move(first);
                    break;
                }
                prims_[q] = std::move(prims_[from]);
                q = from;
            }
        }
        // The tree's balls again, compactly: 16 bytes each in float, where the variant
        // takes 72 and keeps its tag on a second cache line (the leaves' hot data, half
        // the leaf test's time on 100,000 balls went to loading that tag). Position p of
        // the tree holds its ball, or a NaN radius where p is another primitive (never
        // a ball of the tree: an invalid ball has no enclosing box). Empty when the tree
        // has no ball.
        const std::size_t in_tree = order_.size();
        const auto tree_end = prims_.begin() + std::ptrdiff_t(in_tree);
        const auto is_ball = [](const Primitive<T>& p) { return std::holds_alternative<Sphere<T>>(p); };
        if (std::any_of(prims_.begin(), tree_end, is_ball)) {
            const Sphere<T> none{Vec3<T>::Zero(), std::numeric_limits<T>::quiet_NaN()};
            balls_.assign(in_tree, none);
            for (std::size_t p = 0; p < in_tree; ++p)
                if (const Sphere<T>* b = std::get_if<Sphere<T>>(&prims_[p])) balls_[p] = *b;
        }
        nodes_.shrink_to_fit();
        outside_.shrink_to_fit();
        // The largest finite box coordinate in magnitude (the root's lanes enclose every
        // node's; empty slots are infinite and skipped), for bvh_scaled_usable.
        extent_ = 0;
        if (!nodes_.empty())
            for (int a = 0; a < 3; ++a)
                for (int i = 0; i < W; ++i)
                    if (nodes_[0].box.lo[a][i] <= nodes_[0].box.hi[a][i])
                        extent_ = std::max({extent_, std::abs(double(nodes_[0].box.lo[a][i])),
                                            std::abs(double(nodes_[0].box.hi[a][i]))});
    }

    std::vector<Primitive<T>> prims_;      // in stored order (stored())
    std::vector<Sphere<T>> balls_;         // the tree's balls by position, or empty (finish())
    std::vector<Node> nodes_;              // nodes_[0] the root (when there is a tree)
    std::vector<std::uint32_t> order_;     // leaf positions -> primitive indices
    std::vector<std::size_t> outside_;     // primitives beside the tree, ascending
    std::vector<Ref> refs_;                // the build's scratch (empty after it)
    int depth_ = 0;
    double extent_ = 0;  // the largest finite box coordinate in magnitude (finish())
};

}  // namespace rayproof
