// Ray vs ConvexPolyhedron with general planes, judged against an exact reference in GMP
// rationals (the kernel never uses GMP): per plane num = offset - n·o and den = n·d as
// rationals of the stored floats, the exact interval [max(t_min, entries), min(t_max,
// exits)], parallel planes by the sign of num, the face as the lowest entering plane
// whose crossing equals t_enter (-1 when t_min does). Certified: the verdict and the
// face equal the reference, t_enter and t_exit faithfully round it (faithful.hpp);
// verdict() agrees. Conservative: a hit wherever the reference hits, an interval
// enclosing the exact one. Over float and double, on seeded cases built to reach the
// exact stage: planes through one point (their crossings tie or nearly tie, the
// offsets n·P rounded), rays nearly parallel to a plane, origins on or near planes,
// random polytopes of up to 64 planes, some scenes on a grid where the planes through the
// point tie exactly (grazing touches, the lowest index among tied entries), each scene scaled by 2^s (2^±1000, denormals;
// 2^±100 and float denormals for float), with normals and directions scaled apart.
#include "faithful.hpp"
#include "seeded.hpp"

#include <rayproof/rayproof.hpp>

#include <Eigen/Geometry>
#include <gmpxx.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <sstream>
#include <vector>

using namespace rayproof;
using namespace rayproof::testing;

template <class T> class RayPolyhedronExact : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(RayPolyhedronExact, Scalars);

