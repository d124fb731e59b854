// Convex polyhedra of the scene: the exact hull, the presets and the bounding sphere.
// The derivations are in polyhedron.hpp.
#include <rayproof/render/polyhedron.hpp>

#include <rayproof/detail/exact.hpp>
#include <rayproof/detail/rounding.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace rayproof::render {

namespace {

using Vec3d = Eigen::Vector3d;
using rayproof::detail::exact_tag;
using rayproof::detail::expansion_safe;
using rayproof::detail::with_exact;

bool safe(std::initializer_list<const Vec3d*> vs) {
    for (const Vec3d* v : vs)
        if (!expansion_safe(*v)) return false;
    return true;
}

// The exact normal (b - a) × (c - a) and offset n·a of the plane through a, b, c, in E.
template <class E> struct ExactPlane {
    E n[3];
    E offset;
    bool overflowed() const {
        return n[0].overflowed() || n[1].overflowed() || n[2].overflowed() || offset.overflowed();
    }
};
template <class E> ExactPlane<E> exact_plane(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    E u[3], v[3];
    for (int i = 0; i < 3; ++i) {
        u[i] = E(b[i]) - E(a[i]);
        v[i] = E(c[i]) - E(a[i]);
    }
    ExactPlane<E> p;
    p.n[0] = u[1] * v[2] - u[2] * v[1];
    p.n[1] = u[2] * v[0] - u[0] * v[2];
    p.n[2] = u[0] * v[1] - u[1] * v[0];
    p.offset = p.n[0] * E(a[0]) + p.n[1] * E(a[1]) + p.n[2] * E(a[2]);
    return p;
}

// x/s as a double when it is one exactly (s > 0).
template <class E> std::optional<double> exact_quotient(const E& x, const E& s) {
    const double q = rayproof::detail::faithful_quotient<double>(x, s);
    if (rayproof::detail::compare_quotient(x, s, q) != 0) return std::nullopt;
    return q;
}

// The stored plane of the facet through a, b, c (outward normal (b - a) × (c - a)), and
// whether it is exact; for an inexact one the offset is set later (see convex_hull).
struct Stored {
    Plane<double> plane;
    bool exact = false;
};
Stored stored_plane(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    return *with_exact(safe({&a, &b, &c}), [&](auto tag) -> std::optional<Stored> {
        using E = typename decltype(tag)::type;
        const ExactPlane<E> p = exact_plane<E>(a, b, c);
        if (p.overflowed()) return std::nullopt;
        // Divisors: |n_j| for each nonzero n_j, then 1 (a positive factor keeps the
        // half-space); the first makes a normal component ±1 when it can.
        std::vector<E> divisors;
        for (int j = 0; j < 3; ++j)
            if (p.n[j].sign() != 0) divisors.push_back(p.n[j].sign() > 0 ? p.n[j] : E(-p.n[j]));
        const std::size_t nonzero = divisors.size();
        divisors.push_back(E(1.0));
        for (const E& s : divisors) {
            Stored st;
            bool ok = true;
            for (int j = 0; j < 3 && ok; ++j) {
                const auto q = exact_quotient(p.n[j], s);
                ok = q.has_value();
                if (ok) st.plane.normal[j] = *q;
            }
            if (!ok) continue;
            const auto o = exact_quotient(p.offset, s);
            if (!o) continue;
            st.plane.offset = *o;
            st.exact = true;
            return st;
        }
        // Inexact: n divided by its largest |n_j|, faithfully rounded.
        E largest = divisors[0];
        for (std::size_t k = 1; k < nonzero; ++k)
            if (rayproof::detail::compare_quotients(divisors[k], E(1.0), largest, E(1.0)) > 0) largest = divisors[k];
        Stored st;
        for (int j = 0; j < 3; ++j) st.plane.normal[j] = rayproof::detail::faithful_quotient<double>(p.n[j], largest);
        st.plane.offset = 0;
        st.exact = false;
        return st;
    });
}

// The smallest double >= max over the points of m·p, decided exactly.
double offset_up(const Vec3d& m, std::span<const Vec3d> points) {
    bool all_safe = expansion_safe(m);
    for (const Vec3d& p : points) all_safe = all_safe && expansion_safe(p);
    return *with_exact(all_safe, [&](auto tag) -> std::optional<double> {
        using E = typename decltype(tag)::type;
        E best;
        bool first = true;
        for (const Vec3d& p : points) {
            const E v = E(m[0]) * E(p[0]) + E(m[1]) * E(p[1]) + E(m[2]) * E(p[2]);
            if (v.overflowed()) return std::nullopt;
            if (first || (v - best).sign() > 0) best = v;
            first = false;
        }
        double q = rayproof::detail::faithful_quotient<double>(best, E(1.0));
        if (rayproof::detail::compare_quotient(best, E(1.0), q) > 0) q = std::nextafter(q, std::numeric_limits<double>::infinity());
        return q;
    });
}

bool collinear(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    return *with_exact(safe({&a, &b, &c}), [&](auto tag) -> std::optional<bool> {
        using E = typename decltype(tag)::type;
        const ExactPlane<E> p = exact_plane<E>(a, b, c);
        if (p.overflowed()) return std::nullopt;
        return p.n[0].sign() == 0 && p.n[1].sign() == 0 && p.n[2].sign() == 0;
    });
}

}  // namespace

