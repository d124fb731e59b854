// rayproof/detail/certified.hpp — what every shape's certified (and conservative) mode
// shares, apart from any one method: the exact-stage counters, the meeting of a
// straight-line path with its general path (common_or_general) and of a verdict filter
// with its fallback (verdict_or), the exact decisions on quotients num/den
// (exact_compare, exact_faithful), the roundings of a double to T (faithful_to,
// round_down_to, round_up_to, faithful_from_enclosure), and the answer of an enclosure
// that is a hit or a miss (hit_when).
#pragma once

#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/float_util.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/types.hpp>

#include <algorithm>
#include <cmath>
#include <concepts>
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
        return narrow<T>(std::min(std::max(t, -big), big));
    }
}

// The float nearest t (ties to even) from an enclosure [lo, hi] of t (doubles; ok: it
// holds t), when both ends round to the same float f. Rounding to nearest is monotone,
// so every value in [lo, hi], t included, rounds to f: the answer is a function of the
// exact t, not of the enclosure (a faithful rounding, the closest one), and two paths
// that answer from it agree bit for bit whatever their enclosures. Not ok when an end
// rounds elsewhere (the enclosure holds a midpoint between floats), when f is infinite
// (t beyond the largest float, whose faithful answer is that float: faithful_to) or
// when the enclosure is not ok. -0 == +0, so an enclosure of t around 0 answers +0 (f +
// 0, as the other paths answer t == 0).
RAYPROOF_ALWAYS_INLINE Pinned<float> nearest_float(double lo, double hi, bool ok) {
    const float a = narrow<float>(lo), b = narrow<float>(hi);
    return {a + 0.0f, bool(int(ok) & int(a == b) & int(std::abs(a) <= std::numeric_limits<float>::max()))};
}

