// rayproof/detail/slab_certified.hpp — the slab method for the conservative and the
// certified modes, shared by Ray/Aabb and Ray/Obb (after the change of frame).
//
// A frame describes, for each axis i, the slab as the exact real quotient
//     t(i, side) = num(i, side) / den(i)
// where the ray crosses the slab's side-0 (lo) or side-1 (hi) plane. It offers:
//   den_sign(i)            the exact sign of den(i) (0: the ray is parallel to slab i)
//   inside_parallel(i)     exact: the origin lies in the closed slab (when den(i) == 0)
//   enclose(i, side)       an Interval<double> that contains t(i, side) (filter / bound)
//   num<E>(i, side), den<E>(i)   the exact values in an exact number type E
//   safe()                 whether the Expansion type is exact for this input
//   faithful(i, side)      t(i, side) faithfully rounded to T
// Both modes run one code path: the entry is the latest slab entry (or t_min), the
// exit the earliest slab exit (or t_max), hit iff entry <= exit.
//   conservative: the entry's lower and the exit's upper enclosure bounds; the verdict
//     can only err towards hit, and [t_enter, t_exit] encloses the exact interval.
//   certified: each comparison is decided by the enclosures when they are disjoint
//     (the filter) and by exact arithmetic only when they overlap; then t_enter and
//     t_exit are the winners' values faithfully rounded, the face is the exact argmax
//     with the contract's tie rule (t_min first, then the lowest axis).
#pragma once

#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/types.hpp>

#include <algorithm>
#include <limits>
#include <optional>
#include <type_traits>

