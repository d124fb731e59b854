// bench/baselines.hpp — the plain floating-point baselines the kernel's modes are
// measured against, on the same rays, with the same Hit<T> answer so that the oracle's
// judge can score them. None of them validates its input (the workloads hold valid
// input only) and none promises anything.
//
//   textbook    the branchy slab method as the classic course notes write it: per axis
//               divide (lo - o)/d and (hi - o)/d, swap so that t0 <= t1, compare with
//               the running interval and leave early on a miss (Kay & Kajiya 1986, in
//               the form of Shirley's and Scratchapixel's notes). Obb: the same in the
//               box frame, (o - c)·a_i + t·(d·a_i) in [-h_i, h_i]. Sphere: the
//               textbook quadratic, disc = b² - a·c, roots (-b ∓ √disc)/a. Plane:
//               t = (offset - n·o)/(n·d). ConvexPolyhedron: Haines' loop over the planes
//               (E. Haines, "Fast Ray-Convex Polyhedron Intersection", Graphics Gems II,
//               1991): per plane vd = n·d, vn = n·o - offset; vd == 0 and vn > 0 is a
//               miss (parallel, outside), else t = -vn/vd is an entry (vd < 0: a miss if
//               past the exit so far, else the latest entry) or an exit (vd > 0: a miss
//               if before the entry so far, else the earliest exit).
//   branchless  the branch-free slab with the inverse direction (Williams et al., JGT
//               2005; the min/max form of tavianator's notes): inv = 1/d, t1 = (lo -
//               o)·inv, t2 = (hi - o)·inv, t_enter = max(t_enter, min(t1, t2)), t_exit
//               = min(t_exit, max(t1, t2)); no face (it answers -1). Aabb and Obb.
//   soa_slab    the same branch-free slab over W boxes stored as structure of arrays
//               (one box per lane, the reciprocal direction computed once per ray): a
//               plain loop the compiler vectorizes, the yardstick of the box packets
//               (ray_aabb_packet.hpp); bit i of its mask is box i's hit.
// Each is inlined into the timing loop, as the kernel's entry points are: a Hit
// returned through memory and copied whole would add a store-forwarding stall to one
// method and not to another.
#pragma once

#include <rayproof/detail/float_util.hpp>
#include <rayproof/types.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>