// The conservative answer from a straight-line path when it answered, else from
// `general()`: common_or_general below without the certified mode's query count.
template <class T, class General>
RAYPROOF_ALWAYS_INLINE Hit<T> common_or_fallback(const std::optional<Hit<T>>& common, General&& general) {
    Verdict verdict;
    T t_enter, t_exit;
    int face;
    if (common) [[likely]] {
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

// A source of exact quotients: for each axis i and side, the real number
// t(i, side) = num(i, side) / den(i), with num and den in any exact number type E of
// detail/exact.hpp, and safe() saying whether the Expansion type is exact for this input
// (see with_exact). The slab frames (detail/slab_certified.hpp) are such sources, and so
// is the plane's crossing (axis 0, side 0 only).
template <class S> concept ExactQuotients = requires(const S& s, int i, int side) {
    { s.safe() } -> std::convertible_to<bool>;
    { s.template num<Expansion<kDefaultExpansionCap>>(i, side) } -> std::same_as<Expansion<kDefaultExpansionCap>>;
    { s.template den<Expansion<kDefaultExpansionCap>>(i) } -> std::same_as<Expansion<kDefaultExpansionCap>>;
    { s.template num<BigDyadic>(i, side) } -> std::same_as<BigDyadic>;
    { s.template den<BigDyadic>(i) } -> std::same_as<BigDyadic>;
};

// Exact sign of value(a) - value(b), each either a quotient of the source or a finite
// constant.
struct SlabRef {
    int axis;  // -1: the constant c
    int side;
    double c;
};

// A source may also offer scaled(): where it is not safe() for the Expansion type, an
// optional source of the same quotients times 2^shift() (shift() an int), each num and
// den multiplied by a power of two chosen to bring them into the safe range. A sign
// of the difference of two quotients, or of a quotient and a constant c scaled alike,
// is the same for the scaled values (2^shift > 0); a constant whose scaled value is not
// exact leaves the comparison to the source itself.
template <ExactQuotients Source> int exact_compare(const Source& f, const SlabRef& a, const SlabRef& b) {
    // ±inf constants (t_min = -inf, t_max = +inf) against finite quotients.
    if (a.axis < 0 && std::isinf(a.c)) return a.c > 0 ? 1 : -1;
    if (b.axis < 0 && std::isinf(b.c)) return b.c > 0 ? -1 : 1;
    if (a.axis < 0 && b.axis < 0) return (a.c > b.c) - (a.c < b.c);
    // A source may offer compare_at_any_scale(a, b): the sign without an expansion type on
    // the input as given, exact at every scale by its own range checks, or none where a
    // check fails (the Aabb's slab values: compare_slab_values, a few products checked).
    // Tried before a rescaled copy is made, which it mostly makes unnecessary.
    if constexpr (requires { f.compare_at_any_scale(a, b); })
        if (const std::optional<int> q = f.compare_at_any_scale(a, b)) return *q;
    if constexpr (requires { f.scaled(); }) {
        if (!f.safe())
            if (const auto& s = f.scaled()) {
                SlabRef sa = a, sb = b;
                if ((a.axis >= 0 || scale_exactly(a.c, s->shift(), sa.c)) &&
                    (b.axis >= 0 || scale_exactly(b.c, s->shift(), sb.c)))
                    return exact_compare(*s, sa, sb);
            }
    }
    // A source may also offer quick_compare(a, b): the same sign without an expansion type
    // (the Aabb's rescaled slab values, compare_slab_values; the Obb's, ObbQuotients), or
    // none where it cannot decide it exactly.
    if constexpr (requires { f.quick_compare(a, b); })
        if (const std::optional<int> q = f.quick_compare(a, b)) return *q;
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

// num/den faithfully rounded to T, in exact arithmetic. For double, a source that is
// not safe() but offers scaled() (exact_compare) rounds there, where the Expansion type
// is exact, and scales back (unscaled_faithful).
template <class T, ExactQuotients Source> T exact_faithful(const Source& f, int axis, int side) {
    // A source may offer quick_faithful<T>(axis, side): a faithful rounding without an
    // expansion type (AffineQuotients), or none where it cannot find one exactly.
    if constexpr (requires { f.template quick_faithful<T>(axis, side); })
        if (const std::optional<T> q = f.template quick_faithful<T>(axis, side)) return *q;
    if constexpr (std::is_same_v<T, double> && requires { f.scaled(); })
        if (!f.safe())
            if (const auto& s = f.scaled())
                if (const std::optional<double> q = unscaled_faithful(exact_faithful<double>(*s, axis, side), s->shift()))
                    return *q;
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
// Without a branch: whether x rounded to nearest landed above x (below, for round_up_to)
// is a coin toss. The step is one unit of the bits, toward -inf (+inf): down from a
// positive y or up from a negative one is bits - 1, the other way bits + 1. It is the
// step_down (step_up) of y at every y where it is taken: y = +0 never steps down (+0 > x
// means x < 0, which rounds to -0 or below) and -0 never up; -0 steps down to the
// least negative subnormal, -denorm_min up to -0, +inf down to the largest float, -inf
// up to its negation, as step_down and step_up do; -inf never steps down, +inf never up
// and NaN never (each comparison fails).
template <class T> RAYPROOF_ALWAYS_INLINE T round_down_to(double x) {
    if constexpr (std::is_same_v<T, double>) {
        return x;
    } else {
        using U = FloatBits<T>;
        const T y = narrow<T>(x);
        const U b = std::bit_cast<U>(y), s = b >> (8 * sizeof(U) - 1);  // 1: negative
        return std::bit_cast<T>(U(b + (U(2 * s - 1) & (U(0) - U(double(y) > x)))));
    }
}
template <class T> RAYPROOF_ALWAYS_INLINE T round_up_to(double x) {
    if constexpr (std::is_same_v<T, double>) {
        return x;
    } else {
        using U = FloatBits<T>;
        const T y = narrow<T>(x);
        const U b = std::bit_cast<U>(y), s = b >> (8 * sizeof(U) - 1);
        return std::bit_cast<T>(U(b + (U(1 - 2 * s) & (U(0) - U(double(y) < x)))));
    }
}

// A conservative enclosure's ends as T: [lo, hi] (doubles, holding the exact interval)
// rounded outward and clamped to [t_min, t_max], and whether [lo, hi] meets [t_min,
// t_max] (lo <= t_max, hi >= t_min, lo <= hi; false for a NaN end), the verdict the
// callers answer. When the exact interval meets [t_min, t_max] (an exact hit), meets is
// true and the clamped ends hold that meeting, so lo' <= hi'. The verdict is decided on
// [lo, hi] itself, never on the order of the widened float ends, which would also take
// enclosures that miss the range by less than the widening (more false hits, measured).
// Not always the closest floats, as round_down_to and round_up_to give, but
// at most three floats wider (the shift below is one to two float steps, and its 2^-149
// one more near the subnormal range): the conservative mode promises an enclosure, and
// this costs about half their instructions (no integer step), with the clamps in T
// after the rounding.
// The clamped ends themselves for T = double. For float, the lower end is y =
// fl_f(fl(lo - m)), m = fl(fl(|lo|·2^-23) + 2^-149) (fl_f: to the nearest float), then
// min(y, max float), then max with t_min: with u = 2^-53, m >= (1 - u)(2^-23|lo| +
// 2^-149) - 2^-1075 (the product exact but for an underflow), w = fl(lo - m) <= lo - m
// + u|w|, |w| <= (1 + 2^-22)|lo| + 2^-148, and rounding w to the nearest float moves it
// by at most half a float step, max(2^-24|w|, 2^-150). So y <= lo - (2^-23 - 2^-24(1 +
// 2^-21))|lo| - (2^-149 - 2^-150 - 2^-170) < lo: more than a float step covers every
// rounding. y is +inf only for w above the largest float by half a step, so lo above it
// and the largest float below lo; lo = -inf gives -inf. The upper end likewise,
// mirrored. Contraction (detail/eft.hpp): class C1 (a fused |lo|·2^-23 + 2^-149 has one
// rounding fewer).
template <class T> struct OutwardEnds {
    T lo, hi;
    bool meets;
};
template <class T> RAYPROOF_ALWAYS_INLINE OutwardEnds<T> outward_to(double lo, double hi, T t_min, T t_max) {
    const bool meets = bool(int(lo <= double(t_max)) & int(hi >= double(t_min)) & int(lo <= hi));
    if constexpr (std::is_same_v<T, double>) {
        return {lo > t_min ? lo : t_min, hi < t_max ? hi : t_max, meets};  // maxsd, minsd
    } else {
        static_assert(std::is_same_v<T, float>);
        constexpr float top = std::numeric_limits<float>::max();
        const float down = narrow<float>(lo - (std::abs(lo) * 0x1p-23 + 0x1p-149));
        const float up = narrow<float>(hi + (std::abs(hi) * 0x1p-23 + 0x1p-149));
        const float d = down < top ? down : top, u = up > -top ? up : -top;
        return {d > t_min ? d : t_min, u < t_max ? u : t_max, meets};
    }
}

// A hit proven by bounds computed in C: lo a lower bound of the exact entry and hi an
// upper bound of the exact exit, such that the exact entry lies below lo + 2·e_max and
// the exact exit above hi - 2·e_max (each bound an approximation widened by at most
// e_max, as the float stages of the Obb and the polyhedron compute them, where E
// exceeds the approximation's error by more than the rounding of t~ ∓ E). A hit where
// fl(hi - lo) >= fl(5·e_max), finite: then hi - lo >= 5·e_max(1 - u)/(1 + u) > 4·e_max (a
// difference that overflows is above the largest C), so the exact exit exceeds the
// exact entry and the exact answer hits too. e_max = 0 (exact bounds) asks hi >= lo.
template <class C> RAYPROOF_ALWAYS_INLINE bool certain_hit(C lo, C hi, C e_max) {
    const C gap = 5 * e_max;
    return bool(int(hi - lo >= gap) & int(gap <= std::numeric_limits<C>::max()));
}

// [t_enter, t_exit] with its face on a hit, and on a miss Hit<T>{} (t 0, face -1), chosen
// without a jump: on random rays hit or miss is a coin toss, and a branch on it is
// mispredicted half the time.
// The shapes without faces (plane, sphere) leave the face at its -1.
template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> hit_when(bool hit, T t_enter, T t_exit) {
    Hit<T> h;
    h.verdict = hit ? Verdict::hit : Verdict::miss;
    h.t_enter = pick(hit, t_enter, T(0));
    h.t_exit = pick(hit, t_exit, T(0));
    return h;
}
template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> hit_when(bool hit, T t_enter, T t_exit, int face) {
    Hit<T> h = hit_when(hit, t_enter, t_exit);
    h.face = pick_int(hit, face, -1);
    return h;
}

// Faithful rounding from an enclosure, when it is narrow enough: if [lo, hi] lies
// strictly between the neighbours of m = RN(mid), the exact value x is in
// (pred m, succ m), so m is one of the two floats enclosing x, and m == x when x is
// representable. Otherwise nothing is returned.
template <class T> std::optional<T> faithful_from_enclosure(const Interval<double>& v) {
    const T m = narrow<T>(v.mid());
    if (!std::isfinite(m)) return std::nullopt;
    if (double(step_down(m)) < v.lo && v.hi < double(step_up(m))) return m;
    return std::nullopt;
}

}  // namespace rayproof::detail