namespace rayproof::detail {

#ifdef RAYPROOF_COUNTERS
// How often the certified mode left its floating-point filter for exact arithmetic.
struct ExactStageCounters {
    unsigned long long queries = 0;  // certified queries answered
    unsigned long long exact = 0;    // of which needed at least one exact decision
};
inline thread_local ExactStageCounters exact_stage_counters;
#define RAYPROOF_COUNT_QUERY() (++::rayproof::detail::exact_stage_counters.queries)
#define RAYPROOF_COUNT_EXACT(flag) ((flag) = true)
#define RAYPROOF_COUNT_FLUSH(flag) ((flag) ? ++::rayproof::detail::exact_stage_counters.exact : 0ULL)
#else
#define RAYPROOF_COUNT_QUERY() ((void)0)
#define RAYPROOF_COUNT_EXACT(flag) ((void)(flag))
#define RAYPROOF_COUNT_FLUSH(flag) ((void)(flag))
#endif

// The faithfully rounded double to T: a faithfully rounded double rounded to nearest T
// is a faithfully rounded T (the two T values enclosing t enclose the double); beyond
// the largest finite T the enclosing finite neighbour is answered, as exact_faithful
// does.
template <class T> T faithful_to(double t) {
    if constexpr (std::is_same_v<T, double>) {
        return t;
    } else {
        constexpr double big = std::numeric_limits<T>::max();
        return static_cast<T>(std::min(std::max(t, -big), big));
    }
}

// The certified answer from a straight-line path when it answered (`common`), else from
// `general()`, a call of the general path. The two meet in the four fields, not in a Hit:
// a Hit in memory written field by field and copied whole stalls on store-to-load
// forwarding.
template <class T, class General>
RAYPROOF_ALWAYS_INLINE Hit<T> common_or_general(const std::optional<Hit<T>>& common, General&& general) {
    Verdict verdict;
    T t_enter, t_exit;
    int face;
    if (common) {
        RAYPROOF_COUNT_QUERY();
        verdict = common->verdict, t_enter = common->t_enter, t_exit = common->t_exit, face = common->face;
    } else {
        const Hit<T> g = general();
        verdict = g.verdict, t_enter = g.t_enter, t_exit = g.t_exit, face = g.face;
    }
    Hit<T> out;
    out.verdict = verdict;
    out.t_enter = t_enter;
    out.t_exit = t_exit;
    out.face = face;
    return out;
}

// The verdict filters' answer (ray_aabb.hpp, ray_plane.hpp, ray_sphere.hpp): int(Verdict::
// miss) or int(Verdict::hit), or verdict_declined when the filter cannot decide; an int
// rather than an optional, whose flag would go through memory on every query.
inline constexpr int verdict_declined = -1;
static_assert(int(Verdict::miss) == 0 && int(Verdict::hit) == 1);

// The certified verdict from a filter's answer when it decided, else from `declined()`.
template <class Declined> RAYPROOF_ALWAYS_INLINE Verdict verdict_or(int filtered, Declined&& declined) {
    if (filtered != verdict_declined) [[likely]] {
        RAYPROOF_COUNT_QUERY();
        return Verdict(filtered);
    }
    return declined();
}

// Exact sign of value(a) - value(b), each either a slab quotient or a finite constant.
struct SlabRef {
    int axis;  // -1: the constant c
    int side;
    double c;
};

template <class Frame> int exact_compare(const Frame& f, const SlabRef& a, const SlabRef& b) {
    // ±inf constants (t_min = -inf, t_max = +inf) against finite quotients.
    if (a.axis < 0 && std::isinf(a.c)) return a.c > 0 ? 1 : -1;
    if (b.axis < 0 && std::isinf(b.c)) return b.c > 0 ? -1 : 1;
    if (a.axis < 0 && b.axis < 0) return (a.c > b.c) - (a.c < b.c);
    const std::optional<int> s = with_exact(f.safe(), [&](auto tag) -> std::optional<int> {
        using E = typename decltype(tag)::type;
        if (a.axis < 0) {
            const E n = f.template num<E>(b.axis, b.side), d = f.template den<E>(b.axis);
            if (any_overflowed(n, d)) return std::nullopt;
            return -compare_quotient(n, d, a.c);
        }
        const E n1 = f.template num<E>(a.axis, a.side), d1 = f.template den<E>(a.axis);
        if (any_overflowed(n1, d1)) return std::nullopt;
        if (b.axis < 0) return compare_quotient(n1, d1, b.c);
        const E n2 = f.template num<E>(b.axis, b.side), d2 = f.template den<E>(b.axis);
        if (any_overflowed(n2, d2)) return std::nullopt;
        return compare_quotients(n1, d1, n2, d2);
    });
    return *s;
}

// num/den faithfully rounded to T, in exact arithmetic.
template <class T, class Frame> T exact_faithful(const Frame& f, int axis, int side) {
    const std::optional<T> q = with_exact(f.safe(), [&](auto tag) -> std::optional<T> {
        using E = typename decltype(tag)::type;
        const E n = f.template num<E>(axis, side), d = f.template den<E>(axis);
        if (any_overflowed(n, d)) return std::nullopt;
        return faithful_quotient<T>(n, d);
    });
    return *q;
}

// The closest T to x in the direction of -inf / +inf (an outward rounding of a double
// enclosure end to T; the identity for T = double).
template <class T> T round_down_to(double x) {
    if constexpr (std::is_same_v<T, double>) {
        return x;
    } else {
        const T y = static_cast<T>(x);
        return double(y) > x ? step_down(y) : y;
    }
}
template <class T> T round_up_to(double x) {
    if constexpr (std::is_same_v<T, double>) {
        return x;
    } else {
        const T y = static_cast<T>(x);
        return double(y) < x ? step_up(y) : y;
    }
}

template <class T, class Frame> Hit<T> slab_conservative(const Frame& f, T t_min, T t_max) {
    Hit<T> h;
    double lo = t_min, hi = t_max;
    int face = -1;
    for (int i = 0; i < 3; ++i) {
        const int s = f.den_sign(i);
        if (s == 0) {
            if (!f.inside_parallel(i)) return h;
            continue;
        }
        const int side_in = s > 0 ? 0 : 1;
        const Interval<double> vin = f.enclose(i, side_in), vout = f.enclose(i, 1 - side_in);
        if (vin.lo > lo) {
            lo = vin.lo;
            face = 2 * i + side_in;
        }
        if (vout.hi < hi) hi = vout.hi;
    }
    if (!(lo <= hi)) return h;
    h.verdict = Verdict::hit;
    h.t_enter = round_down_to<T>(lo);
    h.t_exit = round_up_to<T>(hi);
    h.face = face;
    return h;
}

template <class T, class Frame> Hit<T> slab_certified(const Frame& f, T t_min, T t_max) {
    RAYPROOF_COUNT_QUERY();
    bool went_exact = false;
    Hit<T> h;
    int sden[3];
    for (int i = 0; i < 3; ++i) {
        sden[i] = f.den_sign(i);
        if (sden[i] == 0 && !f.inside_parallel(i)) return h;
    }
    // Latest entry: t_min first, then the axes in order, replacing only on a strictly
    // greater value, which is the contract's tie rule.
    SlabRef in{-1, 0, double(t_min)}, out{-1, 0, double(t_max)};
    Interval<double> vin(t_min), vout(t_max);
    for (int i = 0; i < 3; ++i) {
        if (sden[i] == 0) continue;
        const SlabRef c{i, sden[i] > 0 ? 0 : 1, 0};
        const Interval<double> v = f.enclose(i, c.side);
        bool greater;
        if (v.lo > vin.hi) {
            greater = true;
        } else if (v.hi <= vin.lo) {
            greater = false;
        } else {
            RAYPROOF_COUNT_EXACT(went_exact);
            greater = exact_compare(f, c, in) > 0;
        }
        if (greater) {
            in = c;
            vin = v;
        }
    }
    // Earliest exit (ties: any, the value is the same).
    for (int i = 0; i < 3; ++i) {
        if (sden[i] == 0) continue;
        const SlabRef c{i, sden[i] > 0 ? 1 : 0, 0};
        const Interval<double> v = f.enclose(i, c.side);
        bool less;
        if (v.hi < vout.lo) {
            less = true;
        } else if (v.lo >= vout.hi) {
            less = false;
        } else {
            RAYPROOF_COUNT_EXACT(went_exact);
            less = exact_compare(f, c, out) < 0;
        }
        if (less) {
            out = c;
            vout = v;
        }
    }
    // hit iff entry <= exit.
    int order;  // sign(entry - exit)
    if (vin.hi < vout.lo) {
        order = -1;
    } else if (vin.lo > vout.hi) {
        order = 1;
    } else {
        RAYPROOF_COUNT_EXACT(went_exact);
        order = exact_compare(f, in, out);
    }
    if (order > 0) {
        RAYPROOF_COUNT_FLUSH(went_exact);
        return h;
    }
    h.verdict = Verdict::hit;
    h.face = in.axis < 0 ? -1 : 2 * in.axis + in.side;
    h.t_enter = in.axis < 0 ? t_min : f.faithful(in.axis, in.side, vin, went_exact);
    h.t_exit = out.axis < 0 ? t_max : (order == 0 ? h.t_enter : f.faithful(out.axis, out.side, vout, went_exact));
    // Two different exact values in one gap between adjacent floats may round apart
    // the wrong way; the smaller rounding is faithful for both then.
    if (h.t_enter > h.t_exit) h.t_enter = h.t_exit;
    RAYPROOF_COUNT_FLUSH(went_exact);
    return h;
}

// Faithful rounding from an enclosure, when it is narrow enough: if [lo, hi] lies
// strictly between the neighbours of m = RN(mid), the exact value x is in
// (pred m, succ m), so m is one of the two floats enclosing x, and m == x when x is
// representable. Otherwise nothing is returned.
template <class T> std::optional<T> faithful_from_enclosure(const Interval<double>& v) {
    const T m = static_cast<T>(v.mid());
    if (!std::isfinite(m)) return std::nullopt;
    if (double(step_down(m)) < v.lo && v.hi < double(step_up(m))) return m;
    return std::nullopt;
}

}  // namespace rayproof::detail