namespace rayproof::bench::baseline {

template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> make_hit(T t_enter, T t_exit, int face) {
    return Hit<T>{Verdict::hit, t_enter, t_exit, face};
}

// The textbook slab on scalar slabs: origin o_i, direction d_i, slab [lo_i, hi_i].
template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> textbook_slab(const T* o, const T* d, const T* lo, const T* hi, T t_min, T t_max) {
    T t_enter = t_min, t_exit = t_max;
    int face = -1;
    for (int i = 0; i < 3; ++i) {
        T t0 = (lo[i] - o[i]) / d[i];
        T t1 = (hi[i] - o[i]) / d[i];
        int side = 0;
        if (t0 > t1) {
            std::swap(t0, t1);
            side = 1;
        }
        if (t0 > t_enter) {
            t_enter = t0;
            face = 2 * i + side;
        }
        if (t1 < t_exit) t_exit = t1;
        if (t_enter > t_exit) return Hit<T>{};
    }
    return make_hit(t_enter, t_exit, face);
}

template <class T> inline T min_(T a, T b) { return a < b ? a : b; }
template <class T> inline T max_(T a, T b) { return a > b ? a : b; }

template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> branchless_slab(const T* o, const T* d, const T* lo, const T* hi, T t_min, T t_max) {
    T t_enter = t_min, t_exit = t_max;
    for (int i = 0; i < 3; ++i) {
        const T inv = T(1) / d[i];
        const T t1 = (lo[i] - o[i]) * inv;
        const T t2 = (hi[i] - o[i]) * inv;
        t_enter = max_(t_enter, min_(t1, t2));
        t_exit = min_(t_exit, max_(t1, t2));
    }
    Hit<T> h;
    h.verdict = t_enter <= t_exit ? Verdict::hit : Verdict::miss;
    h.t_enter = t_enter;
    h.t_exit = t_exit;
    return h;
}

// W boxes in structure of arrays (box i: lo[a][i], hi[a][i]), inv = 1/d per axis.
template <class T, int W>
RAYPROOF_ALWAYS_INLINE std::uint32_t soa_slab(const T* o, const T* inv, const T (&lo)[3][W], const T (&hi)[3][W], T t_min,
                                              T t_max) {
    std::uint32_t mask = 0;
    for (int i = 0; i < W; ++i) {
        T t_enter = t_min, t_exit = t_max;
        for (int a = 0; a < 3; ++a) {
            const T t1 = (lo[a][i] - o[a]) * inv[a];
            const T t2 = (hi[a][i] - o[a]) * inv[a];
            t_enter = max_(t_enter, min_(t1, t2));
            t_exit = min_(t_exit, max_(t1, t2));
        }
        mask |= std::uint32_t(t_enter <= t_exit) << i;
    }
    return mask;
}

// The ray in an Obb's frame: o'_i = (o - c)·a_i, d'_i = d·a_i, slab [-h_i, h_i].
template <class T> struct ObbFrame {
    T o[3], d[3], lo[3], hi[3];
    ObbFrame(const Ray<T>& r, const Obb<T>& b) {
        const Vec3<T> rel = r.origin - b.center;
        for (int i = 0; i < 3; ++i) {
            o[i] = rel.dot(b.axes.col(i));
            d[i] = r.direction.dot(b.axes.col(i));
            lo[i] = -b.half_extent[i];
            hi[i] = b.half_extent[i];
        }
    }
};

// ---- textbook ----------------------------------------------------------------------
template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> textbook(const Ray<T>& r, const Aabb<T>& b) {
    return textbook_slab(r.origin.data(), r.direction.data(), b.lo.data(), b.hi.data(), r.t_min, r.t_max);
}
template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> textbook(const Ray<T>& r, const Obb<T>& b) {
    const ObbFrame<T> f(r, b);
    return textbook_slab(f.o, f.d, f.lo, f.hi, r.t_min, r.t_max);
}
template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> textbook(const Ray<T>& r, const Sphere<T>& s) {
    const Vec3<T> oc = r.origin - s.center;
    const T a = r.direction.dot(r.direction);
    const T b = oc.dot(r.direction);
    const T c = oc.dot(oc) - s.radius * s.radius;
    const T disc = b * b - a * c;
    if (disc < 0) return Hit<T>{};
    const T sq = std::sqrt(disc);
    const T t0 = (-b - sq) / a, t1 = (-b + sq) / a;
    const T t_enter = t0 > r.t_min ? t0 : r.t_min;
    const T t_exit = t1 < r.t_max ? t1 : r.t_max;
    if (t_enter > t_exit) return Hit<T>{};
    return make_hit(t_enter, t_exit, -1);
}
template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> textbook(const Ray<T>& r, const Plane<T>& p) {
    const T den = p.normal.dot(r.direction);
    const T num = p.offset - p.normal.dot(r.origin);
    if (den == 0) return num == 0 ? make_hit(r.t_min, r.t_max, -1) : Hit<T>{};
    const T t = num / den;
    if (t < r.t_min || t > r.t_max) return Hit<T>{};
    return make_hit(t, t, -1);
}

template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> textbook(const Ray<T>& r, const ConvexPolyhedron<T>& p) {
    T t_near = r.t_min, t_far = r.t_max;
    int face = -1;
    for (std::size_t k = 0; k < p.planes.size(); ++k) {
        const Plane<T>& q = p.planes[k];
        const T vd = q.normal.dot(r.direction);
        const T vn = q.normal.dot(r.origin) - q.offset;
        if (vd == 0) {
            if (vn > 0) return Hit<T>{};
            continue;
        }
        const T t = -vn / vd;
        if (vd < 0) {
            if (t > t_far) return Hit<T>{};
            if (t > t_near) {
                t_near = t;
                face = int(k);
            }
        } else {
            if (t < t_near) return Hit<T>{};
            if (t < t_far) t_far = t;
        }
    }
    return make_hit(t_near, t_far, face);
}

// ---- branchless (boxes only) -------------------------------------------------------
template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> branchless(const Ray<T>& r, const Aabb<T>& b) {
    return branchless_slab(r.origin.data(), r.direction.data(), b.lo.data(), b.hi.data(), r.t_min, r.t_max);
}
template <class T> RAYPROOF_ALWAYS_INLINE Hit<T> branchless(const Ray<T>& r, const Obb<T>& b) {
    const ObbFrame<T> f(r, b);
    return branchless_slab(f.o, f.d, f.lo, f.hi, r.t_min, r.t_max);
}

template <class Shape> inline constexpr bool has_branchless =
    std::is_same_v<Shape, Aabb<float>> || std::is_same_v<Shape, Aabb<double>> || std::is_same_v<Shape, Obb<float>> ||
    std::is_same_v<Shape, Obb<double>>;

}  // namespace rayproof::bench::baseline
