// detail::compare_entry and the certified closest_hit (rayproof/closest.hpp) against the
// exact oracle: for two primitives hit by one ray, the sign compare_entry gives must be the
// order of the oracle's exact t_enter values (oracle::exact, CGAL rationals; sphere entries
// as Root_of_2, compared by crosscheck::compare), and closest_hit over {a, b} must pick the
// exactly closer one, ties to the lower index. Over float and double, on seeded
// adversarial pairs built so that the two entries are equal exactly or nearly:
//   - equal exact t through faces of different axes (t = k/3, not representable);
//   - a box face one or two ulps off an exact entry (the floats equal or adjacent);
//   - two boxes with coplanar faces; an Obb and a polyhedron on a box's planes, rotated
//     boxes sharing an entry point; an Obb with integer, non-unit axes whose entry face
//     lies on a polyhedron's plane, or one ulp off it;
//   - spheres tangent to one plane at one point, from the same side (equal entries when
//     the ray passes the point, adjacent otherwise), spheres internally tangent at the
//     entry point (centers rounded: entries a few ulps apart), a sphere touching a box face;
//   - a box face at the rounded entry of a sphere (a quotient against a root);
//   - t_min entries (starts inside) against crossings at t_min;
// each at scale 1, 2^±1000 (double; float 2^±100) and in the denormals (the whole case
// scaled by a power of two: every t is unchanged where the scaling is exact).
// Every case is seeded (RAYPROOF_SEED=<decimal> replays) and prints the ray and both
// primitives in hexadecimal when it fails.
#include "seeded.hpp"

#include <rayproof/io.hpp>
#include <rayproof/oracle/crosscheck.hpp>
#include <rayproof/oracle/oracle.hpp>
#include <rayproof/rayproof.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace rayproof;
using namespace rayproof::testing;

namespace {

std::uint64_t base_seed() {
    static const std::uint64_t s = env_seed_or(20261203);
    return s;
}
std::mt19937_64 make_rng() { return rng_for_current_test(base_seed()); }

template <class T> Vec3<T> v3(double x, double y, double z) { return Vec3<T>(T(x), T(y), T(z)); }

// One adversarial case: a ray and two primitives (owning the polyhedra's planes).
template <class T> struct Pair {
    std::string kind;
    Ray<T> ray;
    std::vector<std::shared_ptr<std::vector<Plane<T>>>> planes;
    Primitive<T> a, b;
    ConvexPolyhedron<T> poly(std::vector<Plane<T>> p) {
        planes.push_back(std::make_shared<std::vector<Plane<T>>>(std::move(p)));
        return ConvexPolyhedron<T>{std::span<const Plane<T>>(*planes.back())};
    }
};

template <class T> std::vector<Plane<T>> box_planes(const Aabb<T>& b) {
    std::vector<Plane<T>> p;
    for (int i = 0; i < 3; ++i) {
        Vec3<T> n = Vec3<T>::Zero();
        n[i] = -1;
        p.push_back({n, -b.lo[i]});
        n[i] = 1;
        p.push_back({n, b.hi[i]});
    }
    return p;
}

// Everything scaled by s = 2^e (t unchanged where exact): points, directions, extents,
// radii and offsets; axes and normals kept.
template <class T> Primitive<T> scaled(const Primitive<T>& p, T s, Pair<T>& owner) {
    return std::visit(
        [&](const auto& x) -> Primitive<T> {
            using S = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<S, Aabb<T>>) return Aabb<T>{x.lo * s, x.hi * s};
            else if constexpr (std::is_same_v<S, Obb<T>>) return Obb<T>{x.center * s, x.axes, x.half_extent * s};
            else if constexpr (std::is_same_v<S, Sphere<T>>) return Sphere<T>{x.center * s, x.radius * s};
            else if constexpr (std::is_same_v<S, Plane<T>>) return Plane<T>{x.normal, x.offset * s};
            else {
                std::vector<Plane<T>> q(x.planes.begin(), x.planes.end());
                for (Plane<T>& pl : q) pl.offset *= s;
                return owner.poly(std::move(q));
            }
        },
        p);
}
template <class T> Pair<T> scaled(const Pair<T>& c, int e) {
    const T s = std::ldexp(T(1), e);
    Pair<T> r;
    r.kind = c.kind + " scale 2^" + std::to_string(e);
    r.ray = Ray<T>{c.ray.origin * s, c.ray.direction * s, c.ray.t_min, c.ray.t_max};
    r.a = scaled(c.a, s, r);
    r.b = scaled(c.b, s, r);
    return r;
}

