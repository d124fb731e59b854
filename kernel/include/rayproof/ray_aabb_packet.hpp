// rayproof/ray_aabb_packet.hpp — one prepared ray against a packet of W = 4 or 8
// axis-aligned boxes in SIMD lanes: the node test of a wide BVH.
//
// Lanes:     lane i is the box lo = (lo[0][i], lo[1][i], lo[2][i]), hi likewise, the
//            closed solid lo <= p <= hi of ray_aabb.hpp. Bit i of the mask is 1 exactly
//            when lane i's verdict is hit; t_enter[i], t_exit[i], face[i] are that
//            lane's Hit fields (a miss and an empty slot have 0, 0, -1, the fields of a
//            scalar miss). Each lane obeys its mode's contract for its box.
// Empty slots: a lane with lo > hi on some axis, or any non-finite bound, is an empty
//            slot: bit 0, never an error (the way a BVH pads a node). An invalid ray
//            (PreparedRay::valid() false) gives mask 0 in every mode.
// Algorithm: the slab method (Kay & Kajiya 1986) per lane with the prepared reciprocals,
//            as in pbrt-v4's Bounds3::IntersectP and Embree's wide-node intersector: per
//            axis the near plane (lo for d_i > 0, hi for d_i < 0, chosen once per ray by
//            the sign of d_i) gives the entry, the far plane the exit; the latest entry
//            and the earliest exit, clamped to [t_min, t_max], overlap on a hit.
//            The vectors are detail/simd.hpp's (SSE2, AVX2 where compiled for it, or
//            plain arrays), chosen at compile time; every function below also takes the
//            backend as a template argument (detail::packet_verdict<B>), so the tests run
//            the portable and the native backend side by side.
// Degenerate cases: d_i = ±0 (the ray is parallel to slab i) is known per ray, and the
//            axis is decided exactly in every mode by lo_i <= o_i <= hi_i (an origin on a
//            slab plane is inside): its slab values are never computed, so no lane sees
//            0·inf. Flat boxes (lo_i == hi_i) are valid.
// Modes:     fast — in T with the prepared reciprocals inv_i = fl_T(1/d_i): each slab
//            value (p - o)·inv is the exact one times (1+δ), |δ| <= gamma(3) (T = double:
//            gamma(2)) while nothing over- or underflows; one mask, no promise beyond
//            the empty slots, invalid rays and parallel axes above (a lane whose slab
//            values overflow is answered as a miss).
//            conservative and certified — in double (float input is widened exactly), for
//            each axis with 1/d_i normal: t~ = fl(fl(p - o)·rinv_i), rinv_i = fl(1/d_i)
//            (PreparedRay::rinv). (The certified filter of a float packet runs in float
//            instead, below.) Error bound (the derivation of ray_aabb.hpp): with
//            rinv_i normal and finite, p - o exact when subnormal and a subnormal product
//            off by at most 2^-1075, |t~ - t| <= gamma(3)|t| + 2^-1075, and the enclosure
//                lo(t~) = fl(t~ - fl(fl(K|t~|) + eta)), hi(t~) = fl(t~ + fl(fl(K|t~|) + eta)),
//            K = 2·gamma(3), eta = 2^-1022, contains t: K|t~|(1 - u)^2 - u|t~|(1 + K) >=
//            gamma(3)/(1 - gamma(3))|t~| covers the value's three roundings and the
//            bound's own two, and eta the absolute 2^-1075 and the roundings of
//            subnormal ends. Both computed ends increase with t~ (as in ray_aabb.hpp's
//            aabb_lanes), so the exact latest entry E lies in [max(t_min, lo(m)),
//            max(t_min, hi(m))], m the largest computed entry, and the exact earliest
//            exit X in [min(t_max, lo(M)), min(t_max, hi(M))], M the smallest computed
//            exit. Certified float packets: the same filter in float, eight lanes to a
//            register, with inv_i = fl_f(rinv_i) (PreparedRay::inv) where every inv_i is a
//            normal finite float (|d_i| in [2^-128, 2^126]; otherwise the double filter):
//            inv_i = (1/d_i)(1 + a)(1 + b), |a| <= 2^-53, |b| <= u = 2^-24; fl_f(p - o)
//            is exact when subnormal; the product adds (1 + c) and an absolute 2^-150, so
//            |t~ - t| <= ((1 + u)^4 - 1)|t| + 2^-150 <= gamma_f(4)|t| + 2^-150, and the ends
//            with K = 2·gamma_f(4), eta = 2^-126 (the smallest normal float) cover it as in
//            double: K|t~|(1 - u)^2 - u|t~|(1 + K) >= gamma_f(4)/(1 - gamma_f(4))|t~|
//            (about 7u against 4u), eta the absolute terms.
//            Contraction (eft.hpp): the six products are rounded() (class C3: the
//            probe and the bounds must see the values the comparisons see); the bounds
//            are class C1.
//            conservative — hit unless max(t_min, lo(m)) > min(t_max, hi(M)) (never a
//            false miss), t_enter = that lower end rounded down to T, t_exit the upper
//            end rounded up (the enclosure of [E, X]); face the axis of the largest lower
//            entry bound, the lowest axis on ties, -1 when t_min is not exceeded. The
//            bounds are taken per axis here (lo of each entry, hi of each exit).
//            certified — the filter: a lane is a proven hit when hi(E) <= lo(X), a proven
//            miss when lo(E) > hi(X) or a parallel axis has the origin outside (with
//            t_min and t_max taken into m and M before the bounds: certified_filter_in;
//            a double packet of eight in two halves of four, lane for lane the same);
//            only the lanes it cannot separate, and the lanes where a value or the probe
//            is not finite (overflow), go to the scalar certified query (ray_aabb.hpp),
//            one by one. intersect() answers in lanes only the proven misses (their
//            fields are fixed); each hit needs its winners' faithful rounding, which the
//            scalar query does, so a certified lane equals the scalar certified answer
//            bit for bit, and verdict() == intersect().mask (a verdict is exact either
//            way). A ray with some |d_i| >= 2^1022 (1/d_i subnormal: the bound fails)
//            goes to the scalar query in every lane, as do conservative lanes whose
//            values overflow.
// Environment: the conservative and certified forms answer in the default
//            floating-point environment whatever the caller's (detail/fp_env.hpp),
//            read once per packet (the lanes' scalar queries run inside it:
//            detail::query_in_env, no read of their own), or not at all in the
//            forms that take an FpEnvScope (fp_env_scope.hpp).
// No allocation, no exception.
#pragma once

