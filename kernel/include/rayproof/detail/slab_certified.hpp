// rayproof/detail/slab_certified.hpp — the slab method for the conservative and the
// certified modes, shared by Ray/Aabb and Ray/Obb (after the change of frame).
//
// A frame (the concept SlabFrame below) describes, for each axis i, the slab as the
// exact real quotient
//     t(i, side) = num(i, side) / den(i)
// where the ray crosses the slab's side-0 (lo) or side-1 (hi) plane. It offers:
//   den_sign(i)            the exact sign of den(i) (0: the ray is parallel to slab i)
//   inside_parallel(i)     exact: the origin lies in the closed slab (when den(i) == 0)
//   enclose(i, side)       an Interval<double> that contains t(i, side) (filter / bound)
//   num<E>(i, side), den<E>(i)   the exact values in an exact number type E
//   safe()                 whether the Expansion type is exact for this input
//   faithful(i, side, v, went_exact)   t(i, side) faithfully rounded to T, given its
//                          enclosure v; sets went_exact when it needed exact arithmetic
// (num, den and safe make it a source of exact quotients, detail/certified.hpp).
// Both modes run one code path: the entry is the latest slab entry (or t_min), the
// exit the earliest slab exit (or t_max), hit iff entry <= exit.
//   conservative: the entry's lower and the exit's upper enclosure bounds; the verdict
//     can only err towards hit, and [t_enter, t_exit] encloses the exact interval.
//   certified: each comparison is decided by the enclosures when they are disjoint
//     (the filter) and by exact arithmetic only when they overlap; then t_enter and
//     t_exit are the winners' values faithfully rounded, the face is the exact argmax
//     with the contract's tie rule (t_min first, then the lowest axis).
#pragma once

#include <rayproof/detail/certified.hpp>
#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/interval.hpp>
#include <rayproof/types.hpp>

#include <concepts>

namespace rayproof::detail {

template <class F, class T>
concept SlabFrame = ExactQuotients<F> && requires(const F& f, int i, int side, const Interval<double>& v, bool& went_exact) {
    { f.den_sign(i) } -> std::same_as<int>;
    { f.inside_parallel(i) } -> std::same_as<bool>;
    { f.enclose(i, side) } -> std::same_as<Interval<double>>;
    { f.faithful(i, side, v, went_exact) } -> std::same_as<T>;
};

template <class T, SlabFrame<T> Frame> Hit<T> slab_conservative(const Frame& f, T t_min, T t_max) {
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

// The enclosures of the slab values the certified slab method chooses among: per axis
// i not parallel to the ray, in[i] = {lo, hi} of the value where the ray enters slab i
// (side 0 when den(i) > 0) and out[i] of the value where it leaves it.
struct SlabEnclosures {
    double in[3][2], out[3][2];
};

// The certified slab method's choices, shared by slab_certified and the second stages
// of the straight-line paths (ray_aabb.hpp, ray_obb.hpp), so that all of them decide
// alike: sden[i] the exact sign of den(i) (0: parallel, with the origin inside the
// slab; the caller answers a parallel miss), v the enclosures, every comparison they
// leave decided exactly on src (exact_compare; went_exact is set then), and
// round(ref, enclosure) the winner's faithful rounding to T.
template <class T, class Source, class Round>
Hit<T> slab_decide(const Source& src, const int (&sden)[3], const SlabEnclosures& v, T t_min, T t_max,
                   bool& went_exact, Round&& round) {
    // Latest entry: t_min first, then the axes in order, replacing only on a strictly
    // greater value, which is the contract's tie rule.
    SlabRef in{-1, 0, double(t_min)}, out{-1, 0, double(t_max)};
    double in_lo = t_min, in_hi = t_min, out_lo = t_max, out_hi = t_max;
    for (int i = 0; i < 3; ++i) {
        if (sden[i] == 0) continue;
        const SlabRef c{i, sden[i] > 0 ? 0 : 1, 0};
        const double v_lo = v.in[i][0], v_hi = v.in[i][1];
        bool greater;
        if (v_lo > in_hi) {
            greater = true;
        } else if (v_hi <= in_lo) {
            greater = false;
        } else {
            RAYPROOF_COUNT_EXACT(went_exact);
            greater = exact_compare(src, c, in) > 0;
        }
        if (greater) in = c, in_lo = v_lo, in_hi = v_hi;
    }
    // Earliest exit (ties: any, the value is the same).
    for (int i = 0; i < 3; ++i) {
        if (sden[i] == 0) continue;
        const SlabRef c{i, sden[i] > 0 ? 1 : 0, 0};
        const double v_lo = v.out[i][0], v_hi = v.out[i][1];
        bool less;
        if (v_hi < out_lo) {
            less = true;
        } else if (v_lo >= out_hi) {
            less = false;
        } else {
            RAYPROOF_COUNT_EXACT(went_exact);
            less = exact_compare(src, c, out) < 0;
        }
        if (less) out = c, out_lo = v_lo, out_hi = v_hi;
    }
    // hit iff entry <= exit.
    int order;  // sign(entry - exit)
    if (in_hi < out_lo) {
        order = -1;
    } else if (in_lo > out_hi) {
        order = 1;
    } else {
        RAYPROOF_COUNT_EXACT(went_exact);
        order = exact_compare(src, in, out);
    }
    Hit<T> h;
    if (order > 0) return h;
    h.verdict = Verdict::hit;
    h.face = in.axis < 0 ? -1 : 2 * in.axis + in.side;
    h.t_enter = in.axis < 0 ? t_min : round(in, Interval<double>(in_lo, in_hi));
    h.t_exit = out.axis < 0 ? t_max : (order == 0 ? h.t_enter : round(out, Interval<double>(out_lo, out_hi)));
    // Two different exact values in one gap between adjacent floats may round apart
    // the wrong way; the smaller rounding is faithful for both then.
    if (h.t_enter > h.t_exit) h.t_enter = h.t_exit;
    return h;
}

template <class T, SlabFrame<T> Frame> Hit<T> slab_certified(const Frame& f, T t_min, T t_max) {
    RAYPROOF_COUNT_QUERY();
    bool went_exact = false;
    int sden[3];
    SlabEnclosures v;
    for (int i = 0; i < 3; ++i) {
        sden[i] = f.den_sign(i);
        if (sden[i] == 0) {
            if (!f.inside_parallel(i)) return Hit<T>{};
            continue;
        }
        const Interval<double> a = f.enclose(i, sden[i] > 0 ? 0 : 1), b = f.enclose(i, sden[i] > 0 ? 1 : 0);
        v.in[i][0] = a.lo, v.in[i][1] = a.hi, v.out[i][0] = b.lo, v.out[i][1] = b.hi;
    }
    const Hit<T> h = slab_decide(f, sden, v, t_min, t_max, went_exact, [&](const SlabRef& x, const Interval<double>& e) {
        return f.faithful(x.axis, x.side, e, went_exact);
    });
    RAYPROOF_COUNT_FLUSH(went_exact);
    return h;
}

}  // namespace rayproof::detail
