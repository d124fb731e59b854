// rayproof/generators/scene_gen.hpp — seeded generators of whole scenes (a span of
// Primitive<T> and one ray) aimed at what a bounding volume hierarchy can lose: ties in
// t_enter between primitives, primitives that touch or coincide, rays that run along
// shared faces and through shared edges and corners, ranges cut exactly at a face,
// origins inside and on primitives, every magnitude from the denormals to the overflow
// threshold, ±0 direction components, and scene sizes from 0 to a few thousand.
//
// Every constructed scene starts from small integers (exact in float and double): box
// corners, Obb centres with integer (non-normalized) axes and integer half extents,
// integer sphere centres and radii (radius 0 is a point), planes through integer points
// with integer normals, and convex polyhedra given by integer planes (boxes, cut boxes,
// half spaces, slabs, the empty set, all of space). A random signed axis permutation
// (exact: it permutes and negates coordinates) and an exact power-of-two rescaling
// (positions 2^kp, direction 2^kd, t 2^(kp-kd); scene_rescale) then move the same
// geometry anywhere in the exponent range, so every tie and touch survives exactly.
//
//   mixed         0 to 48 primitives of all five kinds around the origin, a ray aimed at
//                 a lattice point of one of them (or anywhere), any range
//   duplicates    a few base primitives, each repeated and given coincident twins of
//                 other kinds (an Aabb, the Obb with identity axes, the polyhedron of its
//                 six planes, in every order): equal t_enter everywhere, ties by index
//   touching      unit cells of a 4x4x4 lattice as boxes, Obbs or polyhedra, sharing
//                 faces, edges and corners; rays along a shared face (one zero direction
//                 component), along a shared edge (two), or through lattice corners
//   same_t        rows of identical and of different primitives whose exact t_enter is
//                 the same along the ray (boxes with one entry face, spheres at one
//                 distance from the line, the plane through the entry point, a half space)
//   inside        a mixed scene whose ray starts inside a primitive or on its boundary
//                 (a corner, a face point, a sphere's centre or surface point)
//   cut_range     touching or same_t scenes with t_min or t_max exactly at a face crossing
//   extreme       any of the above rescaled near the overflow threshold or into the
//                 denormals (the rescaling falls back to smaller exponents when inexact)
//   tiny          0, 1 or 2 primitives (a pair may coincide)
//   large         500 to 3000 boxes and spheres on a 128³ lattice, a few planes and
//                 polyhedra among them
//   log_uniform   1 to 8 primitives and the ray of wide values (any exponent, specials)
//   invalid       a mixed scene with invalid primitives among the valid ones (NaN or
//                 infinite numbers, lo > hi, negative radius or half extent, zero normal,
//                 dependent Obb axes), and one time in four an invalid ray
//
// A Scene owns the planes of its polyhedra (shared, so that a copy of the scene keeps
// the spans of both valid). It prints every number in hexadecimal floating point.
#pragma once

#include <rayproof/generators.hpp>  // core.hpp, ray_obb.hpp (random_rotation), scalar_name
#include <rayproof/closest.hpp>
#include <rayproof/io.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <ostream>
#include <span>
#include <string_view>
#include <variant>
#include <vector>

namespace rayproof::gen {

template <class T> struct Scene {
    std::vector<Primitive<T>> prims;
    // The planes of the polyhedra among prims (each ConvexPolyhedron spans one of these).
    std::vector<std::shared_ptr<const std::vector<Plane<T>>>> plane_sets;
    Ray<T> ray{Vec3<T>(0, 0, 0), Vec3<T>(1, 0, 0)};
    std::string_view generator;

    std::span<const Primitive<T>> view() const { return prims; }
    void add(const Primitive<T>& p) { prims.push_back(p); }
    void add_polyhedron(std::vector<Plane<T>> planes) {
        auto owned = std::make_shared<const std::vector<Plane<T>>>(std::move(planes));
        prims.push_back(ConvexPolyhedron<T>{std::span<const Plane<T>>(*owned)});
        plane_sets.push_back(std::move(owned));
    }
};

template <class T> std::ostream& print_primitive(std::ostream& os, const Primitive<T>& p) {
    std::visit(
        [&os](const auto& s) {
            using S = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<S, ConvexPolyhedron<T>>) {
                os << "ConvexPolyhedron{" << s.planes.size() << " planes:";
                for (std::size_t k = 0; k < s.planes.size(); ++k) os << " [" << k << "] " << s.planes[k];
                os << '}';
            } else {
                os << s;
            }
        },
        p);
    return os;
}