template <class T> struct Maker {
    std::mt19937_64& g;
    double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(g); }
    int pick(int n) { return int(std::uniform_int_distribution<int>(0, n - 1)(g)); }
    int small() { return pick(9) - 4; }
    Mat3<T> rotation() {
        const Eigen::Quaterniond q{uni(-1, 1), uni(-1, 1), uni(-1, 1), uni(-1, 1)};
        return q.normalized().toRotationMatrix().cast<T>();
    }

    // A ray with a 3 and a 6 in its direction (entries k/3 are not dyadic).
    Ray<T> thirds_ray() {
        const Vec3<T> o{T(small()), T(small()), T(small())};
        return Ray<T>{o, v3<T>(3, 6, 1 + pick(3))};
    }

    Pair<T> equal_thirds() {  // x face at t = k/3 against y face at the same t
        Pair<T> c;
        c.kind = "equal thirds";
        c.ray = thirds_ray();
        const int k = 1 + pick(5);
        const T px = c.ray.origin[0] + T(k), py = c.ray.origin[1] + T(2 * k);  // (px-ox)/3 = (py-oy)/6 = k/3
        c.a = Aabb<T>{v3<T>(px, -100, -100), v3<T>(px + 50, 100, 100)};
        c.b = Aabb<T>{v3<T>(-100, py, -100), v3<T>(100, py + T(pick(3)), 100)};
        return c;
    }

    Pair<T> ulps_off() {  // a z face one or two ulps off an exact entry k/3 through x
        Pair<T> c = equal_thirds();
        c.kind = "ulps off";
        c.ray.origin[2] = 0;
        c.ray.direction[2] = 1;
        T z = T(1 + pick(5)) / T(3);
        for (int s = pick(5) - 2; s != 0; s += s > 0 ? -1 : 1) z = s > 0 ? std::nextafter(z, T(10)) : std::nextafter(z, T(-10));
        c.b = Aabb<T>{v3<T>(-100, -100, z), v3<T>(100, 100, 100)};
        // a's x face at t = k'/3 with k' chosen so that both entries are near 1/3 .. 5/3.
        const T k = T(std::round(double(z) * 3));
        const T px = c.ray.origin[0] + k;
        c.a = Aabb<T>{v3<T>(px, -100, -100), v3<T>(px + 1, 100, 100)};
        return c;
    }

    Pair<T> coplanar() {  // two boxes sharing the plane of their entry face
        Pair<T> c;
        c.kind = "coplanar faces";
        c.ray = Ray<T>{Vec3<T>{T(uni(-1, 1)), T(uni(-1, 1)), T(-5)}, Vec3<T>{T(uni(-1, 1)), T(uni(-1, 1)), T(uni(0.5, 2))}};
        const T z = T(uni(-1, 1));
        c.a = Aabb<T>{v3<T>(-10, -10, z), v3<T>(10, 10, z + 1)};
        c.b = Aabb<T>{v3<T>(-20, -20, z), v3<T>(20, 20, z + T(uni(0, 3)))};
        if (pick(2) == 0) c.b = Obb<T>{v3<T>(0, 0, z + 1), Mat3<T>::Identity(), v3<T>(10, 10, 1)};
        if (pick(3) == 0) c.b = c.poly(box_planes(std::get<Aabb<T>>(c.a)));
        return c;
    }

    Pair<T> rotated_boxes() {  // two rotated boxes (an Obb and a polyhedron) with a corner near one point
        Pair<T> c;
        c.kind = "rotated through a point";
        const Vec3<T> p{T(uni(-1, 1)), T(uni(-1, 1)), T(uni(-1, 1))};
        c.ray = Ray<T>{Vec3<T>{T(uni(-1, 1)), T(uni(-1, 1)), T(-6)}, Vec3<T>::Zero()};
        c.ray.direction = Vec3<T>(p - c.ray.origin);
        const Mat3<T> R = rotation(), S = rotation();
        // An Obb whose face plane through p faces the ray: center p + R·(h·n) for the axis
        // most against the ray.
        const Vec3<T> h{T(uni(0.5, 2)), T(uni(0.5, 2)), T(uni(0.5, 2))};
        c.a = Obb<T>{p, R, h};
        std::vector<Plane<T>> planes;
        for (int i = 0; i < 3; ++i)
            for (int s : {-1, 1}) {
                const Vec3<T> n = (S.col(i) * T(s)).eval();
                const T lift = T(uni(0, 1));
                planes.push_back({n, T(n.dot(p) + lift * T(pick(2)))});
            }
        c.b = c.poly(std::move(planes));
        return c;
    }

    Pair<T> tangent_spheres() {  // tangent to z = Z at (X, Y) from above
        Pair<T> c;
        c.kind = "spheres tangent to one plane";
        const T X = T(uni(-1, 1)), Y = T(uni(-1, 1)), Z = T(small());
        const T r1 = T(uni(0.1, 3)), r2 = pick(2) == 0 ? T(pick(4) + 1) : T(uni(0.1, 3));
        c.a = Sphere<T>{v3<T>(X, Y, Z + r1), r1};
        c.b = Sphere<T>{v3<T>(X, Y, Z + r2), r2};
        const T dx = T(uni(-1, 1)), sx = T(pick(2)), dy = T(uni(-1, 1)), sy = T(pick(2));
        const Vec3<T> o{T(X + dx * sx), T(Y + dy * sy), T(Z - T(1 + pick(4)))};
        c.ray = Ray<T>{o, Vec3<T>(v3<T>(X, Y, Z) - o)};
        if (c.ray.direction.isZero()) c.ray.direction = v3<T>(0, 0, 1);
        return c;
    }

    Pair<T> internally_tangent() {  // the second sphere tangent inside the first at its entry point
        Pair<T> c;
        c.kind = "internally tangent spheres";
        const Vec3<T> ctr{T(uni(-2, 2)), T(uni(-2, 2)), T(uni(-2, 2))};
        const T r = T(uni(0.5, 2));
        c.ray = Ray<T>{Vec3<T>{T(uni(-1, 1)), T(uni(-1, 1)), T(-8)}, Vec3<T>::Zero()};
        c.ray.direction = Vec3<T>(ctr + Vec3<T>{T(uni(-0.3, 0.3)), T(uni(-0.3, 0.3)), T(0)} - c.ray.origin);
        c.a = Sphere<T>{ctr, r};
        // The entry point p, approximately; sphere b: center p + μ(ctr − p), radius μr.
        const Eigen::Vector3d o = c.ray.origin.template cast<double>(), d = c.ray.direction.template cast<double>(),
                              cc = ctr.template cast<double>();
        const double A = d.dot(d), B = d.dot(o - cc), C = (o - cc).squaredNorm() - double(r) * double(r);
        const double t = (-B - std::sqrt(std::max(0.0, B * B - A * C))) / A;
        const Eigen::Vector3d p = o + t * d;
        const double mu = uni(0.2, 0.9);
        c.b = Sphere<T>{(p + mu * (cc - p)).cast<T>(), T(mu * double(r))};
        return c;
    }

    Pair<T> sphere_on_box() {  // a sphere resting on a box's top face, the ray from above
        Pair<T> c;
        c.kind = "sphere touching a box";
        const T X = T(uni(-1, 1)), Y = T(uni(-1, 1)), Z = T(small());
        const T r = pick(2) == 0 ? T(1 + pick(3)) : T(uni(0.1, 3));
        c.a = Aabb<T>{v3<T>(-5, -5, Z - 3), v3<T>(5, 5, Z)};
        c.b = Sphere<T>{v3<T>(X, Y, Z - r), r};
        c.ray = Ray<T>{v3<T>(X, Y, Z + T(1 + pick(4))), v3<T>(0, 0, -1)};
        if (pick(2) == 0) {  // oblique through the contact point
            c.ray.origin += Vec3<T>{T(uni(-1, 1)), T(uni(-1, 1)), T(0)};
            c.ray.direction = Vec3<T>(v3<T>(X, Y, Z) - c.ray.origin);
        }
        return c;
    }

    Pair<T> face_at_root() {  // a box face at the rounded sphere entry
        Pair<T> c;
        c.kind = "face at a rounded root";
        const Vec3<T> ctr{T(uni(-1, 1)), T(uni(-1, 1)), T(uni(2, 5))};
        const T r = T(uni(0.3, 1.5));
        c.ray = Ray<T>{Vec3<T>{T(uni(-0.2, 0.2)), T(uni(-0.2, 0.2)), T(0)}, v3<T>(0, 0, 1)};
        if (pick(2) == 0) c.ray.direction = Vec3<T>{T(uni(-0.1, 0.1)), T(uni(-0.1, 0.1)), T(1)};
        c.a = Sphere<T>{ctr, r};
        const Hit<T> h = intersect(c.ray, std::get<Sphere<T>>(c.a), certified);
        T z = h ? h.t_enter * c.ray.direction[2] : ctr[2] - r;
        if (const int s = pick(3) - 1; s != 0) z = s > 0 ? std::nextafter(z, T(100)) : std::nextafter(z, T(-100));
        c.b = Aabb<T>{v3<T>(-9, -9, z), v3<T>(9, 9, z + 1)};
        if (pick(2) == 0) c.b = Plane<T>{v3<T>(0, 0, 1), z};
        return c;
    }

    Pair<T> starts_inside() {  // t_min entries against a crossing at t_min
        Pair<T> c;
        c.kind = "t_min entries";
        c.ray = Ray<T>{Vec3<T>{T(small()), T(small()), T(small())}, v3<T>(1 + pick(3), 1, 2), T(pick(3) - 1)};
        const Vec3<T> at = (c.ray.origin + c.ray.direction * c.ray.t_min).eval();  // exact: small integers
        switch (pick(4)) {
            case 0: {
                const T r = T(uni(0, 1));
                c.a = Sphere<T>{at, r * T(pick(2))};
                break;
            }
            case 1: c.a = Aabb<T>{Vec3<T>(at - v3<T>(1, 1, 1)), Vec3<T>(at + v3<T>(1, 1, 1))}; break;
            case 2: c.a = Plane<T>{v3<T>(1, -1, 0), T(at[0] - at[1])}; break;  // through the point at t_min: crossed there, or holding the ray (d_x = 1)
            default: c.a = Aabb<T>{at, Vec3<T>(at + v3<T>(1, 1, 1))}; break;                       // entered at t_min through a face
        }
        const Vec3<T> ctr = (at + c.ray.direction * T(uni(0, 0.5))).eval();
        c.b = Sphere<T>{ctr, T((ctr - at).norm())};  // the point at t_min on its surface, roughly
        if (pick(2) == 0) c.b = Aabb<T>{Vec3<T>(at - v3<T>(2, 2, 2)), at};
        return c;
    }

    Pair<T> obb_on_plane() {  // an Obb's face (integer axes, not unit) against the same or a shifted half-space
        Pair<T> c;
        c.kind = "obb face on a plane";
        const Vec3<T> ctr{T(small()), T(small()), T(small())};
        Mat3<T> A;
        const int p = 1 + pick(3), q = 1 + pick(3);
        A << T(p), T(-q), 0, T(q), T(p), 0, 0, 0, T(1 + pick(2));  // columns (p,q,0), (-q,p,0), (0,0,s)
        const Vec3<T> h{T(1 + pick(4)), T(1 + pick(4)), T(1 + pick(4))};
        c.a = Obb<T>{ctr, A, h};
        // Face side 0 of axis 0: a0·x = a0·ctr − h0 =: K (small integers, exact).
        const Vec3<T> a0 = A.col(0);
        T off = -(a0.dot(ctr) - h[0]);  // the half-space −a0·x <= off is a0·x >= K
        if (const int s = pick(3) - 1; s != 0) off = s > 0 ? std::nextafter(off, T(1000)) : std::nextafter(off, T(-1000));
        c.b = c.poly({Plane<T>{Vec3<T>(-a0), off}, Plane<T>{a0, T(1000)}, Plane<T>{v3<T>(0, 1, 0), T(1000)},
                      Plane<T>{v3<T>(0, -1, 0), T(1000)}, Plane<T>{v3<T>(0, 0, 1), T(1000)}, Plane<T>{v3<T>(0, 0, -1), T(1000)}});
        const T back = T(3 + pick(3));
        const Vec3<T> o = (ctr - a0 * back + Vec3<T>{T(small()), T(small()), T(small())}).eval();
        c.ray = Ray<T>{o, Vec3<T>(ctr + Vec3<T>{T(pick(3) - 1), T(pick(3) - 1), T(pick(3) - 1)} - o)};
        if (c.ray.direction.isZero()) c.ray.direction = a0;
        if (pick(2) == 0) std::swap(c.a, c.b);
        return c;
    }

    Pair<T> any() {
        switch (pick(10)) {
            case 9: return obb_on_plane();
            case 0: return equal_thirds();
            case 1: return ulps_off();
            case 2: return coplanar();
            case 3: return rotated_boxes();
            case 4: return tangent_spheres();
            case 5: return internally_tangent();
            case 6: return sphere_on_box();
            case 7: return face_at_root();
            default: return starts_inside();
        }
    }
};