// Fast path: when the nine differences are exact in double (Knuth's TwoSum leaves no
// error term: integer and dyadic points of moderate size), the orientation is the sign
// of the determinant of those doubles, which the kernel's det3_sign decides exactly
// (its filter, else expansions). Otherwise the differences themselves are taken
// exactly, in expansions.
int orient(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& d) {
    Eigen::Matrix3d m;
    bool exact = true;
    for (int i = 0; i < 3 && exact; ++i) {
        const rayproof::detail::Pair du = rayproof::detail::two_sum(b[i], -a[i]);
        const rayproof::detail::Pair dv = rayproof::detail::two_sum(c[i], -a[i]);
        const rayproof::detail::Pair dw = rayproof::detail::two_sum(d[i], -a[i]);
        exact = du.lo == 0 && dv.lo == 0 && dw.lo == 0 && std::isfinite(du.hi) && std::isfinite(dv.hi) &&
                std::isfinite(dw.hi);
        m(0, i) = du.hi;
        m(1, i) = dv.hi;
        m(2, i) = dw.hi;
    }
    if (exact) return rayproof::detail::det3_sign(m);
    return rayproof::detail::exact_sign(safe({&a, &b, &c, &d}), [&](auto tag) {
        using E = typename decltype(tag)::type;
        E u[3], v[3], w[3];
        for (int i = 0; i < 3; ++i) {
            u[i] = E(b[i]) - E(a[i]);
            v[i] = E(c[i]) - E(a[i]);
            w[i] = E(d[i]) - E(a[i]);
        }
        const E r = (u[1] * v[2] - u[2] * v[1]) * w[0] + (u[2] * v[0] - u[0] * v[2]) * w[1] + (u[0] * v[1] - u[1] * v[0]) * w[2];
        return r;
    });
}

HullResult convex_hull(std::span<const Vec3d> pts) {
    HullResult r;
    const std::size_t n = pts.size();
    if (n < 4) {
        r.error = "a convex hull needs at least 4 points, got " + std::to_string(n);
        return r;
    }
    if (n > max_hull_points) {
        r.error = "at most " + std::to_string(max_hull_points) + " points per hull, got " + std::to_string(n);
        return r;
    }
    for (std::size_t i = 0; i < n; ++i)
        if (!pts[i].allFinite()) {
            r.error = "point " + std::to_string(i) + " is not finite";
            return r;
        }
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
            if (pts[i] == pts[j]) {
                r.error = "points " + std::to_string(i) + " and " + std::to_string(j) + " are the same point";
                return r;
            }
    // Three points not on a line, then a fourth off their plane.
    std::size_t k = 2;
    while (k < n && collinear(pts[0], pts[1], pts[k])) ++k;
    if (k == n) {
        r.error = "all points lie on one line: their hull is no solid";
        return r;
    }
    std::size_t l = 0;
    while (l < n && orient(pts[0], pts[1], pts[k], pts[l]) == 0) ++l;
    if (l == n) {
        r.error = "all points lie in one plane: their hull is no solid";
        return r;
    }

    struct Facet {
        std::uint64_t on = 0;  // the points on its plane
        std::size_t a, b, c;   // ordered: (b - a) × (c - a) points out
    };
    std::vector<Facet> facets;
    for (std::size_t a = 0; a < n; ++a)
        for (std::size_t b = a + 1; b < n; ++b)
            for (std::size_t c = b + 1; c < n; ++c) {
                int side = 0;  // the sign seen so far off the plane
                bool facet = true;
                std::uint64_t on = 0;
                for (std::size_t d = 0; d < n && facet; ++d) {
                    if (d == a || d == b || d == c) {
                        on |= std::uint64_t(1) << d;
                        continue;
                    }
                    const int s = orient(pts[a], pts[b], pts[c], pts[d]);
                    if (s == 0) on |= std::uint64_t(1) << d;
                    else if (side == 0) side = s;
                    else if (s != side) facet = false;
                }
                // side == 0: a, b, c on a line (every orientation is 0); the points are not
                // all coplanar (checked above).
                if (!facet || side == 0) continue;
                const bool seen = std::any_of(facets.begin(), facets.end(), [&](const Facet& f) { return f.on == on; });
                if (seen) continue;
                // Every other point on the negative side: (b - a) × (c - a) points out.
                facets.push_back(side < 0 ? Facet{on, a, b, c} : Facet{on, a, c, b});
            }

    r.exact = true;
    std::vector<Vec3d> on_facet;
    for (const Facet& f : facets) {
        Stored s = stored_plane(pts[f.a], pts[f.b], pts[f.c]);
        if (!s.exact) {
            r.exact = false;
            s.plane.offset = offset_up(s.plane.normal, pts);
            const double len = s.plane.normal.norm();
            for (std::size_t d = 0; d < n; ++d)
                if (f.on >> d & 1) r.slack = std::max(r.slack, (s.plane.offset - s.plane.normal.dot(pts[d])) / len);
        }
        r.planes.push_back(s.plane);
    }
    return r;
}