#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/fp_env.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/detail/simd.hpp>
#include <rayproof/fp_env_scope.hpp>
#include <rayproof/intersect.hpp>
#include <rayproof/prepared_ray.hpp>
#include <rayproof/ray_aabb.hpp>
#include <rayproof/types.hpp>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace rayproof {

// W boxes, one per lane, structure of arrays: lane i is lo = (lo[0][i], lo[1][i],
// lo[2][i]), hi likewise. W = 4 or 8.
template <class T, int W> struct AabbPacket {
    static_assert(is_scalar_v<T> && (W == 4 || W == 8), "AabbPacket<T, W>: T float or double, W 4 or 8");
    T lo[3][std::size_t(W)];
    T hi[3][std::size_t(W)];

    // Lane i as a box.
    [[nodiscard]] Aabb<T> box(int i) const {
        return Aabb<T>{Vec3<T>(lo[0][i], lo[1][i], lo[2][i]), Vec3<T>(hi[0][i], hi[1][i], hi[2][i])};
    }
    // Sets lane i to the box b.
    void set(int i, const Aabb<T>& b) {
        for (int a = 0; a < 3; ++a) {
            lo[a][i] = b.lo[a];
            hi[a][i] = b.hi[a];
        }
    }
};

// The answer per lane: bit i of mask is lane i's hit; the fields as in Hit<T>.
template <class T, int W> struct PacketHit {
    std::uint32_t mask;
    T t_enter[std::size_t(W)];
    T t_exit[std::size_t(W)];
    int face[std::size_t(W)];

    // Lane i's answer as a Hit (hit or miss; a packet has no invalid lane).
    [[nodiscard]] Hit<T> lane(int i) const noexcept {
        Hit<T> h;
        h.verdict = ((mask >> i) & 1u) ? Verdict::hit : Verdict::miss;
        h.t_enter = t_enter[i];
        h.t_exit = t_exit[i];
        h.face = face[i];
        return h;
    }
};