template <class T> std::string describe(const Pair<T>& c) {
    std::ostringstream os;
    os << c.kind << "\n  ray " << c.ray << "\n  a ";
    std::visit([&](const auto& s) { os << s; }, c.a);
    os << "\n  b ";
    std::visit([&](const auto& s) { os << s; }, c.b);
    return os.str();
}

template <class T> oracle::Exact<T> exact_of(const Ray<T>& r, const Primitive<T>& p) {
    return std::visit([&](const auto& s) { return oracle::exact(r, s); }, p);
}

struct Tally {
    int pairs = 0, exact_path = 0, ties = 0;
    std::map<std::string, int> exact_by_kind;  // past the float filter, per kind of case
};

// One case: returns false on a failure (the caller stops).
template <class T> bool check_pair(const Pair<T>& c, Tally& tally) {
    const PreparedRay<T> pr(c.ray);
    const Hit<T> ha = detail::intersect_primitive(pr, c.a, certified), hb = detail::intersect_primitive(pr, c.b, certified);
    if (!ha || !hb) return true;
    const oracle::Exact<T> ea = exact_of(c.ray, c.a), eb = exact_of(c.ray, c.b);
    EXPECT_TRUE(ea.verdict == Verdict::hit && eb.verdict == Verdict::hit) << describe(c);
    const oracle::Order o = oracle::crosscheck::compare(ea.t_enter, eb.t_enter);
    EXPECT_NE(o, oracle::Order::unordered) << describe(c);
    const int want = o == oracle::Order::below ? -1 : o == oracle::Order::above ? 1 : 0;
    ++tally.pairs;
    if (detail::compare_entry_filter(ha.t_enter, hb.t_enter) == 0) {
        ++tally.exact_path;
        ++tally.exact_by_kind[c.kind.substr(0, c.kind.find(" scale"))];
    }
    tally.ties += want == 0;
    const int ab = detail::compare_entry<T>(pr, c.a, ha, c.b, hb), ba = detail::compare_entry<T>(pr, c.b, hb, c.a, ha);
    EXPECT_EQ(ab, want) << describe(c) << "\n  exact a " << ea.t_enter.str() << "\n  exact b " << eb.t_enter.str()
                        << "\n  hits " << ha << " " << hb;
    EXPECT_EQ(ba, -want) << describe(c);
    const Primitive<T> ps[2] = {c.a, c.b};
    const ClosestHit<T> ch = closest_hit(c.ray, std::span<const Primitive<T>>(ps), certified);
    EXPECT_EQ(ch.index, want <= 0 ? 0 : 1) << describe(c);
    const Primitive<T> qs[2] = {c.b, c.a};
    EXPECT_EQ(closest_hit(c.ray, std::span<const Primitive<T>>(qs), certified).index, want >= 0 ? 0 : 1) << describe(c);
    return !::testing::Test::HasFailure();
}

