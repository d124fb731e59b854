// rayproof/generators/ray_polyhedron.hpp — case generators for ray vs convex polyhedron.
//
// A ConvexPolyhedron does not own its planes, so a case holds them in an OwnedPolyhedron
// (a vector of planes; view() is the ConvexPolyhedron over it, valid while the case
// lives) and prints them all in hexadecimal floating point.
//
// The constructed families start from integer polytopes whose vertices are integers and
// whose planes are integer (normal, offset) pairs, exact in T: boxes, tetrahedra (each
// face the plane through three integer vertices, n = (b - a) × (c - a), offset n·a),
// octahedra (|x - c| + |y - c| + |z - c| <= r as eight planes), optionally cut by extra
// supporting planes through a vertex (so that many planes meet there). The planes are
// listed in a random order, some normals multiplied by an integer (a coincident plane),
// and the case is moved by an exact integer translation and rescaled by exact powers of
// two (positions 2^kp, direction 2^kd, normals 2^ka, offsets 2^(kp+ka), t 2^(kp-kd)):
// every special point (a vertex passed through, an edge followed, a face plane lain in)
// survives exactly in T at every magnitude.
//
//   general       random planes around a point inside, rays aimed near it
//   log_uniform   every number log-uniform over the whole range (0 to 6 planes)
//   grazing       rays exactly through a vertex, along an edge, or lying in a face plane
//                 (direction n × w, ±0 components), t_min/t_max at the special point
//   near_grazing  those with a direction or origin coordinate or an offset moved by an ulp
//   parallel      rays exactly parallel to a face plane, on it, inside or outside it
//   on_boundary   origins exactly at a vertex, an edge midpoint or a point of a face
//   duplicates    duplicate and coincident planes (exact copies, integer multiples) at
//                 random positions, and flat slabs of two opposite planes
//   unbounded     a random subset of a polytope's planes (none, one, a wedge, ...)
//   infeasible    a polytope with a plane opposite one of its own, past it: empty
//   many_planes   up to 64 planes: supporting planes through the vertices added, loose
//                 ones too, so that up to dozens of planes meet at a vertex
//   extreme       the constructed cases scaled to the ends of the exponent range (2^±1000
//                 for double), to denormals, or random planes of denormal size
//   invalid       one invalid class of the contract: a ray fault, a zero normal (signed
//                 zeros), NaN or inf in a normal or an offset, in a random plane
#pragma once

#include <rayproof/generators/core.hpp>

#include <algorithm>
#include <cstddef>
#include <ostream>
#include <span>
#include <vector>