template <class T> std::ostream& operator<<(std::ostream& os, const Scene<T>& s) {
    os << "Scene{" << s.generator << ": " << s.ray << ", " << s.prims.size() << " primitives:";
    for (std::size_t i = 0; i < s.prims.size(); ++i) {
        os << "\n    [" << i << "] ";
        print_primitive(os, s.prims[i]);
    }
    return os << '}';
}

namespace detail {

// ---------------------------------------------------------------------------------
// Integer primitives (all numbers small integers: exact in T).

template <class T> Vec3<T> v3(std::int64_t x, std::int64_t y, std::int64_t z) {
    return Vec3<T>(narrow<T>(x), narrow<T>(y), narrow<T>(z));
}
template <class T> Vec3<T> v3(const I3& a) { return to_vec<T>(a); }

template <class T> Aabb<T> int_box(const I3& lo, const I3& hi) { return Aabb<T>{v3<T>(lo), v3<T>(hi)}; }
// The box's six planes (outward normals, each normal possibly multiplied by an integer:
// the same plane), in a random order.
template <class T> std::vector<Plane<T>> box_planes(const I3& lo, const I3& hi, Rng& rng) {
    std::vector<Plane<T>> p;
    for (int a = 0; a < 3; ++a) {
        for (int side = 0; side < 2; ++side) {
            const std::int64_t m = chance(rng, 1, 4) ? uniform_int(rng, 2, 3) : 1;
            I3 n{0, 0, 0};
            n[a] = side ? m : -m;
            p.push_back(Plane<T>{v3<T>(n), narrow<T>(side ? m * hi[a] : -m * lo[a])});
        }
    }
    for (std::size_t i = p.size(); i > 1; --i) std::swap(p[i - 1], p[below(rng, i)]);
    return p;
}
// The Obb equal to the box [lo, hi] when every extent is even (identity axes, or a
// signed permutation of them with the half extents permuted to match).
template <class T> Obb<T> box_as_obb(const I3& lo, const I3& hi, Rng& rng) {
    Obb<T> o;
    std::array<int, 3> perm = {0, 1, 2};
    for (int i = 2; i > 0; --i) std::swap(perm[i], perm[below(rng, i + 1)]);
    o.axes = Mat3<T>::Zero();
    for (int c = 0; c < 3; ++c) {
        o.axes(perm[c], c) = narrow<T>(random_sign(rng));
        o.half_extent[c] = narrow<T>((hi[perm[c]] - lo[perm[c]]) / 2);
    }
    o.center = v3<T>((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
    return o;
}
// The plane n·p = n·point.
template <class T> Plane<T> plane_through(const I3& n, const I3& point) { return Plane<T>{v3<T>(n), narrow<T>(dot(n, point))}; }

// A random box in [-r, r]³, lo <= hi (flat on an axis one time in eight), even extents
// when `even`.
inline void random_ibox(Rng& rng, std::int64_t r, bool even, I3& lo, I3& hi) {
    for (int a = 0; a < 3; ++a) {
        lo[a] = uniform_int(rng, -r, r);
        std::int64_t e = chance(rng, 1, 8) ? 0 : uniform_int(rng, 1, 4);
        if (even) e = 2 * ((e + 1) / 2);
        hi[a] = lo[a] + e;
    }
}

// One random valid primitive of any kind around [-r, r]³; `target` receives a lattice
// point of it (a point the ray may be aimed at).
template <class T> void add_random(Scene<T>& s, Rng& rng, std::int64_t r, I3& target) {
    I3 lo, hi;
    switch (below(rng, 10)) {
        case 0:
        case 1:
        case 2:
            random_ibox(rng, r, false, lo, hi);
            s.add(int_box<T>(lo, hi));
            target = chance(rng, 1, 2) ? lo : hi;
            break;
        case 3:
        case 4: {
            const I3 c = random_i3(rng, -r, r);
            s.add(Sphere<T>{v3<T>(c), narrow<T>(uniform_int(rng, 0, 4))});
            target = c;
            break;
        }
        case 5: {  // an Obb with integer axes (rotated, sheared or permuted)
            const IMat3 a = integer_axes(rng);
            const I3 c = random_i3(rng, -r, r);
            Obb<T> o{v3<T>(c), to_mat<T>(a), v3<T>(uniform_int(rng, 0, 3), uniform_int(rng, 0, 3), uniform_int(rng, 0, 3))};
            s.add(o);
            target = c;
            break;
        }
        case 6:
        case 7: {  // a box as a polyhedron, maybe cut by a plane through a corner
            random_ibox(rng, r, false, lo, hi);
            auto planes = box_planes<T>(lo, hi, rng);
            if (chance(rng, 1, 3)) {
                const I3 n = {random_sign(rng), random_sign(rng), random_sign(rng)};
                I3 corner;
                for (int a = 0; a < 3; ++a) corner[a] = n[a] > 0 ? hi[a] : lo[a];
                planes.push_back(plane_through<T>(n, corner));
                target = corner;
            } else {
                target = lo;
            }
            s.add_polyhedron(std::move(planes));
            break;
        }
        case 8: {  // a half space or a slab (unbounded: beside the tree)
            const I3 n = random_nonzero_i3(rng, 2);
            const I3 p = random_i3(rng, -r, r);
            std::vector<Plane<T>> planes{plane_through<T>(n, p)};
            if (chance(rng, 1, 2)) planes.push_back(plane_through<T>(mul(-1, n), add(p, mul(uniform_int(rng, 0, 1), n))));
            s.add_polyhedron(std::move(planes));
            target = p;
            break;
        }
        default: {
            const I3 n = random_nonzero_i3(rng, 2);
            const I3 p = random_i3(rng, -r, r);
            s.add(plane_through<T>(n, p));
            target = p;
            break;
        }
    }
}

// The ray from an integer origin towards an integer target (a random direction when they
// coincide), zero components given random signs.
template <class T> void aim(Scene<T>& s, Rng& rng, const I3& origin, const I3& target) {
    I3 d = sub(target, origin);
    if (is_zero(d)) d = random_nonzero_i3(rng, 2);
    s.ray.origin = v3<T>(origin);
    s.ray.direction = to_vec_signed_zeros<T>(d, rng);
}

// ---------------------------------------------------------------------------------
// Exact transformations of a whole scene.

// Coordinate i of the result is sign[i] times coordinate perm[i] of the input.
struct AxisMap {
    std::array<int, 3> perm{0, 1, 2};
    std::array<int, 3> sign{1, 1, 1};
};
inline AxisMap random_axis_map(Rng& rng) {
    AxisMap m;
    for (int i = 2; i > 0; --i) std::swap(m.perm[i], m.perm[below(rng, i + 1)]);
    for (int& s : m.sign) s = random_sign(rng);
    return m;
}
template <class T> Vec3<T> mapped(const Vec3<T>& v, const AxisMap& m) {
    Vec3<T> o;
    for (int i = 0; i < 3; ++i) o[i] = m.sign[i] < 0 ? -v[m.perm[i]] : v[m.perm[i]];
    return o;
}
template <class T> Aabb<T> mapped(const Aabb<T>& b, const AxisMap& m) {
    Aabb<T> o;
    for (int i = 0; i < 3; ++i) {
        o.lo[i] = m.sign[i] < 0 ? -b.hi[m.perm[i]] : b.lo[m.perm[i]];
        o.hi[i] = m.sign[i] < 0 ? -b.lo[m.perm[i]] : b.hi[m.perm[i]];
    }
    return o;
}
template <class T> Obb<T> mapped(const Obb<T>& b, const AxisMap& m) {
    Obb<T> o = b;
    o.center = mapped(b.center, m);
    for (int c = 0; c < 3; ++c) o.axes.col(c) = mapped(Vec3<T>(b.axes.col(c)), m);
    return o;
}
template <class T> Sphere<T> mapped(const Sphere<T>& s, const AxisMap& m) { return Sphere<T>{mapped(s.center, m), s.radius}; }
template <class T> Plane<T> mapped(const Plane<T>& p, const AxisMap& m) { return Plane<T>{mapped(p.normal, m), p.offset}; }

// Rebuilds the scene with `f` applied to each primitive (polyhedra plane by plane, into
// fresh storage); false, leaving s untouched, when f fails on some number.
template <class T, class F> bool transform_scene(Scene<T>& s, F f) {
    Scene<T> out;
    out.generator = s.generator;
    out.ray = s.ray;
    for (const Primitive<T>& p : s.prims) {
        bool ok = true;
        std::visit(
            [&](const auto& shape) {
                using S = std::decay_t<decltype(shape)>;
                if constexpr (std::is_same_v<S, ConvexPolyhedron<T>>) {
                    std::vector<Plane<T>> planes;
                    for (const Plane<T>& q : shape.planes) {
                        Plane<T> r = q;
                        ok = ok && f(q, r);
                        planes.push_back(r);
                    }
                    out.add_polyhedron(std::move(planes));
                } else {
                    S r = shape;
                    ok = f(shape, r);
                    out.add(r);
                }
            },
            p);
        if (!ok) return false;
    }
    s = std::move(out);
    return true;
}

template <class T> void map_scene(Scene<T>& s, const AxisMap& m) {
    transform_scene(s, [&m](const auto& in, auto& out) {
        out = mapped(in, m);
        return true;
    });
    s.ray.origin = mapped(s.ray.origin, m);
    s.ray.direction = mapped(s.ray.direction, m);
}

}  // namespace detail

// Positions times 2^kp, the direction times 2^kd, t_min and t_max times 2^(kp-kd) (the
// ray covers the same points; every exact t_enter is multiplied by 2^(kp-kd), so the
// order of the primitives along the ray and every tie is kept). False, leaving s
// untouched, when some number would not be exact.
template <class T> bool scene_rescale(Scene<T>& s, int kp, int kd) {
    Ray<T> r;
    if (!detail::scale_ray(s.ray, kp, kd, r)) return false;
    Scene<T> t = s;
    if (!detail::transform_scene(t, [kp](const auto& in, auto& out) { return detail::scale_shape(in, kp, 0, out); }))
        return false;
    t.ray = r;
    s = std::move(t);
    return true;
}

// An exact rescaling anywhere in the exponent range (half the time none): exponents
// halved until the scaling is exact. `wide`: always, from the ends of the range.
template <class T> void random_scene_scaling(Scene<T>& s, Rng& rng, bool wide = false) {
    if (!wide && chance(rng, 1, 2)) return;
    constexpr int e = std::numeric_limits<T>::max_exponent - std::numeric_limits<T>::min_exponent + kPrecision<T>;
    int kp = int(uniform_int(rng, -e / 2, e / 2)), kd = int(uniform_int(rng, -e / 2, e / 2));
    if (wide) {
        // Near the overflow threshold or in the denormals (the lattice spans ~2^12).
        kp = chance(rng, 1, 2) ? std::numeric_limits<T>::max_exponent - 14 - int(below(rng, 4))
                               : std::numeric_limits<T>::min_exponent - kPrecision<T> + int(below(rng, 12));
        kd = chance(rng, 1, 2) ? kp : int(uniform_int(rng, -e / 2, e / 2));
    } else if (chance(rng, 1, 2)) {
        kd = kp;  // keep t
    }
    for (int attempt = 0; attempt < 12; ++attempt) {
        if (scene_rescale(s, kp, kd)) return;
        if (attempt % 2) kp /= 2;
        else kd = kd / 2;
    }
}

namespace detail {

template <class T> Scene<T> scene_mixed_raw(Rng& rng, std::string_view name, std::int64_t n_max) {
    Scene<T> s;
    s.generator = name;
    const auto n = std::int64_t(below(rng, std::uint64_t(n_max) + 1));
    std::vector<I3> targets;
    for (std::int64_t i = 0; i < n; ++i) {
        I3 t;
        add_random(s, rng, 8, t);
        targets.push_back(t);
    }
    const I3 origin = random_i3(rng, -12, 12);
    const I3 target = targets.empty() || chance(rng, 1, 5) ? random_i3(rng, -8, 8) : targets[below(rng, targets.size())];
    aim(s, rng, origin, target);
    random_t_range(s.ray, rng, 4);
    return s;
}

}  // namespace detail

template <class T> Scene<T> scene_mixed(Rng& rng) {
    Scene<T> s = detail::scene_mixed_raw<T>(rng, "mixed", 48);
    detail::map_scene(s, detail::random_axis_map(rng));
    random_scene_scaling(s, rng);
    return s;
}

template <class T> Scene<T> scene_duplicates(Rng& rng) {
    Scene<T> s;
    s.generator = "duplicates";
    const auto bases = 1 + below(rng, 4);
    std::vector<I3> targets;
    for (std::uint64_t b = 0; b < bases; ++b) {
        I3 lo, hi;
        detail::random_ibox(rng, 6, true, lo, hi);
        const auto copies = 1 + below(rng, 4);
        for (std::uint64_t k = 0; k < copies; ++k) {
            switch (below(rng, 4)) {
                case 0: s.add(detail::int_box<T>(lo, hi)); break;
                case 1: s.add(detail::box_as_obb<T>(lo, hi, rng)); break;
                case 2: s.add_polyhedron(detail::box_planes<T>(lo, hi, rng)); break;
                default: {  // a sphere at a corner (the same sphere each time for this base)
                    s.add(Sphere<T>{detail::v3<T>(lo), narrow<T>(hi[0] - lo[0])});
                    break;
                }
            }
        }
        targets.push_back(chance(rng, 1, 2) ? lo : hi);
        targets.push_back(I3{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2});
    }
    for (std::size_t i = s.prims.size(); i > 1; --i) {  // shuffle, keeping each polyhedron's storage
        std::swap(s.prims[i - 1], s.prims[below(rng, i)]);
    }
    detail::aim(s, rng, random_i3(rng, -12, 12), targets[below(rng, targets.size())]);
    random_t_range(s.ray, rng, 4);
    detail::map_scene(s, detail::random_axis_map(rng));
    random_scene_scaling(s, rng);
    return s;
}

namespace detail {

// Unit cells of the 4x4x4 lattice [0, 4]³ (each kept with probability 1/2) as boxes,
// Obbs (centre at the half-integer cell centre: the lattice is doubled, cells of side 2)
// or polyhedra; a ray that runs along a lattice plane, a lattice line, or diagonally
// through lattice points. Returns the integer origin and direction (on the doubled lattice).
template <class T> Scene<T> touching_raw(Rng& rng, I3& origin, I3& dir) {
    Scene<T> s;
    s.generator = "touching";
    for (std::int64_t x = 0; x < 4; ++x)
        for (std::int64_t y = 0; y < 4; ++y)
            for (std::int64_t z = 0; z < 4; ++z) {
                if (chance(rng, 1, 2)) continue;
                const I3 lo{2 * x, 2 * y, 2 * z}, hi{2 * x + 2, 2 * y + 2, 2 * z + 2};
                switch (below(rng, 5)) {
                    case 0:
                    case 1: s.add(int_box<T>(lo, hi)); break;
                    case 2: s.add(box_as_obb<T>(lo, hi, rng)); break;
                    case 3: s.add_polyhedron(box_planes<T>(lo, hi, rng)); break;
                    default: s.add(Sphere<T>{v3<T>(lo[0] + 1, lo[1] + 1, lo[2] + 1), T(1)}); break;  // touching spheres
                }
            }
    for (std::size_t i = s.prims.size(); i > 1; --i) std::swap(s.prims[i - 1], s.prims[below(rng, i)]);
    // Origin on the lattice (even coordinates: on cell faces, edges and corners), outside
    // the block half the time.
    origin = {2 * uniform_int(rng, -1, 5), 2 * uniform_int(rng, -1, 5), 2 * uniform_int(rng, -1, 5)};
    switch (below(rng, 4)) {
        case 0: {  // along a shared face: one zero component
            const int a = int(below(rng, 3));
            dir = {signed_int(rng, 1, 3), signed_int(rng, 1, 3), signed_int(rng, 1, 3)};
            dir[a] = 0;
            break;
        }
        case 1: {  // along a lattice line (a shared edge): two zero components
            dir = {0, 0, 0};
            dir[below(rng, 3)] = signed_int(rng, 1, 2);
            break;
        }
        case 2:  // through lattice corners
            dir = {signed_int(rng, 1, 1), signed_int(rng, 1, 1), signed_int(rng, 1, 1)};
            break;
        default:  // towards the block's centre or a corner of it
            dir = sub(chance(rng, 1, 2) ? I3{4, 4, 4} : I3{2 * uniform_int(rng, 0, 4), 2 * uniform_int(rng, 0, 4), 2 * uniform_int(rng, 0, 4)}, origin);
            if (is_zero(dir)) dir = {1, 0, 0};
            break;
    }
    return s;
}

// Rows along the x axis from the origin whose exact t_enter is the same value t0 (with d
// = (1, 0, 0)): boxes entered through x = t0 with various y, z extents containing 0,
// spheres of radius 5 at distance 3 from the line centred at x = t0 + 4, the plane x =
// t0, the half space x >= t0, an Obb entered at x = t0; and a few primitives entered
// later or earlier. Returns t0.
template <class T> Scene<T> same_t_raw(Rng& rng, std::int64_t& t0) {
    Scene<T> s;
    s.generator = "same_t";
    t0 = uniform_int(rng, -4, 8);
    const auto n = 2 + below(rng, 10);
    for (std::uint64_t i = 0; i < n; ++i) {
        const std::int64_t t = chance(rng, 1, 5) ? t0 + signed_int(rng, 0, 3) : t0;
        switch (below(rng, 7)) {
            case 0:
            case 1: {
                const std::int64_t len = uniform_int(rng, 0, 4);
                s.add(int_box<T>(I3{t, -uniform_int(rng, 0, 3), -uniform_int(rng, 0, 3)},
                                 I3{t + len, uniform_int(rng, 0, 3), uniform_int(rng, 0, 3)}));
                break;
            }
            case 2: {
                static constexpr std::int64_t off[4][2] = {{3, 0}, {0, 3}, {-3, 0}, {0, -3}};
                const auto k = below(rng, 5);
                if (k == 4) s.add(Sphere<T>{v3<T>(t + 5, 0, 0), T(5)});  // on the line, radius 5: also enters at t
                else s.add(Sphere<T>{v3<T>(t + 4, off[k][0], off[k][1]), T(5)});
                break;
            }
            case 3: s.add(plane_through<T>(I3{signed_int(rng, 1, 2), 0, 0}, I3{t, 5, -2})); break;
            case 4: s.add_polyhedron({plane_through<T>(I3{-1, 0, 0}, I3{t, 0, 0})}); break;
            case 5: {
                const std::int64_t h = uniform_int(rng, 0, 2);
                s.add(Obb<T>{v3<T>(t + h, 0, 0), Mat3<T>::Identity(), v3<T>(h, uniform_int(rng, 0, 2), uniform_int(rng, 0, 2))});
                break;
            }
            default: {  // the box's planes, an entry plane duplicated
                const I3 lo{t, -1, -1}, hi{t + 2, 1, 1};
                auto planes = box_planes<T>(lo, hi, rng);
                planes.push_back(plane_through<T>(I3{-2, 0, 0}, lo));
                s.add_polyhedron(std::move(planes));
                break;
            }
        }
    }
    s.ray.origin = Vec3<T>(0, 0, 0);
    s.ray.direction = Vec3<T>(1, chance(rng, 1, 2) ? T(0) : -T(0), chance(rng, 1, 2) ? T(0) : -T(0));
    return s;
}

}  // namespace detail

template <class T> Scene<T> scene_touching(Rng& rng) {
    I3 o, d;
    Scene<T> s = detail::touching_raw<T>(rng, o, d);
    detail::aim(s, rng, o, add(o, d));
    random_t_range(s.ray, rng, 8);
    detail::map_scene(s, detail::random_axis_map(rng));
    random_scene_scaling(s, rng);
    return s;
}

template <class T> Scene<T> scene_same_t(Rng& rng) {
    std::int64_t t0 = 0;
    Scene<T> s = detail::same_t_raw<T>(rng, t0);
    special_t_range(s.ray, rng, narrow<T>(chance(rng, 1, 2) ? t0 : uniform_int(rng, -4, 8)));
    detail::map_scene(s, detail::random_axis_map(rng));
    random_scene_scaling(s, rng);
    return s;
}

template <class T> Scene<T> scene_inside(Rng& rng) {
    Scene<T> s = detail::scene_mixed_raw<T>(rng, "inside", 24);
    if (s.prims.empty()) {
        I3 t;
        detail::add_random(s, rng, 8, t);
    }
    // The origin at a point of a drawn primitive: inside, on its boundary, or (a plane, an
    // Obb) on it.
    const Primitive<T>& p = s.prims[below(rng, s.prims.size())];
    Vec3<T> o = s.ray.origin;
    std::visit(
        [&](const auto& shape) {
            using S = std::decay_t<decltype(shape)>;
            if constexpr (std::is_same_v<S, Aabb<T>>) {
                for (int a = 0; a < 3; ++a) {
                    const auto k = below(rng, 3);
                    o[a] = k == 0 ? shape.lo[a] : k == 1 ? shape.hi[a] : narrow<T>(std::floor((double(shape.lo[a]) + double(shape.hi[a])) / 2));
                }
            } else if constexpr (std::is_same_v<S, Sphere<T>>) {
                o = shape.center;
                if (chance(rng, 1, 2)) o[below(rng, 3)] += shape.radius;  // on the surface
            } else if constexpr (std::is_same_v<S, Obb<T>>) {
                o = shape.center;
            } else if constexpr (std::is_same_v<S, Plane<T>>) {
                // a plane: the origin stays where it is
            } else {
                if (!shape.planes.empty()) {  // a point on the first plane's axis when it is axis-aligned
                    const Plane<T>& q = shape.planes[0];
                    for (int a = 0; a < 3; ++a)
                        if (q.normal[a] != 0 && q.normal[(a + 1) % 3] == 0 && q.normal[(a + 2) % 3] == 0)
                            o[a] = q.offset / q.normal[a];  // exact: the offset is a multiple of the normal
                }
            }
        },
        p);
    s.ray.origin = o;
    if (chance(rng, 1, 2)) s.ray.t_min = chance(rng, 1, 2) ? T(0) : -kInf<T>;
    if (s.ray.t_max < s.ray.t_min) s.ray.t_max = kInf<T>;
    detail::map_scene(s, detail::random_axis_map(rng));
    random_scene_scaling(s, rng);
    return s;
}

template <class T> Scene<T> scene_cut_range(Rng& rng) {
    Scene<T> s;
    if (chance(rng, 1, 2)) {
        I3 o, d;
        s = detail::touching_raw<T>(rng, o, d);
        // An axis-parallel direction so that every crossing of a lattice plane is at an
        // integer t: t_min and/or t_max exactly at the crossing of a cell face.
        const int a = int(below(rng, 3));
        const std::int64_t sign = random_sign(rng);
        I3 dir{0, 0, 0};
        dir[a] = sign;
        detail::aim(s, rng, o, add(o, dir));
        const std::int64_t c0 = 2 * uniform_int(rng, 0, 4), c1 = 2 * uniform_int(rng, 0, 4);
        const std::int64_t t0 = (c0 - o[a]) * sign, t1 = (c1 - o[a]) * sign;
        s.ray.t_min = narrow<T>(std::min(t0, t1));
        s.ray.t_max = chance(rng, 1, 3) ? kInf<T> : narrow<T>(std::max(t0, t1));
        if (chance(rng, 1, 4)) s.ray.t_min = -kInf<T>;
    } else {
        std::int64_t t0 = 0;
        s = detail::same_t_raw<T>(rng, t0);
        const auto k = below(rng, 3);
        s.ray.t_min = k == 0 ? narrow<T>(t0) : T(0);
        s.ray.t_max = k == 1 ? narrow<T>(t0) : k == 2 ? narrow<T>(t0 + 4) : kInf<T>;
        if (s.ray.t_max < s.ray.t_min) s.ray.t_min = -kInf<T>;
    }
    s.generator = "cut_range";
    detail::map_scene(s, detail::random_axis_map(rng));
    random_scene_scaling(s, rng);
    return s;
}

template <class T> Scene<T> scene_extreme(Rng& rng) {
    Scene<T> s;
    switch (below(rng, 4)) {
        case 0: s = detail::scene_mixed_raw<T>(rng, "extreme", 16); break;
        case 1: {
            I3 o, d;
            s = detail::touching_raw<T>(rng, o, d);
            detail::aim(s, rng, o, add(o, d));
            random_t_range(s.ray, rng, 8);
            break;
        }
        case 2: {
            std::int64_t t0 = 0;
            s = detail::same_t_raw<T>(rng, t0);
            special_t_range(s.ray, rng, narrow<T>(t0));
            break;
        }
        default: s = scene_duplicates<T>(rng); break;
    }
    s.generator = "extreme";
    detail::map_scene(s, detail::random_axis_map(rng));
    random_scene_scaling(s, rng, true);
    return s;
}

template <class T> Scene<T> scene_tiny(Rng& rng) {
    Scene<T> s;
    s.generator = "tiny";
    const auto n = below(rng, 3);
    I3 t{0, 0, 0};
    if (n >= 1) detail::add_random(s, rng, 4, t);
    if (n == 2) {
        if (chance(rng, 1, 2)) s.prims.push_back(s.prims.back());  // a coincident pair (shared planes)
        else {
            I3 u;
            detail::add_random(s, rng, 4, u);
        }
    }
    detail::aim(s, rng, random_i3(rng, -6, 6), t);
    random_t_range(s.ray, rng, 4);
    detail::map_scene(s, detail::random_axis_map(rng));
    random_scene_scaling(s, rng);
    return s;
}

template <class T> Scene<T> scene_large(Rng& rng) {
    Scene<T> s;
    s.generator = "large";
    const auto n = 500 + below(rng, 2501);
    std::vector<I3> targets;
    for (std::uint64_t i = 0; i < n; ++i) {
        const auto k = below(rng, 64);
        if (k == 0) {
            I3 t;
            detail::add_random(s, rng, 64, t);  // any kind, planes and polyhedra included
            targets.push_back(t);
        } else if (k < 40) {
            I3 lo = random_i3(rng, -64, 64), hi;
            for (int a = 0; a < 3; ++a) hi[a] = lo[a] + uniform_int(rng, 0, 3);
            s.add(detail::int_box<T>(lo, hi));
            targets.push_back(lo);
        } else {
            const I3 c = random_i3(rng, -64, 64);
            s.add(Sphere<T>{detail::v3<T>(c), narrow<T>(uniform_int(rng, 0, 3))});
            targets.push_back(c);
        }
    }
    detail::aim(s, rng, random_i3(rng, -80, 80), targets[below(rng, targets.size())]);
    random_t_range(s.ray, rng, 64);
    detail::map_scene(s, detail::random_axis_map(rng));
    random_scene_scaling(s, rng);
    return s;
}

template <class T> Scene<T> scene_log_uniform(Rng& rng) {
    Scene<T> s;
    s.generator = "log_uniform";
    const auto n = 1 + below(rng, 8);
    for (std::uint64_t i = 0; i < n; ++i) {
        switch (below(rng, 5)) {
            case 0: {
                Aabb<T> b;
                for (int a = 0; a < 3; ++a) {
                    T x = wide_value<T>(rng), y = wide_value<T>(rng);
                    if (y < x) std::swap(x, y);
                    b.lo[a] = x;
                    b.hi[a] = y;
                }
                s.add(b);
                break;
            }
            case 1: {
                const T r = std::fabs(wide_value<T>(rng));
                s.add(Sphere<T>{Vec3<T>(wide_value<T>(rng), wide_value<T>(rng), wide_value<T>(rng)), r});
                break;
            }
            case 2: {
                Obb<T> o;
                o.axes = detail::random_rotation<T>(rng);
                for (int a = 0; a < 3; ++a) {
                    o.center[a] = wide_value<T>(rng);
                    o.half_extent[a] = std::fabs(wide_value<T>(rng));
                }
                s.add(o);
                break;
            }
            case 3: {
                const T off = wide_value<T>(rng);
                s.add(Plane<T>{nonzero_wide_vec<T>(rng), off});
                break;
            }
            default: {
                std::vector<Plane<T>> planes;
                const auto m = below(rng, 5);
                for (std::uint64_t k = 0; k < m; ++k) {
                    const T off = wide_value<T>(rng);
                    planes.push_back(Plane<T>{nonzero_wide_vec<T>(rng), off});
                }
                s.add_polyhedron(std::move(planes));
                break;
            }
        }
    }
    for (int a = 0; a < 3; ++a) s.ray.origin[a] = wide_value<T>(rng);
    wide_direction_and_range(s.ray, rng);
    return s;
}

template <class T> Scene<T> scene_invalid(Rng& rng) {
    Scene<T> s = detail::scene_mixed_raw<T>(rng, "invalid", 16);
    const auto bad = 1 + below(rng, 3);
    for (std::uint64_t b = 0; b < bad; ++b) {
        Primitive<T> p;
        switch (below(rng, 7)) {
            case 0: p = Aabb<T>{Vec3<T>(0, 0, 0), Vec3<T>(1, non_finite<T>(rng), 1)}; break;
            case 1: p = Aabb<T>{Vec3<T>(0, 2, 0), Vec3<T>(1, 1, 1)}; break;  // lo > hi
            case 2: p = Sphere<T>{Vec3<T>(0, 0, 0), T(-1)}; break;
            case 3: p = Plane<T>{Vec3<T>(0, -T(0), 0), T(1)}; break;
            case 4: p = Obb<T>{Vec3<T>(0, 0, 0), Mat3<T>::Ones(), Vec3<T>(1, 1, 1)}; break;  // dependent axes
            case 5: p = Obb<T>{Vec3<T>(0, 0, 0), Mat3<T>::Identity(), Vec3<T>(1, -1, 1)}; break;
            default: p = Sphere<T>{Vec3<T>(0, 0, non_finite<T>(rng)), T(1)}; break;
        }
        s.prims.insert(s.prims.begin() + std::ptrdiff_t(below(rng, s.prims.size() + 1)), p);
        if (chance(rng, 1, 3)) s.add_polyhedron({Plane<T>{Vec3<T>(0, 0, 0), T(1)}});  // a zero normal
    }
    if (chance(rng, 1, 4)) break_ray(s.ray, RayFault(below(rng, unsigned(RayFault::count))), rng);
    return s;
}

template <class T> struct SceneGenerator {
    std::string_view name;
    Scene<T> (*make)(Rng&);
};

namespace detail {
template <class T> struct SceneRegistry {
    static constexpr SceneGenerator<T> list[] = {
        {"mixed", scene_mixed<T>},         {"duplicates", scene_duplicates<T>}, {"touching", scene_touching<T>},
        {"same_t", scene_same_t<T>},       {"inside", scene_inside<T>},         {"cut_range", scene_cut_range<T>},
        {"extreme", scene_extreme<T>},     {"tiny", scene_tiny<T>},             {"large", scene_large<T>},
        {"log_uniform", scene_log_uniform<T>}, {"invalid", scene_invalid<T>}};
};
}  // namespace detail

// Every scene generator, in a fixed order.
template <class T> constexpr std::span<const SceneGenerator<T>> scene_generators() { return detail::SceneRegistry<T>::list; }

// The scene that generator `name` makes from `seed` (a fresh Rng); an empty scene named
// "unknown" for a name that is not registered.
template <class T> Scene<T> make_scene(std::string_view name, std::uint64_t seed) {
    for (const auto& g : scene_generators<T>())
        if (g.name == name) {
            Rng rng(seed);
            return g.make(rng);
        }
    Scene<T> s;
    s.generator = "unknown";
    return s;
}

}  // namespace rayproof::gen