template <class T> class ClosestOracle : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(ClosestOracle, Scalars);

TYPED_TEST(ClosestOracle, CompareEntryIsTheExactOrder) {
    using T = TypeParam;
    RAYPROOF_SEED_TRACE(base_seed());
    auto rng = make_rng();
    Maker<T> m{rng};
    // Scales: 1, far out, far in, and the denormals (where the scaled inputs lose bits: a
    // different case, judged the same way).
    const std::vector<int> scales = std::is_same_v<T, float> ? std::vector<int>{0, 100, -100, -135}
                                                              : std::vector<int>{0, 1000, -1000, -1060};
    Tally tally;
    for (int k = 0; k < 1500; ++k) {
        const Pair<T> base = m.any();
        for (const int e : scales)
            if (!check_pair(e == 0 ? base : scaled(base, e), tally)) return;
    }
    std::printf("pairs hit %d, past the float filter %d, exact ties %d\n", tally.pairs, tally.exact_path, tally.ties);
    for (const auto& [kind, n] : tally.exact_by_kind) std::printf("  past the filter: %5d %s\n", n, kind.c_str());
    EXPECT_GT(tally.pairs, 3000);
    EXPECT_GT(tally.exact_path, 1000) << "the cases must reach the exact comparison";
    EXPECT_GT(tally.ties, 300) << "the cases must hold exact ties";
}