namespace {

std::uint64_t base_seed() {
    static const std::uint64_t s = env_seed_or(1912);
    return s;
}

mpq_class Q(double x) { return mpq_class(x); }

// The exact answer. enter/exit empty for -inf/+inf.
struct Exact {
    bool hit = false;
    std::optional<mpq_class> enter, exit;
    int face = -1;
};

template <class T> Exact reference(const Ray<T>& r, const std::vector<Plane<T>>& planes) {
    Exact e;
    if (!std::isinf(r.t_min)) e.enter = Q(r.t_min);
    if (!std::isinf(r.t_max)) e.exit = Q(r.t_max);
    for (std::size_t k = 0; k < planes.size(); ++k) {
        const Plane<T>& p = planes[k];
        mpq_class num = Q(p.offset), den = 0;
        for (int j = 0; j < 3; ++j) {
            num -= Q(p.normal[j]) * Q(r.origin[j]);
            den += Q(p.normal[j]) * Q(r.direction[j]);
        }
        if (sgn(den) == 0) {
            if (sgn(num) < 0) return Exact{};
            continue;
        }
        const mpq_class t = num / den;
        if (sgn(den) < 0) {
            if (!e.enter || t > *e.enter) e.enter = t, e.face = int(k);
        } else if (!e.exit || t < *e.exit) {
            e.exit = t;
        }
    }
    e.hit = !e.enter || !e.exit || *e.enter <= *e.exit;
    return e;
}

template <class T> auto minus_bound(const std::optional<mpq_class>& q, bool upper) {
    // sign(x - v) for v = q, or v = -inf (upper false) / +inf (upper true) when empty.
    return [q, upper](T x) -> int {
        if (q) return minus_rational(*q)(x);
        if (std::isinf(x) && (x > 0) == upper) return 0;
        return upper ? -1 : 1;
    };
}

template <class T> std::string repro(const Ray<T>& r, const std::vector<Plane<T>>& p) {
    std::ostringstream os;
    os << r << " vs " << ConvexPolyhedron<T>{p};
    return os.str();
}

template <class T> Vec3<T> scaled(const Vec3<double>& v, int e) {
    return Vec3<T>(T(std::ldexp(v[0], e)), T(std::ldexp(v[1], e)), T(std::ldexp(v[2], e)));
}

template <class T> std::vector<int> exponents() {
    if constexpr (std::is_same_v<T, float>) return {0, 0, 0, 0, 100, -100, -130, 60, -60};
    else return {0, 0, 0, 0, 1000, -1000, -1060, 500, -500};
}

// A seeded scene: kind 0 planes through one point P with the ray through P, kind 1 a
// plane nearly parallel to the ray, kind 2 a random polytope around the origin, kind 3
// origins on planes. Positions and offsets scaled by 2^s, normals by 2^sn, directions by
// 2^sd (a plane's offset scales with s + sn).
template <class T> void scene(std::mt19937_64& rng, Ray<T>& r, std::vector<Plane<T>>& planes) {
    std::uniform_real_distribution<double> u(-1, 1);
    std::uniform_int_distribution<int> kind_of(0, 3), count(1, 64), coin(0, 3);
    const std::vector<int> ex = exponents<T>();
    std::uniform_int_distribution<int> pick(0, int(ex.size()) - 1);
    const int s = ex[std::size_t(pick(rng))], sn = coin(rng) ? 0 : ex[std::size_t(pick(rng))] / 2,
              sd = coin(rng) ? 0 : ex[std::size_t(pick(rng))] / 2;
    // Braces: the three draws are sequenced left to right (a call's arguments are not).
    const auto rv = [&] { return Vec3<double>{u(rng), u(rng), u(rng)}; };
    // Work in double at unit scale, then scale and round to T.
    const int kind = kind_of(rng);
    const int n = kind == 2 ? count(rng) : std::uniform_int_distribution<int>(1, 8)(rng);
    // Now and then every number on a grid of 2^-8 (|x| <= 2): n·P, P - k·d and the
    // crossings' comparisons are then exact in float too, so planes through P tie exactly.
    const bool grid = coin(rng) == 0;
    const auto q = [grid](Vec3<double> v) {
        if (grid)
            for (int j = 0; j < 3; ++j) v[j] = std::round(v[j] * 256) / 256;
        return v;
    };
    const Vec3<double> P = q(rv() * 2);
    Vec3<double> d = q(rv());
    if (d.isZero()) d[0] = 1;
    const double k = std::uniform_int_distribution<int>(1, 4)(rng);
    Vec3<double> o = kind == 0 ? Vec3<double>(P - k * d) : Vec3<double>(rv() * 4);
    std::vector<Vec3<double>> normals;
    std::vector<double> offsets;
    for (int i = 0; i < n; ++i) {
        Vec3<double> nrm = q(rv());
        if (nrm.isZero()) nrm[2] = 1;
        double off;
        switch (kind) {
            case 0: off = nrm.dot(P); break;                                   // through P (rounded)
            case 1:
                if (i == 0) nrm = d.cross(rv()), nrm = nrm.isZero() ? Vec3<double>(1, 0, 0) : nrm;  // n·d ~ 0
                off = nrm.dot(o) + (coin(rng) ? 0.0 : u(rng) * 1e-12);
                break;
            case 3: off = nrm.dot(o); break;                                   // origin on (near) the plane
            default: off = 1 + u(rng) * 0.5; break;                            // around the origin
        }
        normals.push_back(nrm);
        offsets.push_back(off);
    }
    r = Ray<T>{scaled<T>(o, s), scaled<T>(d, sd)};
    if (r.direction.isZero()) r.direction[0] = T(1);
    switch (coin(rng)) {
        case 0: r.t_min = -std::numeric_limits<T>::infinity(); break;
        case 1: {  // at P's crossing (kind 0), where finite
            const T t = T(std::ldexp(k, s - sd));
            if (std::isfinite(t)) r.t_min = t;
            break;
        }
        default: break;
    }
    planes.clear();
    for (int i = 0; i < n; ++i) {
        Plane<T> p{scaled<T>(normals[std::size_t(i)], sn), T(std::ldexp(offsets[std::size_t(i)], s + sn))};
        if (p.normal.isZero()) p.normal[0] = T(1);
        if (!std::isfinite(p.offset)) p.offset = T(0);
        planes.push_back(p);
        if (kind == 0 && coin(rng) == 0) planes.push_back(p);  // a duplicate now and then
    }
}

template <class T> void run(int cases) {
    std::mt19937_64 rng = rng_for_current_test(base_seed());
    RAYPROOF_SEED_TRACE(base_seed());
    Ray<T> r;
    std::vector<Plane<T>> planes;
    int hits = 0, faces = 0, ties = 0;
    for (int n = 0; n < cases; ++n) {
        scene(rng, r, planes);
        const ConvexPolyhedron<T> c{planes};
        SCOPED_TRACE("case " + std::to_string(n) + ": " + repro(r, planes));
        const Exact e = reference(r, planes);
        const Hit<T> h = intersect(r, c, certified);
        ASSERT_EQ(h.verdict, e.hit ? Verdict::hit : Verdict::miss) << h;
        ASSERT_EQ(verdict(r, c, certified), h.verdict);
        const Hit<T> cons = intersect(r, c, conservative);
        if (!e.hit) {
            ASSERT_NE(cons.verdict, Verdict::invalid);
            continue;
        }
        ++hits;
        faces += e.face >= 0;
        ASSERT_EQ(h.face, e.face) << h;
        ASSERT_TRUE(is_faithful(h.t_enter, minus_bound<T>(e.enter, false))) << "t_enter " << h;
        ASSERT_TRUE(is_faithful(h.t_exit, minus_bound<T>(e.exit, true))) << "t_exit " << h;
        ASSERT_LE(h.t_enter, h.t_exit) << h;
        ties += e.enter && e.exit && *e.enter == *e.exit;
        ASSERT_EQ(cons.verdict, Verdict::hit) << cons;
        ASSERT_LE(minus_bound<T>(e.enter, false)(cons.t_enter), 0) << "conservative t_enter " << cons;
        ASSERT_GE(minus_bound<T>(e.exit, true)(cons.t_exit), 0) << "conservative t_exit " << cons;
    }
    // The mix the cases are for.
    EXPECT_GT(hits, cases / 10);
    EXPECT_GT(faces, cases / 20);
    std::cout << "cases " << cases << ", hits " << hits << ", entry faces " << faces << ", touching " << ties << '\n';
}

}  // namespace

TYPED_TEST(RayPolyhedronExact, MatchesTheRationalReference) { run<TypeParam>(30000); }