std::optional<Sphere<double>> enclosing_sphere(std::span<const Vec3d> pts) {
    if (pts.empty()) return std::nullopt;
    Vec3d lo = pts[0], hi = pts[0];
    for (const Vec3d& p : pts) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const Vec3d c = lo + (hi - lo) / 2;
    double l = 0;
    for (const Vec3d& p : pts) {
        double s = 0;
        for (int i = 0; i < 3; ++i) {
            const double d = p[i] - c[i];
            s = s + d * d;
        }
        l = std::max(l, std::sqrt(s));
    }
    if (!c.allFinite() || !std::isfinite(l)) return std::nullopt;
    constexpr double u = rayproof::detail::unit_roundoff<double>;
    const double grown = l * (1 + 16 * u);
    const double r = std::nextafter(grown + 0x1p-500, std::numeric_limits<double>::infinity());
    return Sphere<double>{c, r};
}

double dodecahedron_h() {
    // round(2^13/φ)/2^13, φ = (1 + sqrt 5)/2: an integer below 2^13 over 2^13 (the
    // rounding of 2/(1 + sqrt 5) in double is far below the 2^-14 that decides it).
    static const double h = std::nearbyint(0x1p13 * 2 / (1 + std::sqrt(5.0))) * 0x1p-13;
    return h;
}

std::vector<Vec3d> preset_points(std::string_view name) {
    std::vector<Vec3d> v;
    if (name == "tetrahedron") {
        v = {Vec3d(1, 1, 1), Vec3d(1, -1, -1), Vec3d(-1, 1, -1), Vec3d(-1, -1, 1)};
    } else if (name == "octahedron") {
        for (int i = 0; i < 3; ++i)
            for (double s : {-1.0, 1.0}) {
                Vec3d p = Vec3d::Zero();
                p[i] = s;
                v.push_back(p);
            }
    } else if (name == "prism") {
        for (double z : {-1.0, 1.0}) v.insert(v.end(), {Vec3d(-1, -1, z), Vec3d(1, -1, z), Vec3d(0, 1, z)});
    } else if (name == "cube" || name == "dodecahedron") {
        for (double x : {-1.0, 1.0})
            for (double y : {-1.0, 1.0})
                for (double z : {-1.0, 1.0}) v.push_back(Vec3d(x, y, z));
        if (name == "dodecahedron") {
            const double h = dodecahedron_h(), a = 1 + h, b = 1 - h * h;  // both exact: 14 and 26 bits
            for (double s : {-1.0, 1.0})
                for (double t : {-1.0, 1.0}) {
                    v.push_back(Vec3d(0, s * a, t * b));
                    v.push_back(Vec3d(s * a, t * b, 0));
                    v.push_back(Vec3d(t * b, 0, s * a));
                }
        }
    }
    return v;
}

}  // namespace rayproof::render