namespace rayproof::gen {

// The planes of a polyhedron case, owned; view() is the kernel's non-owning shape.
template <class T> struct OwnedPolyhedron {
    std::vector<Plane<T>> planes;
    [[nodiscard]] ConvexPolyhedron<T> view() const { return ConvexPolyhedron<T>{std::span<const Plane<T>>(planes)}; }
};

template <class T> std::ostream& operator<<(std::ostream& os, const OwnedPolyhedron<T>& p) {
    os << "ConvexPolyhedron{" << p.planes.size() << " planes:";
    for (std::size_t k = 0; k < p.planes.size(); ++k) os << " [" << k << "] " << p.planes[k];
    return os << '}';
}

template <class T> using PolyCase = Case<T, OwnedPolyhedron<T>>;

namespace detail {

// An integer polytope: planes n_k·p <= off_k and its vertices (all integer).
struct IPoly {
    std::vector<I3> n;
    std::vector<std::int64_t> off;
    std::vector<I3> verts;
    void add(const I3& normal, std::int64_t offset) {
        n.push_back(normal);
        off.push_back(offset);
    }
    // The planes through point v.
    std::vector<std::size_t> planes_on(const I3& v) const {
        std::vector<std::size_t> on;
        for (std::size_t k = 0; k < n.size(); ++k)
            if (dot(n[k], v) == off[k]) on.push_back(k);
        return on;
    }
};

inline IPoly integer_box_poly(Rng& rng) {
    IPoly p;
    I3 lo, hi;
    for (int i = 0; i < 3; ++i) {
        lo[i] = 2 * uniform_int(rng, -8, 8);
        hi[i] = lo[i] + 2 * uniform_int(rng, 1, 8);
    }
    for (int i = 0; i < 3; ++i) {
        I3 e{0, 0, 0};
        e[i] = 1;
        p.add(mul(-1, e), -lo[i]);
        p.add(e, hi[i]);
    }
    for (int m = 0; m < 8; ++m)
        p.verts.push_back({(m & 1) ? hi[0] : lo[0], (m & 2) ? hi[1] : lo[1], (m & 4) ? hi[2] : lo[2]});
    return p;
}

inline IPoly integer_tetra_poly(Rng& rng) {
    for (;;) {
        const std::array<I3, 4> v = {random_i3(rng, -8, 8), random_i3(rng, -8, 8), random_i3(rng, -8, 8),
                                     random_i3(rng, -8, 8)};
        if (det3(sub(v[1], v[0]), sub(v[2], v[0]), sub(v[3], v[0])) == 0) continue;
        IPoly p;
        static constexpr int faces[4][4] = {{0, 1, 2, 3}, {0, 1, 3, 2}, {0, 2, 3, 1}, {1, 2, 3, 0}};
        for (const auto& f : faces) {
            I3 n = cross(sub(v[f[1]], v[f[0]]), sub(v[f[2]], v[f[0]]));
            std::int64_t off = dot(n, v[f[0]]);
            if (dot(n, v[f[3]]) > off) {  // the fourth vertex must be inside: point n out
                n = mul(-1, n);
                off = -off;
            }
            p.add(n, off);
        }
        p.verts.assign(v.begin(), v.end());
        return p;
    }
}

inline IPoly integer_octa_poly(Rng& rng) {
    IPoly p;
    const I3 c = random_i3(rng, -8, 8);
    const std::int64_t r = uniform_int(rng, 1, 8);
    for (int m = 0; m < 8; ++m) {
        const I3 n{(m & 1) ? -1 : 1, (m & 2) ? -1 : 1, (m & 4) ? -1 : 1};
        p.add(n, r + dot(n, c));
    }
    for (int i = 0; i < 3; ++i)
        for (const std::int64_t s : {-r, r}) {
            I3 v = c;
            v[i] += s;
            p.verts.push_back(v);
        }
    return p;
}

// A supporting plane with normal n: touches the polytope at its extreme vertex (or
// vertices) in direction n, so the solid is unchanged and one more plane meets there.
inline void add_supporting(IPoly& p, const I3& n, std::int64_t slack = 0) {
    std::int64_t m = dot(n, p.verts[0]);
    for (const I3& v : p.verts) m = std::max(m, dot(n, v));
    p.add(n, m + slack);
}

// A box, a tetrahedron or an octahedron, sometimes cut by a supporting plane.
inline IPoly integer_polytope(Rng& rng) {
    const auto k = below(rng, 3);
    IPoly p = k == 0 ? integer_box_poly(rng) : k == 1 ? integer_tetra_poly(rng) : integer_octa_poly(rng);
    if (chance(rng, 1, 4)) add_supporting(p, random_nonzero_i3(rng, 3));
    return p;
}

// The planes in a random order (Fisher-Yates on the portable draws), vertices unchanged.
inline void shuffle_planes(IPoly& p, Rng& rng) {
    for (std::size_t i = p.n.size(); i > 1; --i) {
        const std::size_t j = std::size_t(below(rng, i));
        std::swap(p.n[i - 1], p.n[j]);
        std::swap(p.off[i - 1], p.off[j]);
    }
}

// Plane k multiplied by the integer m > 0: the same half space, a coincident plane.
inline void scale_plane(IPoly& p, std::size_t k, std::int64_t m) {
    p.n[k] = mul(m, p.n[k]);
    p.off[k] *= m;
}

// The polytope translated by tau and converted to T with the ray (origin, d); false when
// a number is not exact in T.
template <class T> bool poly_from_integers(const IPoly& p, const I3& tau, const I3& origin, const Vec3<T>& d,
                                           Rng& rng, PolyCase<T>& c) {
    c.shape.planes.clear();
    for (std::size_t k = 0; k < p.n.size(); ++k) {
        const std::int64_t off = p.off[k] + dot(p.n[k], tau);
        if (!representable<T>(p.n[k]) || !representable<T>(off)) return false;
        c.shape.planes.push_back(Plane<T>{to_vec_signed_zeros<T>(p.n[k], rng), narrow<T>(off)});
    }
    return ray_from_integers(add(origin, tau), d, c.ray);
}

// x·2^k, exact, for each number of a polyhedron case (see the header: positions 2^kp,
// direction 2^kd, normals 2^ka, offsets 2^(kp+ka), t 2^(kp-kd)); false, c untouched,
// when one is not.
template <class T> bool scale_polyhedron_case(PolyCase<T>& c, int kp, int kd, int ka) {
    PolyCase<T> out = c;
    if (!scale_ray(c.ray, kp, kd, out.ray)) return false;
    for (std::size_t k = 0; k < c.shape.planes.size(); ++k)
        if (!scaled(c.shape.planes[k].normal, ka, out.shape.planes[k].normal) ||
            !scaled(c.shape.planes[k].offset, kp + ka, out.shape.planes[k].offset))
            return false;
    c = std::move(out);
    return true;
}

// With probability 1/2, an exact power-of-two rescaling anywhere in the exponent range
// (as random_exact_scaling does for the other shapes).
template <class T> void random_polyhedron_scaling(PolyCase<T>& c, Rng& rng) {
    if (chance(rng, 1, 2)) return;
    const int e = std::numeric_limits<T>::max_exponent - std::numeric_limits<T>::min_exponent + kPrecision<T>;
    int kp = int(uniform_int(rng, -e / 2, e / 2)), kd = int(uniform_int(rng, -e / 2, e / 2)),
        ka = int(uniform_int(rng, -e / 4, e / 4));
    if (chance(rng, 1, 2)) kd = kp;  // keep t
    for (int attempt = 0; attempt < 8; ++attempt, kp /= 2, kd /= 2, ka /= 2)
        if (scale_polyhedron_case(c, kp, kd, ka)) return;
}

// A constructed case: `build(c)` returns false when some number is not exact; then the
// case is drawn again. The case is rescaled unless `scale` is false.
template <class T, class Build> PolyCase<T> constructed_polyhedron(std::string_view name, Rng& rng, Build build,
                                                                    bool scale = true) {
    for (;;) {
        PolyCase<T> c{{}, {}, name};
        if (!build(c)) continue;
        if (scale) random_polyhedron_scaling(c, rng);
        return c;
    }
}

// Two distinct vertices sharing at least two planes (an edge), if any: their indices.
inline bool random_edge(const IPoly& p, Rng& rng, std::size_t& a, std::size_t& b) {
    std::vector<std::pair<std::size_t, std::size_t>> edges;
    for (std::size_t i = 0; i < p.verts.size(); ++i)
        for (std::size_t j = i + 1; j < p.verts.size(); ++j) {
            const auto on_i = p.planes_on(p.verts[i]), on_j = p.planes_on(p.verts[j]);
            int shared = 0;
            for (const std::size_t k : on_i) shared += std::count(on_j.begin(), on_j.end(), k) > 0;
            if (shared >= 2) edges.emplace_back(i, j);
        }
    if (edges.empty()) return false;
    const auto& e = edges[below(rng, edges.size())];
    a = e.first;
    b = e.second;
    return true;
}

// A grazing ray on polytope p: through a vertex (a random direction, or towards another
// vertex), along an edge, or lying in the plane of a face through one of its vertices.
// Sets origin and d (integers) and the parameter s of the special point.
inline bool grazing_ray(const IPoly& p, Rng& rng, I3& origin, I3& d, std::int64_t& s) {
    const std::size_t vi = std::size_t(below(rng, p.verts.size()));
    const I3 v = p.verts[vi];
    const auto kind = below(rng, 4);
    if (kind == 0) {
        d = random_nonzero_i3(rng, 8);
    } else if (kind == 1) {
        d = sub(p.verts[below(rng, p.verts.size())], v);
    } else if (kind == 2) {
        std::size_t a = 0, b = 0;
        if (!random_edge(p, rng, a, b)) return false;
        d = sub(p.verts[b], p.verts[a]);
        if (chance(rng, 1, 2)) d = mul(-1, d);
        s = uniform_int(rng, -8, 8);
        origin = sub(p.verts[a], mul(s, d));
        return !is_zero(d);
    } else {
        const auto on = p.planes_on(v);
        if (on.empty()) return false;
        const I3 n = p.n[on[below(rng, on.size())]];
        d = cross(n, random_nonzero_i3(rng, 4));
    }
    if (is_zero(d)) return false;
    s = uniform_int(rng, -8, 8);
    origin = sub(v, mul(s, d));
    return true;
}

// The polytope's planes with a few duplicated: an exact copy or an integer multiple
// inserted at a random position (before or after the original).
inline void add_duplicates(IPoly& p, Rng& rng) {
    const auto copies = 1 + below(rng, 4);
    for (std::uint64_t i = 0; i < copies; ++i) {
        const std::size_t k = std::size_t(below(rng, p.n.size()));
        const std::int64_t m = chance(rng, 1, 2) ? 1 : uniform_int(rng, 2, 4);
        const I3 n = mul(m, p.n[k]);
        const std::int64_t off = m * p.off[k];
        const std::size_t at = std::size_t(below(rng, p.n.size() + 1));
        p.n.insert(p.n.begin() + std::ptrdiff_t(at), n);
        p.off.insert(p.off.begin() + std::ptrdiff_t(at), off);
    }
}

}  // namespace detail

// General position: 4 to 12 planes with normals in [-1, 1]³, each at a distance of 0.5
// to 4 normal lengths beyond a centre in [-4, 4]³ (so the centre is inside and the solid
// bounded or not as it falls); an origin in [-16, 16]³ aimed near the centre.
template <class T> PolyCase<T> polyhedron_general(Rng& rng) {
    PolyCase<T> c{{}, {}, "general"};
    Vec3<T> centre;
    for (int i = 0; i < 3; ++i) centre[i] = uniform<T>(rng, -4, 4);
    const auto n = 4 + below(rng, 9);
    for (std::uint64_t k = 0; k < n; ++k) {
        const Vec3<T> normal = nonzero_vec<T>(rng, [](Rng& g) { return uniform<T>(g, -1, 1); });
        const double margin = 0.5 + 3.5 * uniform01(rng);
        const double off = double(normal[0]) * double(centre[0]) + double(normal[1]) * double(centre[1]) +
                           double(normal[2]) * double(centre[2]) + margin;
        c.shape.planes.push_back(Plane<T>{normal, narrow<T>(off)});
    }
    Vec3<T> target;
    for (int i = 0; i < 3; ++i) {
        target[i] = narrow<T>(double(centre[i]) + 6 * (uniform01(rng) - 0.5));
        c.ray.origin[i] = uniform<T>(rng, -16, 16);
    }
    c.ray.direction = target - c.ray.origin;
    if (c.ray.direction.isZero()) c.ray.direction = Vec3<T>(1, 0, 0);
    random_t_range(c.ray, rng, 64);
    return c;
}

// Every number log-uniform over the whole exponent range (0 to 6 planes).
template <class T> PolyCase<T> polyhedron_log_uniform(Rng& rng) {
    PolyCase<T> c{{}, {}, "log_uniform"};
    const auto n = below(rng, 7);
    for (std::uint64_t k = 0; k < n; ++k) {
        const Vec3<T> normal = nonzero_wide_vec<T>(rng);
        const T off = wide_value<T>(rng);
        c.shape.planes.push_back(Plane<T>{normal, off});
    }
    for (int i = 0; i < 3; ++i) c.ray.origin[i] = wide_value<T>(rng);
    wide_direction_and_range(c.ray, rng);
    return c;
}

// Rays exactly through a vertex, along an edge or in a face plane of an integer
// polytope (planes shuffled, sometimes one made coincident by an integer factor).
template <class T> PolyCase<T> polyhedron_grazing(Rng& rng) {
    return detail::constructed_polyhedron<T>("grazing", rng, [&](PolyCase<T>& c) {
        detail::IPoly p = detail::integer_polytope(rng);
        I3 origin, d;
        std::int64_t s = 0;
        if (!detail::grazing_ray(p, rng, origin, d, s)) return false;
        detail::shuffle_planes(p, rng);
        if (chance(rng, 1, 4)) detail::scale_plane(p, std::size_t(below(rng, p.n.size())), uniform_int(rng, 2, 5));
        if (!detail::poly_from_integers<T>(p, random_translation<T>(rng), origin, to_vec_signed_zeros<T>(d, rng), rng, c))
            return false;
        special_t_range(c.ray, rng, narrow<T>(s));
        return true;
    });
}

// The grazing rays with one number moved by an ulp: a direction or origin coordinate,
// or the offset of a random plane.
template <class T> PolyCase<T> polyhedron_near_grazing(Rng& rng) {
    return near_grazing_from(
        polyhedron_grazing<T>(rng), rng,
        [](PolyCase<T>& c, int, Rng& g) {
            if (!c.shape.planes.empty()) nudge_ulp(c.shape.planes[below(g, c.shape.planes.size())].offset, g);
        },
        nudge_origin);
}

// Rays exactly parallel to a face plane (d = n × w): on the plane, inside it by an
// integer step, or outside it.
template <class T> PolyCase<T> polyhedron_parallel(Rng& rng) {
    return detail::constructed_polyhedron<T>("parallel", rng, [&](PolyCase<T>& c) {
        detail::IPoly p = detail::integer_polytope(rng);
        const std::size_t k = std::size_t(below(rng, p.n.size()));
        const I3 d = cross(p.n[k], random_nonzero_i3(rng, 4));
        if (is_zero(d)) return false;
        I3 v = p.verts[0];  // a vertex on plane k (every plane holds one), moved by -m·n (m > 0: inside)
        for (const I3& w : p.verts)
            if (dot(p.n[k], w) == p.off[k]) v = w;
        const std::int64_t m = chance(rng, 1, 3) ? 0 : signed_int(rng, 1, 3);
        const std::int64_t s = uniform_int(rng, -8, 8);
        const I3 origin = sub(sub(v, mul(m, p.n[k])), mul(s, d));
        detail::shuffle_planes(p, rng);
        if (!detail::poly_from_integers<T>(p, random_translation<T>(rng), origin, to_vec_signed_zeros<T>(d, rng), rng, c))
            return false;
        random_t_range(c.ray, rng, 16);
        return true;
    });
}

// Origins exactly at a vertex, an edge midpoint or the midpoint of a chord between two
// vertices (on a face, or inside; the polytope doubled so that midpoints are integers),
// or that point at the parameter s with t_min or t_max exactly there.
template <class T> PolyCase<T> polyhedron_on_boundary(Rng& rng) {
    return detail::constructed_polyhedron<T>("on_boundary", rng, [&](PolyCase<T>& c) {
        detail::IPoly p = detail::integer_polytope(rng);
        for (std::size_t k = 0; k < p.n.size(); ++k) p.off[k] *= 2;
        for (I3& v : p.verts) v = mul(2, v);
        I3 point;
        const auto where = below(rng, 3);
        const I3 a = p.verts[below(rng, p.verts.size())];
        if (where == 0) {
            point = a;
        } else {
            std::size_t i = 0, j = 0;
            if (where == 1 && detail::random_edge(p, rng, i, j)) {
                point = add(p.verts[i], p.verts[j]);
            } else {
                point = add(a, p.verts[below(rng, p.verts.size())]);  // a chord's midpoint
            }
            point = {point[0] / 2, point[1] / 2, point[2] / 2};  // even coordinates: exact
        }
        const I3 d = random_nonzero_i3(rng, 8);
        const BoundaryParameter at = boundary_parameter(rng, -8, 8);
        detail::shuffle_planes(p, rng);
        if (!detail::poly_from_integers<T>(p, random_translation<T>(rng), sub(point, mul(at.s, d)),
                                           to_vec_signed_zeros<T>(d, rng), rng, c))
            return false;
        on_boundary_t_range(c.ray, rng, at, 16);
        return true;
    });
}

// Duplicate and coincident planes (copies, integer multiples) at random positions, and
// one time in three a flat slab: a face plane and its opposite, the solid that face.
template <class T> PolyCase<T> polyhedron_duplicates(Rng& rng) {
    return detail::constructed_polyhedron<T>("duplicates", rng, [&](PolyCase<T>& c) {
        detail::IPoly p = detail::integer_polytope(rng);
        I3 origin, d;
        std::int64_t s = 0;
        if (!detail::grazing_ray(p, rng, origin, d, s)) return false;
        if (chance(rng, 1, 3)) {
            const std::size_t k = std::size_t(below(rng, p.n.size()));
            p.add(mul(-1, p.n[k]), -p.off[k]);
        }
        detail::shuffle_planes(p, rng);
        detail::add_duplicates(p, rng);
        if (!detail::poly_from_integers<T>(p, random_translation<T>(rng), origin, to_vec_signed_zeros<T>(d, rng), rng, c))
            return false;
        special_t_range(c.ray, rng, narrow<T>(s));
        return true;
    });
}

// A random subset of a polytope's planes (none, one, a wedge, a prism, ...): unbounded
// solids, with the grazing rays of the whole polytope.
template <class T> PolyCase<T> polyhedron_unbounded(Rng& rng) {
    return detail::constructed_polyhedron<T>("unbounded", rng, [&](PolyCase<T>& c) {
        detail::IPoly p = detail::integer_polytope(rng);
        I3 origin, d;
        std::int64_t s = 0;
        if (!detail::grazing_ray(p, rng, origin, d, s)) return false;
        detail::shuffle_planes(p, rng);
        const std::size_t keep = std::size_t(below(rng, std::min<std::size_t>(p.n.size(), 4)));
        p.n.resize(keep);
        p.off.resize(keep);
        if (!detail::poly_from_integers<T>(p, random_translation<T>(rng), origin, to_vec_signed_zeros<T>(d, rng), rng, c))
            return false;
        if (chance(rng, 1, 2))
            special_t_range(c.ray, rng, narrow<T>(s));
        else
            random_t_range(c.ray, rng, 16);
        return true;
    });
}

// A polytope with the opposite of one of its planes moved past it (n·p >= off + δ, δ >=
// 1): the empty set. The rays are the grazing ones and rays lying in either plane.
template <class T> PolyCase<T> polyhedron_infeasible(Rng& rng) {
    return detail::constructed_polyhedron<T>("infeasible", rng, [&](PolyCase<T>& c) {
        detail::IPoly p = detail::integer_polytope(rng);
        I3 origin, d;
        std::int64_t s = 0;
        if (!detail::grazing_ray(p, rng, origin, d, s)) return false;
        const std::size_t k = std::size_t(below(rng, p.n.size()));
        const std::int64_t delta = uniform_int(rng, 1, 3);
        if (chance(rng, 1, 3)) {  // the ray lying in the plane k or in its opposite
            const I3 w = cross(p.n[k], random_nonzero_i3(rng, 4));
            if (is_zero(w)) return false;
            d = w;
        }
        p.add(mul(-1, p.n[k]), -(p.off[k] + delta));
        detail::shuffle_planes(p, rng);
        if (!detail::poly_from_integers<T>(p, random_translation<T>(rng), origin, to_vec_signed_zeros<T>(d, rng), rng, c))
            return false;
        random_t_range(c.ray, rng, 16);
        if (chance(rng, 1, 2)) c.ray.t_min = -kInf<T>;
        return true;
    });
}

// Up to 64 planes: a polytope with supporting planes added through its vertices (so many
// planes meet at one vertex), some loose ones, duplicates, all shuffled; grazing rays.
template <class T> PolyCase<T> polyhedron_many_planes(Rng& rng) {
    return detail::constructed_polyhedron<T>("many_planes", rng, [&](PolyCase<T>& c) {
        detail::IPoly p = detail::integer_polytope(rng);
        I3 origin, d;
        std::int64_t s = 0;
        if (!detail::grazing_ray(p, rng, origin, d, s)) return false;
        const std::size_t target = std::size_t(uniform_int(rng, 16, 60));
        while (p.n.size() < target) {
            const I3 n = random_nonzero_i3(rng, 6);
            const std::int64_t slack = chance(rng, 1, 4) ? uniform_int(rng, 1, 4) : 0;
            detail::add_supporting(p, n, slack);
        }
        detail::shuffle_planes(p, rng);
        detail::add_duplicates(p, rng);
        if (!detail::poly_from_integers<T>(p, random_translation<T>(rng), origin, to_vec_signed_zeros<T>(d, rng), rng, c))
            return false;
        special_t_range(c.ray, rng, narrow<T>(s));
        return true;
    });
}

// Extreme magnitudes: a grazing or on_boundary case scaled exactly to the top or the
// bottom of the exponent range (2^±1000 for double, ±100 for float; denormals where the
// bits survive), or random planes with denormal normals and offsets.
template <class T> PolyCase<T> polyhedron_extreme(Rng& rng) {
    using L = std::numeric_limits<T>;
    const auto kind = below(rng, 3);
    if (kind == 2) {
        PolyCase<T> c = renamed(polyhedron_general<T>(rng), "extreme");
        for (Plane<T>& q : c.shape.planes) {
            for (int i = 0; i < 3; ++i) q.normal[i] = magnitude<T>(rng, L::min_exponent - kPrecision<T>, L::min_exponent);
            q.offset = magnitude<T>(rng, L::min_exponent - kPrecision<T>, L::min_exponent + 8);
        }
        return c;
    }
    PolyCase<T> c = renamed(chance(rng, 1, 2) ? polyhedron_grazing<T>(rng) : polyhedron_on_boundary<T>(rng), "extreme");
    const int top = L::max_exponent - 24, bottom = L::min_exponent - kPrecision<T> + 24;
    for (int attempt = 0; attempt < 16; ++attempt) {
        const int kp = kind == 0 ? int(uniform_int(rng, top - 40, top)) : int(uniform_int(rng, bottom, bottom + 40));
        const int kd = chance(rng, 1, 2) ? kp : -kp / 2;
        const int ka = chance(rng, 1, 2) ? 0 : (kind == 0 ? -kp / 2 : kp / 4);
        if (detail::scale_polyhedron_case(c, kp, kd, ka)) return c;
    }
    return c;
}

// Invalid inputs: every ray rule; a zero normal (signed zeros mixed) or NaN or inf in a
// normal or an offset, in a random plane (one is added when there is none).
template <class T> PolyCase<T> polyhedron_invalid(Rng& rng) {
    PolyCase<T> c = renamed(chance(rng, 1, 2) ? polyhedron_general<T>(rng) : polyhedron_grazing<T>(rng), "invalid");
    const auto k = below(rng, unsigned(RayFault::count) + 2);
    if (k < unsigned(RayFault::count)) {
        break_ray(c.ray, RayFault(k), rng);
        return c;
    }
    if (c.shape.planes.empty()) c.shape.planes.push_back(Plane<T>{Vec3<T>(0, 0, 1), T(1)});
    Plane<T>& q = c.shape.planes[below(rng, c.shape.planes.size())];
    if (k == unsigned(RayFault::count)) {
        for (int i = 0; i < 3; ++i) q.normal[i] = (rng() & 1) ? T(0) : -T(0);
    } else {
        make_non_finite(q.offset, q.normal, rng);
    }
    return c;
}

}  // namespace rayproof::gen