// Degree-8 comparisons at mixed extreme exponents (huge origin and radii, denormal
// direction components), where the exact stage runs in BigDyadic8 at its widest: the
// exact stage must give an answer (never its fallback) and it must be the oracle's.
TYPED_TEST(ClosestOracle, MixedExtremeExponentsAreDecidedExactly) {
    using T = TypeParam;
    RAYPROOF_SEED_TRACE(base_seed());
    auto rng = make_rng();
    Maker<T> m{rng};
    constexpr bool dbl = std::is_same_v<T, double>;
    const int big = dbl ? 999 : 120;        // the spheres' scale, 2^big
    const int low = dbl ? -1074 : -149;     // the denormals' bottom
    Tally tally;
    int decided = 0;
    for (int k = 0; k < 300; ++k) {
        Pair<T> c;
        c.kind = "mixed exponents";
        const T R = std::ldexp(T(1), big);
        const T mx = T(1 + m.pick(7));
        const T tiny_x = std::ldexp(mx, low + m.pick(dbl ? 1000 : 100));
        const T my = m.pick(2) == 0 ? T(0) : T(1 + m.pick(7));
        const T tiny_y = std::ldexp(my, low + m.pick(20));
        c.ray = Ray<T>{Vec3<T>{std::ldexp(T(m.pick(9)), low), -std::ldexp(T(m.pick(5)), low), -2 * R},
                       Vec3<T>(tiny_x, tiny_y, T(1 + m.pick(3)))};
        c.a = Sphere<T>{v3<T>(0, 0, 0), R};                         // entry near z = -R
        const T r = std::ldexp(T(1), big - 1 - m.pick(dbl ? 90 : 20));
        switch (m.pick(3)) {
            case 0: c.b = Sphere<T>{Vec3<T>(T(0), T(0), T(-R + r)), r}; break;  // tangent inside at (0,0,-R)
            case 1: c.b = Sphere<T>{Vec3<T>(T(0), T(0), T(-R - r)), r}; break;  // tangent outside at (0,0,-R), met first
            default: c.b = Aabb<T>{Vec3<T>(-R, -R, -R), Vec3<T>(R, R, T(-R + r))}; break;  // a face on the tangent plane
        }
        if (m.pick(2) == 0) std::swap(c.a, c.b);
        const PreparedRay<T> pr(c.ray);
        const Hit<T> ha = detail::intersect_primitive(pr, c.a, certified), hb = detail::intersect_primitive(pr, c.b, certified);
        if (!ha || !hb) continue;
        const std::optional<int> s = detail::compare_entry_exact<T>(pr, c.a, ha, c.b, hb);
        ASSERT_TRUE(s.has_value()) << describe(c);
        ++decided;
        if (!check_pair(c, tally)) return;
    }
    std::printf("decided %d, past the float filter %d\n", decided, tally.exact_path);
    EXPECT_GT(decided, 150);
    EXPECT_GT(tally.exact_path, 50);
}

}  // namespace