namespace detail {

namespace packet {

// The filter's constants in its arithmetic E (see the header comment): double, K =
// 2·gamma(3), eta = 2^-1022; float, K = 2·gamma_f(4), eta = 2^-126.
template <class E> struct Bound;
template <> struct Bound<double> {
    static constexpr double K = 2 * gamma<double>(3), eta = 0x1p-1022;
};
template <> struct Bound<float> {
    static constexpr float K = 2 * gamma<float>(4), eta = 0x1p-126f;
};

// Empty slots. On a parallel axis, the lanes whose two bounds are finite with lo <= hi:
// |lo|, |hi| <= the largest finite T and lo <= hi, all false on a NaN (box_ok, in E:
// double or float, from the packet's T values). On the other axes lo <= hi alone: an
// infinite bound makes its slab value infinite (1/d is finite and nonzero there), which
// the lane's probe catches (sum - sum is NaN), and a lane that fails the probe is an
// empty slot in fast mode and goes to the scalar query, which finds it invalid, in the
// other two.
template <class E, int W, class B, class T>
RAYPROOF_ALWAYS_INLINE simd::Mask<E, W, B> box_ok(const simd::Vec<E, W, B>& lo, const simd::Vec<E, W, B>& hi) {
    using V = simd::Vec<E, W, B>;
    const V big = V::splat(E(std::numeric_limits<T>::max()));
    return (lo <= hi) & (abs(lo) <= big) & (abs(hi) <= big);
}

// The reciprocal the filter in E uses: rinv_i = fl(1/d_i) in double, inv_i =
// fl_float(rinv_i) in float.
template <class E, class T> RAYPROOF_ALWAYS_INLINE E reciprocal(const PreparedRay<T>& pr, int i) {
    if constexpr (std::is_same_v<E, double>) return pr.rinv(i);
    else return pr.inv(i);
}

template <class T, int W> PacketHit<T, W> empty_hit() {
    PacketHit<T, W> h;
    h.mask = 0;
    for (int i = 0; i < W; ++i) {
        h.t_enter[i] = 0;
        h.t_exit[i] = 0;
        h.face[i] = -1;
    }
    return h;
}

template <class T, int W> void put(PacketHit<T, W>& h, int i, const Hit<T>& s) {
    const bool hit = s.verdict == Verdict::hit;
    h.mask |= std::uint32_t(hit) << i;
    h.t_enter[i] = hit ? s.t_enter : T(0);
    h.t_exit[i] = hit ? s.t_exit : T(0);
    h.face[i] = hit ? s.face : -1;
}

// --- fast ------------------------------------------------------------------------------
// The fast lanes of a valid prepared ray: ok (the lane's verdict is hit), the latest
// entry and the earliest exit clamped to [t_min, t_max], and with Face the face codes
// (-1 where t_min is not exceeded). Lanes outside ok hold unspecified values.
template <class T, int W, class B> struct FastLanes {
    simd::Mask<T, W, B> ok;
    simd::Vec<T, W, B> enter, exit, face;
};
template <class B, bool Face, bool MayBeParallel, class T, int W>
RAYPROOF_ALWAYS_INLINE FastLanes<T, W, B> fast_lanes_of(const PreparedRay<T>& pr, const AabbPacket<T, W>& b) {
    using V = simd::Vec<T, W, B>;
    using M = simd::Mask<T, W, B>;
    const Ray<T>& r = pr.ray();
    FastLanes<T, W, B> l{M::all(), V::splat(r.t_min), V::splat(r.t_max), V::splat(T(-1))};
    M& ok = l.ok;
    V sum = V::splat(T(0));
    RAYPROOF_UNROLL3
    for (int i = 0; i < 3; ++i) {
        const V lo = V::load(b.lo[i]), hi = V::load(b.hi[i]), o = V::splat(r.origin[i]);
        if constexpr (MayBeParallel)
            if (r.direction[i] == 0) {  // parallel: exactly, never 0·inf
                ok = ok & box_ok<T, W, B, T>(lo, hi) & (lo <= o) & (o <= hi);
                continue;
            }
        ok = ok & (lo <= hi);
        const bool neg = pr.negative(i);
        const V inv = V::splat(pr.inv(i));
        // Near and far slab values by min and max, not by the ray's sign: a ternary on the
        // sign became a jump per axis that fresh rays mispredict (measured, float W = 8,
        // fresh pairs: 1.7 ns a box test with it, 0.94-1.10 without). They are the same values:
        // a NaN (lo or hi NaN, or 0·inf when inv is infinite) drops the lane through
        // lo <= hi or the probe, since the other value of the axis is then infinite or NaN.
        const V t1 = (lo - o) * inv, t2 = (hi - o) * inv;
        const V tn = min(t1, t2), tf = max(t1, t2);
        sum = sum + (tn + tf);
        if constexpr (Face) l.face = select(tn > l.enter, V::splat(T(2 * i + int(neg))), l.face);
        l.enter = max(tn, l.enter);
        l.exit = min(tf, l.exit);
    }
    // The probe (see box_ok): an infinite bound gives an infinite slab value, even fused
    // into the sum (an infinite operand); an overflowed value of a valid box (fast
    // promises nothing there) drops the lane too.
    ok = ok & ((sum - sum) == V::splat(T(0))) & (l.enter <= l.exit);
    return l;
}

// A ray with no axis parallel (the common case; decided once by the prepared ray,
// parallel_axes) takes the lanes without a test per axis: measured in one program,
// float W = 8, AVX2, shuffled pairs, 0.58 ns a box test against 0.61-0.63 with the three
// tests. The certified filter keeps its tests: the same split there measured slower
// (1.03 against 0.94), its two copies inlined into every caller.
template <class B, bool Face, class T, int W>
RAYPROOF_ALWAYS_INLINE FastLanes<T, W, B> fast_lanes(const PreparedRay<T>& pr, const AabbPacket<T, W>& b) {
    if (pr.parallel_axes() == 0) [[likely]]
        return fast_lanes_of<B, Face, false>(pr, b);
    return fast_lanes_of<B, Face, true>(pr, b);
}

// Full: the PacketHit; else the mask alone.
template <class B, bool Full, class T, int W>
RAYPROOF_ALWAYS_INLINE auto fast(const PreparedRay<T>& pr, const AabbPacket<T, W>& b) {
    using V = simd::Vec<T, W, B>;
    using Out = std::conditional_t<Full, PacketHit<T, W>, std::uint32_t>;
    if (!pr.valid()) {
        if constexpr (Full) return empty_hit<T, W>();
        else return Out(0);
    }
    const FastLanes<T, W, B> l = fast_lanes<B, Full>(pr, b);
    if constexpr (!Full) {
        return l.ok.bits();
    } else {
        PacketHit<T, W> h;
        h.mask = l.ok.bits();
        const V zero = V::splat(T(0));
        select(l.ok, l.enter, zero).store(h.t_enter);
        select(l.ok, l.exit, zero).store(h.t_exit);
        T f[std::size_t(W)];
        select(l.ok, l.face, V::splat(T(-1))).store(f);
        for (int i = 0; i < W; ++i) h.face[i] = int(f[i]);
        return h;
    }
}

// --- the filter (conservative: in double; certified: in float for float packets, else
// in double) --------------------------------------------------------------------------
template <class E, class B, class T, int W> struct Filtered {
    using V = simd::Vec<E, W, B>;
    using M = simd::Mask<E, W, B>;
    M ok;      // lo <= hi, finite on parallel axes, which hold the origin (see box_ok)
    M finite;  // every computed slab value finite
    V m, M_;   // certified: the largest computed entry and t_min, the smallest computed exit and t_max
    V e_lo, x_hi, face;  // conservative only: per-axis bounds, face code
};

// The N lanes of the packet from lane `first` on (N = W, first = 0: the whole packet).
template <class E, class B, bool Conservative, int N, class T, int W>
RAYPROOF_ALWAYS_INLINE Filtered<E, B, T, N> filter(const PreparedRay<T>& pr, const AabbPacket<T, W>& b, int first) {
    using V = simd::Vec<E, N, B>;
    using M = simd::Mask<E, N, B>;
    const Ray<T>& r = pr.ray();
    Filtered<E, B, T, N> f;
    const V K = V::splat(Bound<E>::K), eta = V::splat(Bound<E>::eta);
    f.ok = M::all();
    // certified: the limits taken into the latest entry and the earliest exit (see
    // certified_filter_in); conservative: the limits kept apart (e_lo, x_hi)
    f.m = f.e_lo = V::splat(E(r.t_min));
    f.M_ = f.x_hi = V::splat(E(r.t_max));
    f.face = V::splat(E(-1));
    V sum = V::splat(E(0));
    RAYPROOF_UNROLL3
    for (int i = 0; i < 3; ++i) {
        const V lo = V::load(b.lo[i] + first), hi = V::load(b.hi[i] + first), o = V::splat(E(r.origin[i]));
        if (r.direction[i] == 0) {  // parallel: exactly, never 0·inf
            f.ok = f.ok & box_ok<E, N, B, T>(lo, hi) & (lo <= o) & (o <= hi);
            continue;
        }
        f.ok = f.ok & (lo <= hi);
        const bool neg = pr.negative(i);
        const V inv = V::splat(reciprocal<E>(pr, i));
        // Class C3 (eft.hpp): the probe and the bounds see these very values. The near and
        // far values by min and max, as fast_lanes_of takes them: the values a select on
        // the reciprocal's sign picks (the rounded slab value is monotone in the plane,
        // increasing for inv > 0 and decreasing for inv < 0, inv finite and nonzero here),
        // where lo <= hi; a lane with lo > hi or a NaN bound is dropped by ok. Without a
        // jump on `neg` (fresh pairs, float W = 8: 2.5 ns a box test with the jump, 1.6
        // with a select on the sign, 1.36 with a compare for it and two blends, against
        // min and max here).
        const V t1 = rounded((lo - o) * inv), t2 = rounded((hi - o) * inv);
        const V tn = min(t1, t2), tf = max(t1, t2);
        sum = sum + (tn + tf);
        if constexpr (Conservative) {
            const V lo_n = tn - (abs(tn) * K + eta), hi_f = tf + (abs(tf) * K + eta);
            f.face = select(lo_n > f.e_lo, V::splat(E(2 * i + int(neg))), f.face);
            f.e_lo = max(lo_n, f.e_lo);
            f.x_hi = min(hi_f, f.x_hi);
        } else {
            f.m = max(tn, f.m);
            f.M_ = min(tf, f.M_);
        }
    }
    // sum - sum is 0 when every term is finite (and their sum does not overflow), NaN
    // otherwise: the probe of ray_aabb.hpp.
    f.finite = (sum - sum) == V::splat(E(0));
    return f;
}

template <class B, bool Full, class T, int W>
RAYPROOF_ALWAYS_INLINE PacketHit<T, W> conservative(const PreparedRay<T>& pr, const AabbPacket<T, W>& b) {
    PacketHit<T, W> h = empty_hit<T, W>();
    if (!pr.valid()) return h;
    if (!pr.template reciprocals_usable_in<double>()) {
        for (int i = 0; i < W; ++i)
            if (valid(b.box(i))) put(h, i, query_in_env(pr, b.box(i), rayproof::conservative));
        return h;
    }
    const Filtered<double, B, T, W> f = filter<double, B, true, W>(pr, b, 0);
    const auto hit = f.ok & f.finite & (f.e_lo <= f.x_hi);
    h.mask = hit.bits();
    if constexpr (Full) {
        double lo[std::size_t(W)], hi[std::size_t(W)], face[std::size_t(W)];
        f.e_lo.store(lo);
        f.x_hi.store(hi);
        f.face.store(face);
        for (int i = 0; i < W; ++i)
            if ((h.mask >> i) & 1) {
                h.t_enter[i] = round_down_to<T>(lo[i]);
                h.t_exit[i] = round_up_to<T>(hi[i]);
                h.face[i] = int(face[i]);
            }
    }
    // Lanes whose values overflowed: the scalar conservative query.
    for (std::uint32_t u = simd::and_not(f.ok, f.finite).bits(); u != 0; u &= u - 1) {
        const int i = std::countr_zero(u);
        put(h, i, query_in_env(pr, b.box(i), rayproof::conservative));
    }
    return h;
}

// The certified filter's decisions: hit and miss proven (on lanes with ok), and the
// lanes it leaves to the scalar query.
struct Decided {
    std::uint32_t hit, undecided;
};
// The limits are taken into the computed values: m = max(t_min, m~) and M = min(t_max,
// M~), m~ the largest computed entry and M~ the smallest computed exit. The exact latest
// entry E = max(t_min, E~), E~ in [lo(m~), hi(m~)] (the header comment), lies in
// [lo(m), hi(m)]: where m = m~ since E >= E~ and hi(m~) >= m~ >= t_min; where m = t_min
// > m~ since lo(x) <= x <= hi(x) and hi increases with x (hi(m~) <= hi(t_min)).
// Likewise the exact earliest exit X in [lo(M), hi(M)]. So hi(m) <= lo(M) proves the
// hit and hi(M) < lo(m) the miss, with no clamping after the bounds. (An infinite limit
// that wins, every axis parallel, leaves a NaN end: neither proof, the scalar query
// answers.)
// Lanes first to first + N - 1; their bits in place.
template <class E, class B, int N, class T, int W>
RAYPROOF_ALWAYS_INLINE Decided certified_filter_lanes(const PreparedRay<T>& pr, const AabbPacket<T, W>& b, int first) {
    using V = simd::Vec<E, N, B>;
    const Filtered<E, B, T, N> f = filter<E, B, false, N>(pr, b, first);
    const V K = V::splat(Bound<E>::K), eta = V::splat(Bound<E>::eta);
    const V bm = abs(f.m) * K + eta, bM = abs(f.M_) * K + eta;
    const auto sure = f.ok & f.finite;
    const auto hit = sure & (f.m + bm <= f.M_ - bM);
    const auto miss = sure & (f.M_ + bM < f.m - bm);
    return {hit.bits() << first, and_not(f.ok, hit | miss).bits() << first};
}
// A packet whose values take more than 32 bytes of E (double, W = 8) is filtered as two
// halves one after the other: each lane's operations are the same, and the filter's
// dozen live vectors fit the registers (measured, certified verdict, -O2, ns per box
// test: AVX2 double W = 8, 2.63-2.79 in one pass against 2.31-2.36 in halves; SSE2
// double W = 8, 14.7 against 3.6; where the values take 32 bytes, halves were 2-6%
// slower: SSE2 float W = 8, 1.95 against 2.06, and double W = 4, 4.0 against 4.07).
template <class E, class B, class T, int W>
RAYPROOF_ALWAYS_INLINE Decided certified_filter_in(const PreparedRay<T>& pr, const AabbPacket<T, W>& b) {
    if constexpr (sizeof(E) * W > 32) {
        constexpr int H = W / 2;
        const Decided a = certified_filter_lanes<E, B, H>(pr, b, 0), c = certified_filter_lanes<E, B, H>(pr, b, H);
        return {a.hit | c.hit, a.undecided | c.undecided};
    } else {
        return certified_filter_lanes<E, B, W>(pr, b, 0);
    }
}

// The filter in float for a float packet whose reciprocals are normal floats, else in
// double where the double reciprocals are normal; otherwise every lane is undecided.
template <class B, class T, int W>
RAYPROOF_ALWAYS_INLINE Decided certified_filter(const PreparedRay<T>& pr, const AabbPacket<T, W>& b) {
    if constexpr (std::is_same_v<T, float>)
        if (pr.template reciprocals_usable_in<float>()) [[likely]]
            return certified_filter_in<float, B>(pr, b);
    if (pr.template reciprocals_usable_in<double>()) [[likely]]
        return certified_filter_in<double, B>(pr, b);
    return {0, (1u << W) - 1};
}

template <class B, class T, int W>
RAYPROOF_ALWAYS_INLINE std::uint32_t certified_verdict(const PreparedRay<T>& pr, const AabbPacket<T, W>& b) {
    if (!pr.valid()) return 0;
    const Decided d = certified_filter<B>(pr, b);
    std::uint32_t mask = d.hit;
    for (std::uint32_t u = d.undecided; u != 0; u &= u - 1) {
        const int i = std::countr_zero(u);
        mask |= std::uint32_t(verdict_in_env(pr, b.box(i), rayproof::certified) == Verdict::hit) << i;
    }
    return mask;
}

template <class B, class T, int W>
RAYPROOF_ALWAYS_INLINE PacketHit<T, W> certified_intersect(const PreparedRay<T>& pr, const AabbPacket<T, W>& b) {
    PacketHit<T, W> h = empty_hit<T, W>();
    if (!pr.valid()) return h;
    // Every proven hit needs its winners' faithful rounding: the scalar query does it,
    // with the undecided lanes.
    const Decided d = certified_filter<B>(pr, b);
    for (std::uint32_t u = d.hit | d.undecided; u != 0; u &= u - 1) {
        const int i = std::countr_zero(u);
        put(h, i, query_in_env(pr, b.box(i), rayproof::certified));
    }
    return h;
}

}  // namespace packet

// The packet queries with the backend B (simd::native or simd::portable) explicit: the
// public forms below use the native one.
template <class B, class T, int W>
[[nodiscard]] RAYPROOF_ALWAYS_INLINE std::uint32_t packet_verdict(const PreparedRay<T>& pr, const AabbPacket<T, W>& b,
                                                                  fast_t) noexcept {
    return packet::fast<B, false>(pr, b);
}
template <class B, class T, int W>
[[nodiscard]] RAYPROOF_ALWAYS_INLINE PacketHit<T, W> packet_intersect(const PreparedRay<T>& pr,
                                                                      const AabbPacket<T, W>& b, fast_t) noexcept {
    return packet::fast<B, true>(pr, b);
}
// The guarded modes' packet work itself, for a caller that has established the
// environment (the scoped forms below; the forms without a scope wrap it in the guard).
template <class B, class T, int W>
RAYPROOF_ALWAYS_INLINE std::uint32_t packet_verdict_in_env(const PreparedRay<T>& pr, const AabbPacket<T, W>& b,
                                                          conservative_t) noexcept {
    return packet::conservative<B, false>(pr, b).mask;
}
template <class B, class T, int W>
RAYPROOF_ALWAYS_INLINE PacketHit<T, W> packet_intersect_in_env(const PreparedRay<T>& pr, const AabbPacket<T, W>& b,
                                                              conservative_t) noexcept {
    return packet::conservative<B, true>(pr, b);
}
template <class B, class T, int W>
RAYPROOF_ALWAYS_INLINE std::uint32_t packet_verdict_in_env(const PreparedRay<T>& pr, const AabbPacket<T, W>& b,
                                                          certified_t) noexcept {
    return packet::certified_verdict<B>(pr, b);
}
template <class B, class T, int W>
RAYPROOF_ALWAYS_INLINE PacketHit<T, W> packet_intersect_in_env(const PreparedRay<T>& pr, const AabbPacket<T, W>& b,
                                                              certified_t) noexcept {
    return packet::certified_intersect<B>(pr, b);
}
// The guarded modes: their packet work in the default environment (detail/fp_env.hpp).
template <class B, class T, int W, class Mode>
    requires fp_env_guarded<Mode>
[[nodiscard]] inline std::uint32_t packet_verdict(const PreparedRay<T>& pr, const AabbPacket<T, W>& b, Mode) noexcept {
    return in_default_fp_env([](const PreparedRay<T>& r, const AabbPacket<T, W>& p)
                                 noexcept { return packet_verdict_in_env<B>(r, p, Mode{}); },
                             pr, b);
}
template <class B, class T, int W, class Mode>
    requires fp_env_guarded<Mode>
[[nodiscard]] inline PacketHit<T, W> packet_intersect(const PreparedRay<T>& pr, const AabbPacket<T, W>& b, Mode) noexcept {
    return in_default_fp_env([](const PreparedRay<T>& r, const AabbPacket<T, W>& p)
                                 noexcept { return packet_intersect_in_env<B>(r, p, Mode{}); },
                             pr, b);
}
// The packet's work in the environment already established, every mode (the fast one
// is not guarded): the bodies of the scoped forms (intersect.hpp's scoped_entry).
struct PacketVerdictInEnv {
    template <class T, int W, class Mode>
    RAYPROOF_ALWAYS_INLINE std::uint32_t operator()(const PreparedRay<T>& r, const AabbPacket<T, W>& b, Mode m) const noexcept {
        if constexpr (fp_env_guarded<Mode>)
            return packet_verdict_in_env<simd::native>(r, b, m);
        else
            return packet_verdict<simd::native>(r, b, m);
    }
};
struct PacketIntersectInEnv {
    template <class T, int W, class Mode>
    RAYPROOF_ALWAYS_INLINE PacketHit<T, W> operator()(const PreparedRay<T>& r, const AabbPacket<T, W>& b, Mode m) const noexcept {
        if constexpr (fp_env_guarded<Mode>)
            return packet_intersect_in_env<simd::native>(r, b, m);
        else
            return packet_intersect<simd::native>(r, b, m);
    }
};

}  // namespace detail

// Bit i: lane i's verdict is hit (see the header comment). Mode: fast, conservative or
// certified.
template <class T, int W, class Mode>
    requires is_mode_v<Mode>
[[nodiscard]] inline std::uint32_t verdict(const PreparedRay<T>& ray, const AabbPacket<T, W>& boxes, Mode mode) noexcept {
    return detail::packet_verdict<detail::simd::native>(ray, boxes, mode);
}

// The full answer per lane; verdict(...) == intersect(...).mask.
template <class T, int W, class Mode>
    requires is_mode_v<Mode>
[[nodiscard]] inline PacketHit<T, W> intersect(const PreparedRay<T>& ray, const AabbPacket<T, W>& boxes, Mode mode) noexcept {
    return detail::packet_intersect<detail::simd::native>(ray, boxes, mode);
}

// In an FpEnvScope (fp_env_scope.hpp): the same answers, without the per-call read of the
// control state. The packet's work is a few ns; on processors where that read costs as
// much, this is the form for a BVH's inner loop.
template <class T, int W, class Mode>
    requires is_mode_v<Mode>
[[nodiscard]] RAYPROOF_ALWAYS_INLINE std::uint32_t verdict(const PreparedRay<T>& ray, const AabbPacket<T, W>& boxes,
                                                           Mode mode, const FpEnvScope&) noexcept {
    return detail::scoped_entry<detail::PacketVerdictInEnv>(ray, boxes, mode);
}

template <class T, int W, class Mode>
    requires is_mode_v<Mode>
[[nodiscard]] RAYPROOF_ALWAYS_INLINE PacketHit<T, W> intersect(const PreparedRay<T>& ray, const AabbPacket<T, W>& boxes,
                                                               Mode mode, const FpEnvScope&) noexcept {
    return detail::scoped_entry<detail::PacketIntersectInEnv>(ray, boxes, mode);
}

}  // namespace rayproof
