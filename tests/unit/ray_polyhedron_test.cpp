// Ray vs ConvexPolyhedron, over float and double and every mode. Covers:
//   - hand cases through every mode (fast included: small integers, every value exact):
//     a cube, rays from inside, parallel rays on and off a face;
//   - a box's six planes in the order (-x, +x, -y, +y, -z, +z) answer in certified mode
//     exactly as the Aabb does (verdict, t_enter and t_exit bit for bit, face 2*axis +
//     side), on seeded random and hard rays (±0 components, origin on a face, grazing
//     edges and corners, 2^±1000 scaling (2^±100 for float), denormals, limits), and
//     the same box among up to 64 planes, the others redundant, in a seeded order;
//   - duplicate and coincident planes (a normal scaled by 2): the lowest index wins the
//     face, at a face, an edge and a vertex;
//   - no planes: all of space; infeasible sets miss in every mode; unbounded sets;
//   - one plane equals the half-space, decided in exact integer arithmetic on seeded
//     integer inputs, its crossing the plane's certified t bit for bit;
//   - a flat slab from two opposite planes with equal offsets;
//   - invalid inputs (zero normal, non-finite numbers, the ray's own classes), an invalid
//     plane after the one where fast mode's pass stops, and a valid plane whose num
//     overflows (not invalid);
//   - verdict() == intersect().verdict in every mode; batch == scalar and PreparedRay ==
//     Ray (and RuntimeMode::certified == certified) bit for bit in certified mode;
//     conservative encloses the certified interval;
//   - certified and conservative answers under directed rounding equal the default
//     environment's, bit for bit.
// Every random case is seeded (RAYPROOF_SEED=<decimal> replays, seeded.hpp) and prints
// the ray and the planes in hexadecimal when it fails; vectors are drawn in braces, whose
// elements are evaluated left to right, so every compiler draws the same cases.
#include "seeded.hpp"
#include "unit_support.hpp"

#include <algorithm>
#include <cfenv>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

using namespace rayproof;
using namespace rayproof::testing;

template <class T> class RayPolyhedron : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(RayPolyhedron, Scalars);

namespace {

std::uint64_t base_seed() {
    static const std::uint64_t s = env_seed_or(20261203);
    return s;
}
std::mt19937_64 make_rng() { return rng_for_current_test(base_seed()); }

template <class T> bool same_bits(T a, T b) { return std::memcmp(&a, &b, sizeof(T)) == 0; }

template <class T> ::testing::AssertionResult same_hit(const Hit<T>& a, const Hit<T>& b) {
    if (a.verdict != b.verdict) return ::testing::AssertionFailure() << a << " != " << b;
    if (a.verdict != Verdict::hit) return ::testing::AssertionSuccess();
    if (!same_bits(a.t_enter, b.t_enter) || !same_bits(a.t_exit, b.t_exit) || a.face != b.face)
        return ::testing::AssertionFailure() << a << " != " << b;
    return ::testing::AssertionSuccess();
}

// The box's planes in the order (-x, +x, -y, +y, -z, +z): plane 2i + side is the Aabb's
// face 2i + side.
template <class T> std::vector<Plane<T>> box_planes(const Aabb<T>& b) {
    std::vector<Plane<T>> p;
    for (int i = 0; i < 3; ++i) {
        Vec3<T> e = Vec3<T>::Zero();
        e[i] = 1;
        p.push_back({-e, -b.lo[i]});
        p.push_back({e, b.hi[i]});
    }
    return p;
}

template <class T> std::string repro(const Ray<T>& r, const std::vector<Plane<T>>& p) {
    std::ostringstream os;
    os << r << " vs " << ConvexPolyhedron<T>{p};
    return os.str();
}

// Scale factors for hard cases: huge, tiny and denormal ranges of each type.
template <class T> std::vector<int> scale_exponents() {
    if constexpr (std::is_same_v<T, float>) return {0, 0, 0, 100, -100, -60, -140, 60};
    else return {0, 0, 0, 1000, -1000, 500, -500, -1070};
}

// A seeded random or hard ray and box. Small integers make edges, corners, faces and
// parallels exact; random reals exercise the general rounding; then the whole scene
// (box and origin) is scaled by 2^s, and the direction by 2^s2 (either may be 0).
template <class T> struct Scene {
    Ray<T> ray;
    Aabb<T> box;
};
template <class T> Scene<T> hard_scene(std::mt19937_64& rng) {
    std::uniform_int_distribution<int> small(-4, 4), pick(0, 11), coin(0, 1);
    std::uniform_real_distribution<double> real(-4, 4);
    Scene<T> s;
    const bool integers = coin(rng);
    auto val = [&] { return integers ? T(small(rng)) : T(real(rng)); };
    for (int i = 0; i < 3; ++i) {
        T a = val(), b = val();
        if (a > b) std::swap(a, b);
        s.box.lo[i] = a;
        s.box.hi[i] = b;
        s.ray.origin[i] = val();
        s.ray.direction[i] = val();
    }
    const int axis = std::uniform_int_distribution<int>(0, 2)(rng);
    switch (pick(rng)) {
        case 0: s.ray.direction[axis] = coin(rng) ? T(0) : -T(0); break;                       // parallel (±0)
        case 1: s.ray.direction[axis] = -T(0); s.ray.origin[axis] = s.box.lo[axis]; break;      // in a face plane
        case 2: s.ray.origin[axis] = coin(rng) ? s.box.lo[axis] : s.box.hi[axis]; break;        // origin on a face
        case 3: {  // through a corner: origin = corner - k·d with small integers (exact)
            const T k = T(std::uniform_int_distribution<int>(1, 3)(rng));
            for (int i = 0; i < 3; ++i) {
                s.box.lo[i] = T(small(rng));
                s.box.hi[i] = s.box.lo[i] + T(std::uniform_int_distribution<int>(0, 3)(rng));
                s.ray.direction[i] = T(small(rng));
                s.ray.origin[i] = (coin(rng) ? s.box.lo[i] : s.box.hi[i]) - k * s.ray.direction[i];
            }
            break;
        }
        case 4: {  // grazing an edge: as above, one axis free
            const T k = T(2);
            for (int i = 0; i < 3; ++i) {
                s.box.lo[i] = T(small(rng));
                s.box.hi[i] = s.box.lo[i] + T(2);
                s.ray.direction[i] = T(small(rng));
                s.ray.origin[i] = (coin(rng) ? s.box.lo[i] : s.box.hi[i]) - k * s.ray.direction[i];
            }
            s.ray.origin[axis] = s.box.lo[axis] + T(1) - k * s.ray.direction[axis];
            break;
        }
        case 5: s.ray.t_min = T(small(rng)); s.ray.t_max = s.ray.t_min + T(std::uniform_int_distribution<int>(0, 4)(rng)); break;
        case 6: s.ray.t_min = -std::numeric_limits<T>::infinity(); break;
        case 7: s.box.hi[axis] = s.box.lo[axis]; break;  // flat box
        default: break;
    }
    if (s.ray.direction.isZero()) s.ray.direction[axis] = T(1);
    const std::vector<int> ex = scale_exponents<T>();
    const int e = ex[std::size_t(std::uniform_int_distribution<int>(0, int(ex.size()) - 1)(rng))];
    const int e2 = coin(rng) ? 0 : ex[std::size_t(std::uniform_int_distribution<int>(0, int(ex.size()) - 1)(rng))];
    for (int i = 0; i < 3; ++i) {
        s.box.lo[i] = std::ldexp(s.box.lo[i], e);
        s.box.hi[i] = std::ldexp(s.box.hi[i], e);
        s.ray.origin[i] = std::ldexp(s.ray.origin[i], e);
        s.ray.direction[i] = std::ldexp(s.ray.direction[i], e2);
    }
    if (s.ray.direction.isZero()) s.ray.direction[axis] = T(1);  // underflowed to zero
    return s;
}

template <class T> T step_up(T x) { return std::nextafter(x, std::numeric_limits<T>::infinity()); }
template <class T> T step_down(T x) { return std::nextafter(x, -std::numeric_limits<T>::infinity()); }

// Every cross-check of one ray against one polyhedron that needs no reference answer:
// verdict() == intersect().verdict in every mode, PreparedRay == Ray and the run-time
// mode == the tag bit for bit in certified mode, conservative encloses certified (the exact ends lie within one step
// of the certified ones).
template <class T> void self_consistent(const Ray<T>& r, const ConvexPolyhedron<T>& c) {
    const Hit<T> cert = intersect(r, c, certified);
    EXPECT_EQ(verdict(r, c, certified), cert.verdict);
    EXPECT_EQ(verdict(r, c, fast), intersect(r, c, fast).verdict);
    const Hit<T> cons = intersect(r, c, conservative);
    EXPECT_EQ(verdict(r, c, conservative), cons.verdict);
    const PreparedRay<T> pr(r);
    EXPECT_TRUE(same_hit(intersect(pr, c, certified), cert));
    EXPECT_TRUE(same_hit(intersect(r, c, RuntimeMode::certified), cert));
    EXPECT_EQ(verdict(r, c, RuntimeMode::certified), cert.verdict);
    EXPECT_EQ(verdict(pr, c, certified), cert.verdict);
    if (cert.verdict == Verdict::invalid) {
        EXPECT_EQ(cons.verdict, Verdict::invalid);
        return;
    }
    if (cert.verdict != Verdict::hit) return;
    ASSERT_EQ(cons.verdict, Verdict::hit) << cons << " certified " << cert;
    EXPECT_LE(cons.t_enter, step_up(cert.t_enter)) << cons << " certified " << cert;
    EXPECT_GE(cons.t_exit, step_down(cert.t_exit)) << cons << " certified " << cert;
    EXPECT_LE(cert.t_enter, cert.t_exit) << cert;
}

}  // namespace

TYPED_TEST(RayPolyhedron, HandCasesOnACube) {
    using T = TypeParam;
    const Aabb<T> box{v<T>(-1, -1, -1), v<T>(1, 1, 1)};
    const std::vector<Plane<T>> p = box_planes(box);
    const ConvexPolyhedron<T> cube{p};
    check(Ray<T>{v<T>(-4, 0, 0), v<T>(1, 0, 0)}, cube, hit<T>(3, 5, 0));
    check(Ray<T>{v<T>(4, 0, 0), v<T>(-1, 0, 0)}, cube, hit<T>(3, 5, 1));
    check(Ray<T>{v<T>(0, 4, 0), v<T>(0, -2, 0)}, cube, hit<T>(1.5, 2.5, 3));
    check(Ray<T>{v<T>(0, 0, -3), v<T>(0, 0, 1)}, cube, hit<T>(2, 4, 4));
    check(Ray<T>{v<T>(-3, -3, -3), v<T>(1, 1, 1)}, cube, hit<T>(2, 4, 0));  // a vertex: lowest index
    check(Ray<T>{v<T>(0, 0, 0), v<T>(0, 0, 1)}, cube, hit<T>(0, 1, -1));   // from inside
    check(Ray<T>{v<T>(-1, 0, 0), v<T>(1, 0, 0)}, cube, hit<T>(0, 2, -1));  // origin on the entry face
    check(Ray<T>{v<T>(-4, 1, 0), v<T>(1, -0.0, 0)}, cube, hit<T>(3, 5, 0)); // parallel, in the face y = 1
    check(Ray<T>{v<T>(-4, 2, 0), v<T>(1, 0, 0)}, cube, miss<T>());          // parallel, outside
    check(Ray<T>{v<T>(-4, 0, 0), v<T>(-1, 0, 0)}, cube, miss<T>());         // pointing away
    check(Ray<T>{v<T>(-4, 0, 0), v<T>(1, 0, 0), 0, 2}, cube, miss<T>());    // stops short
    check(Ray<T>{v<T>(-4, 0, 0), v<T>(1, 0, 0), 4, 10}, cube, hit<T>(4, 5, -1));
    check(Ray<T>{v<T>(-4, 0, 0), v<T>(1, 0, 0), 0, 3}, cube, hit<T>(3, 3, 0));  // touches at t_max
    check(Ray<T>{v<T>(-3, -1, 0), v<T>(1, 1, 0)}, cube, hit<T>(2, 2, 0));    // grazes the edge (-1, 1)
}

TYPED_TEST(RayPolyhedron, BoxPlanesAnswerAsTheAabbBitForBit) {
    using T = TypeParam;
    auto rng = make_rng();
    RAYPROOF_SEED_TRACE(base_seed());
    int hits = 0, misses = 0, inside = 0, n = 0;
    for (; n < 40000; ++n) {
        const Scene<T> s = hard_scene<T>(rng);
        const std::vector<Plane<T>> p = box_planes(s.box);
        const ConvexPolyhedron<T> c{p};
        const Hit<T> want = intersect(s.ray, s.box, certified), got = intersect(s.ray, c, certified);
        ASSERT_TRUE(same_hit(got, want)) << "case " << n << ": " << repro(s.ray, p);
        ASSERT_EQ(verdict(s.ray, c, certified), want.verdict) << "case " << n << ": " << repro(s.ray, p);
        self_consistent(s.ray, c);
        if (::testing::Test::HasFailure()) FAIL() << "case " << n << ": " << repro(s.ray, p);
        hits += want.verdict == Verdict::hit;
        misses += want.verdict == Verdict::miss;
        inside += want.verdict == Verdict::hit && want.face < 0;
    }
    // The mix is what the cases are for: many of each answer.
    EXPECT_GT(hits, n / 10);
    EXPECT_GT(misses, n / 10);
    EXPECT_GT(inside, n / 100);
}

TYPED_TEST(RayPolyhedron, BoxAmongRedundantPlanesUpTo64) {
    using T = TypeParam;
    auto rng = make_rng();
    RAYPROOF_SEED_TRACE(base_seed());
    std::uniform_real_distribution<double> unit(-1, 1);
    std::uniform_int_distribution<int> count(0, 58);
    for (int n = 0; n < 3000; ++n) {
        // The redundant planes contain the box, within [-4, 4]^3, strictly (|n_i| <= 1,
        // offset 100 > 12).
        Scene<T> s{Ray<T>{Vec3<T>::Zero(), Vec3<T>::Zero()}, Aabb<T>{Vec3<T>::Zero(), Vec3<T>::Zero()}};
        std::uniform_int_distribution<int> small(-4, 4);
        std::uniform_real_distribution<double> real(-4, 4);
        for (int i = 0; i < 3; ++i) {
            T a = T(small(rng)), b = T(small(rng));
            if (a > b) std::swap(a, b);
            s.box.lo[i] = a, s.box.hi[i] = b;
            s.ray.origin[i] = T(real(rng) * 8);
            s.ray.direction[i] = T(real(rng));
        }
        if (n % 3 == 0) s.ray.direction[n % 2] = T(0);
        std::vector<Plane<T>> p;
        const std::vector<Plane<T>> bp = box_planes(s.box);
        const int extra = count(rng);
        for (int k = 0; k < extra; ++k) {
            Vec3<T> nrm{T(unit(rng)), T(unit(rng)), T(unit(rng))};
            if (nrm.isZero()) nrm[0] = T(1);
            p.push_back({nrm, T(100)});
        }
        // The box planes at seeded positions, in their order, among the others.
        std::vector<int> pos(p.size() + 6);
        std::iota(pos.begin(), pos.end(), 0);
        std::shuffle(pos.begin(), pos.end(), rng);
        std::sort(pos.begin(), pos.begin() + 6);
        std::vector<Plane<T>> all(p.size() + 6);
        std::vector<bool> taken(all.size(), false);
        for (int k = 0; k < 6; ++k) all[std::size_t(pos[std::size_t(k)])] = bp[std::size_t(k)], taken[std::size_t(pos[std::size_t(k)])] = true;
        std::size_t next = 0;
        for (std::size_t k = 0; k < all.size(); ++k)
            if (!taken[k]) all[k] = p[next++];
        ASSERT_LE(all.size(), 64u);
        const ConvexPolyhedron<T> c{all};
        Hit<T> want = intersect(s.ray, s.box, certified);
        if (want.verdict == Verdict::hit && want.face >= 0) want.face = pos[std::size_t(want.face)];
        const Hit<T> got = intersect(s.ray, c, certified);
        ASSERT_TRUE(same_hit(got, want)) << "case " << n << ": " << repro(s.ray, all);
        self_consistent(s.ray, c);
        if (::testing::Test::HasFailure()) FAIL() << "case " << n << ": " << repro(s.ray, all);
    }
}

TYPED_TEST(RayPolyhedron, DuplicateAndCoincidentPlanesGiveTheLowestIndex) {
    using T = TypeParam;
    const Aabb<T> box{v<T>(0, 0, 0), v<T>(2, 2, 2)};
    const std::vector<Plane<T>> b = box_planes(box);
    // -x as plane 1 (scaled by 2: the same half-space) and as plane 4 (a duplicate); -y
    // as 2 and 5.
    const std::vector<Plane<T>> p = {b[1], {v<T>(-2, 0, 0), T(0)}, b[2], b[3], b[0], b[2], b[4], b[5]};
    const ConvexPolyhedron<T> c{p};
    check(Ray<T>{v<T>(-2, 1, 1), v<T>(1, 0, 0)}, c, hit<T>(2, 4, 1));            // through -x
    check(Ray<T>{v<T>(1, -2, 1), v<T>(0, 1, 0)}, c, hit<T>(2, 4, 2));            // through -y
    check(Ray<T>{v<T>(-1, -1, 1), v<T>(1, 1, 0)}, c, hit<T>(1, 3, 1));           // the edge -x/-y
    check(Ray<T>{v<T>(-1, -1, -1), v<T>(1, 1, 1)}, c, hit<T>(1, 3, 1));          // the vertex
    check(Ray<T>{v<T>(1, 1, -3), v<T>(0, 0, 1)}, c, hit<T>(3, 5, 6));
    // Reversed order: the duplicate comes first now.
    const std::vector<Plane<T>> q(p.rbegin(), p.rend());
    const ConvexPolyhedron<T> cq{q};
    check(Ray<T>{v<T>(-2, 1, 1), v<T>(1, 0, 0)}, cq, hit<T>(2, 4, 3));
    check(Ray<T>{v<T>(-1, -1, 1), v<T>(1, 1, 0)}, cq, hit<T>(1, 3, 2));           // -y at 2 before -x at 3
    // The same on seeded rays through the box, certified against the plain box: the face
    // maps to the lowest index among the planes of that face.
    auto rng = make_rng();
    RAYPROOF_SEED_TRACE(base_seed());
    const int lowest[6] = {1, 0, 2, 3, 6, 7};  // box face -> lowest plane index in p
    for (int n = 0; n < 5000; ++n) {
        std::uniform_int_distribution<int> small(-4, 4);
        Ray<T> r{Vec3<T>::Zero(), Vec3<T>::Zero()};
        for (int i = 0; i < 3; ++i) r.origin[i] = T(small(rng)), r.direction[i] = T(small(rng));
        if (r.direction.isZero()) r.direction[0] = T(1);
        Hit<T> want = intersect(r, box, certified);
        if (want.verdict == Verdict::hit && want.face >= 0) want.face = lowest[want.face];
        ASSERT_TRUE(same_hit(intersect(r, c, certified), want)) << repro(r, p);
    }
}

TYPED_TEST(RayPolyhedron, NoPlanesIsAllOfSpace) {
    using T = TypeParam;
    const ConvexPolyhedron<T> all{};
    constexpr T inf = std::numeric_limits<T>::infinity();
    check(Ray<T>{v<T>(1, 2, 3), v<T>(0, 0, 1)}, all, hit<T>(0, inf, -1));
    check(Ray<T>{v<T>(1, 2, 3), v<T>(0, 0, 1), -2, 5}, all, hit<T>(-2, 5, -1));
    check(Ray<T>{v<T>(1, 2, 3), v<T>(0, 0, 1), -inf, inf}, all, hit<T>(-inf, inf, -1));
    check(Ray<T>{v<T>(1, 2, 3), v<T>(0, 0, 0)}, all, invalid<T>());
    auto rng = make_rng();
    for (int n = 0; n < 2000; ++n) {
        const Scene<T> s = hard_scene<T>(rng);
        const Hit<T> h = intersect(s.ray, all, certified);
        ASSERT_EQ(h.verdict, Verdict::hit) << s.ray;
        EXPECT_TRUE(same_bits(h.t_enter, s.ray.t_min) && same_bits(h.t_exit, s.ray.t_max) && h.face == -1) << h;
        self_consistent(s.ray, all);
    }
}

TYPED_TEST(RayPolyhedron, InfeasibleSetsMissAndUnboundedSetsHit) {
    using T = TypeParam;
    constexpr T inf = std::numeric_limits<T>::infinity();
    // x <= 0 and x >= 1: empty.
    const std::vector<Plane<T>> empty = {{v<T>(1, 0, 0), T(0)}, {v<T>(-1, 0, 0), T(-1)}};
    const ConvexPolyhedron<T> e{empty};
    check(Ray<T>{v<T>(-4, 0, 0), v<T>(1, 0, 0)}, e, miss<T>());
    check(Ray<T>{v<T>(0.5, 0, 0), v<T>(0, 1, 0), -inf, inf}, e, miss<T>());
    check(Ray<T>{v<T>(0, 0, 0), v<T>(1, 1, 1), -inf, inf}, e, miss<T>());
    // x + y <= 1, -x - y <= -3 (x + y >= 3) among other planes: empty.
    const std::vector<Plane<T>> empty2 = {{v<T>(0, 0, 1), T(5)}, {v<T>(1, 1, 0), T(1)}, {v<T>(-1, -1, 0), T(-3)}};
    const ConvexPolyhedron<T> e2{empty2};
    auto rng = make_rng();
    std::uniform_real_distribution<double> u(-8, 8);
    for (int n = 0; n < 2000; ++n) {
        const Ray<T> r{Vec3<T>{T(u(rng)), T(u(rng)), T(u(rng))}, Vec3<T>{T(u(rng)), T(u(rng)), T(u(rng))}, -inf, inf};
        EXPECT_EQ(intersect(r, e2, certified).verdict, Verdict::miss) << r;
        EXPECT_EQ(intersect(r, e2, conservative).verdict == Verdict::invalid, false) << r;
        EXPECT_EQ(verdict(r, e2, certified), Verdict::miss) << r;
    }
    // Unbounded: the wedge x <= 0, y <= 0 (z free).
    const std::vector<Plane<T>> wedge = {{v<T>(1, 0, 0), T(0)}, {v<T>(0, 1, 0), T(0)}};
    const ConvexPolyhedron<T> w{wedge};
    check(Ray<T>{v<T>(-1, -1, 0), v<T>(0, 0, 1)}, w, hit<T>(0, inf, -1));
    check(Ray<T>{v<T>(-1, -1, 0), v<T>(0, 0, 1), -inf, inf}, w, hit<T>(-inf, inf, -1));
    check(Ray<T>{v<T>(-1, -1, 0), v<T>(1, 0, 0)}, w, hit<T>(0, 1, -1));
    check(Ray<T>{v<T>(3, -1, 0), v<T>(-1, 0, 0)}, w, hit<T>(3, inf, 0));
    check(Ray<T>{v<T>(3, 2, 0), v<T>(-1, -1, 0), -inf, inf}, w, hit<T>(3, inf, 0));  // x enters last
    check(Ray<T>{v<T>(2, 2, 0), v<T>(-1, -1, 0), -inf, inf}, w, hit<T>(2, inf, 0));  // both at 2: lowest
    check(Ray<T>{v<T>(1, 0, 0), v<T>(0, 1, 0), -inf, inf}, w, miss<T>());            // parallel to x, outside
}

// One plane is the half-space n·p <= offset. On seeded integer inputs num = offset - n·o,
// den = n·d and num - t_min·den are exact in double, so the expected answer is decided
// exactly here; the crossing's value is the plane's certified t, bit for bit.
TYPED_TEST(RayPolyhedron, OnePlaneIsTheHalfSpace) {
    using T = TypeParam;
    static_assert(std::numeric_limits<long double>::digits >= 64, "the exact check needs a 64-bit significand");
    constexpr T inf = std::numeric_limits<T>::infinity();
    auto rng = make_rng();
    RAYPROOF_SEED_TRACE(base_seed());
    std::uniform_int_distribution<int> small(-6, 6), pick(0, 5);
    int entering = 0, leaving = 0, parallel = 0;
    for (int n = 0; n < 20000; ++n) {
        Plane<T> pl{Vec3<T>{T(small(rng)), T(small(rng)), T(small(rng))}, T(small(rng))};
        if (pl.normal.isZero()) pl.normal[2] = T(3);
        Ray<T> r{Vec3<T>{T(small(rng)), T(small(rng)), T(small(rng))}, Vec3<T>{T(small(rng)), T(small(rng)), T(small(rng))}};
        if (r.direction.isZero()) r.direction[1] = T(1);
        const int k = pick(rng);
        if (k == 0) r.direction = Vec3<T>(pl.normal[1], -pl.normal[0], T(0));  // parallel (or zero)
        if (r.direction.isZero()) r.direction[2] = T(1);
        if (k == 1) r.t_min = T(small(rng)), r.t_max = r.t_min + T(std::abs(small(rng)));
        if (k == 2) r.t_min = -inf;
        const std::vector<Plane<T>> p = {pl};
        const ConvexPolyhedron<T> c{p};
        SCOPED_TRACE(repro(r, p));
        double num = double(pl.offset), den = 0;
        for (int j = 0; j < 3; ++j) num -= double(pl.normal[j]) * double(r.origin[j]), den += double(pl.normal[j]) * double(r.direction[j]);
        // sign(t - x) for the crossing t = num/den and a finite x: sign(num - x·den)·sign(den),
        // exact in long double: x·den has at most 53 + 7 bits, and the rounded difference
        // keeps the sign of the exact one.
        const auto cross_vs = [&](T x) {
            const long double a = (long double)num - (long double)x * (long double)den;
            return ((a > 0) - (a < 0)) * ((den > 0) - (den < 0));
        };
        const Hit<T> got = intersect(r, c, certified);
        const Hit<T> plane = intersect(r, pl, certified);
        Hit<T> want;
        if (den == 0) {
            ++parallel;
            if (num >= 0) want = Hit<T>{Verdict::hit, r.t_min, r.t_max, -1};
        } else if (den < 0) {  // entering at t: [max(t, t_min), t_max]
            ++entering;
            const bool after_max = cross_vs(r.t_max) > 0;
            const bool after_min = std::isinf(r.t_min) || cross_vs(r.t_min) > 0;
            if (!after_max) want = after_min ? Hit<T>{Verdict::hit, plane.t_enter, r.t_max, 0} : Hit<T>{Verdict::hit, r.t_min, r.t_max, -1};
        } else {  // leaving at t: [t_min, min(t, t_max)]
            ++leaving;
            const bool before_min = !std::isinf(r.t_min) && cross_vs(r.t_min) < 0;
            const bool before_max = cross_vs(r.t_max) < 0;
            if (!before_min) want = before_max ? Hit<T>{Verdict::hit, r.t_min, plane.t_enter, -1} : Hit<T>{Verdict::hit, r.t_min, r.t_max, -1};
        }
        ASSERT_TRUE(same_hit(got, want));
        if (want.verdict == Verdict::hit && den != 0) {  // the crossing itself, judged exactly
            const T t = den < 0 ? got.t_enter : got.t_exit;
            if (t != r.t_min && t != r.t_max) {
                EXPECT_TRUE(is_faithful(t, [&](T x) { return -cross_vs(x); }));
            }
        }
        self_consistent(r, c);
        if (::testing::Test::HasFailure()) FAIL();
    }
    EXPECT_GT(entering, 2000);
    EXPECT_GT(leaving, 2000);
    EXPECT_GT(parallel, 1000);
}

// A ray leaving a half-space from outside it, its origin at distance delta from the
// plane and its direction pointing away (n·d > 0): exactly a miss. Conservative mode
// answers it so (it may err towards hit) once delta·|n| >= gamma(22)·S, S = |offset| +
// Σ|n_j o_j|: the bound the tracer's spawn offset takes for a conservative polyhedron
// (poly_leaving_margin in ray_polyhedron.hpp, which derives it). The directions graze the
// plane, n·d from half to forty times the bound on its computed value (gamma(5)·Σ|n_j
// d_j|): there the derived enclosure of the crossing alone, q ± 3(e_N + |q|·e_D)/|D|,
// reaches past 0 whatever delta is. The distances run from the bound to three times it;
// g = n·o - offset, S and the sign of n·d are judged exactly (BigDyadic).
TYPED_TEST(RayPolyhedron, ConservativeMissesAHalfSpaceLeftFromTheMargin) {
    using T = TypeParam;
    using BD = detail::BigDyadic;
    auto rng = make_rng();
    RAYPROOF_SEED_TRACE(base_seed());
    std::uniform_real_distribution<double> unit(-1, 1), expo(-6, 6), kappa(std::log(0.5), std::log(40.0)),
        spread(1, 3);
    const double margin = detail::poly_leaving_margin;
    const double g5 = detail::gamma<double>(5);
    int judged = 0, grazing = 0;
    for (int n = 0; n < 20000; ++n) {
        const auto vec = [&](double scale) {
            return Vec3<T>{T(unit(rng) * scale), T(unit(rng) * scale), T(unit(rng) * scale)};
        };
        Plane<T> pl{vec(std::exp2(std::round(expo(rng)))), T(unit(rng) * std::exp2(std::round(expo(rng))))};
        if (pl.normal.isZero()) continue;
        const Vec3<double> nd = pl.normal.template cast<double>();
        const double nn = nd.squaredNorm();
        // A point near the plane, a direction along it plus kappa times the bound on its
        // computed n·d towards n, and the origin moved off the plane along n.
        const Vec3<double> y = vec(std::exp2(std::round(expo(rng)))).template cast<double>();
        const Vec3<double> x = y - ((nd.dot(y) - double(pl.offset)) / nn) * nd;
        const Vec3<double> w = vec(1).template cast<double>();
        const Vec3<double> along{nd[1] * w[2] - nd[2] * w[1], nd[2] * w[0] - nd[0] * w[2], nd[0] * w[1] - nd[1] * w[0]};
        const double sd = std::abs(nd[0] * along[0]) + std::abs(nd[1] * along[1]) + std::abs(nd[2] * along[2]);
        const Vec3<T> d = (along + (std::exp(kappa(rng)) * g5 * sd / nn) * nd).template cast<T>();
        const double s_est = std::abs(double(pl.offset)) + std::abs(nd[0] * x[0]) + std::abs(nd[1] * x[1]) + std::abs(nd[2] * x[2]);
        const Vec3<T> o = (x + (spread(rng) * margin * s_est / nn) * nd).template cast<T>();
        BD g = BD(0.0) - BD(double(pl.offset)), S(std::abs(double(pl.offset))), den(0.0);
        for (int j = 0; j < 3; ++j) {
            const BD p = BD(double(pl.normal[j])) * BD(double(o[j]));
            g = g + p;
            S = S + BD(double(p.sign())) * p;
            den = den + BD(double(pl.normal[j])) * BD(double(d[j]));
        }
        if (den.sign() <= 0 || (g - BD(margin) * S).sign() < 0) continue;
        ++judged;
        double sdd = 0;  // Σ|n_j d_j|, for the count of grazing cases
        for (int j = 0; j < 3; ++j) sdd += std::abs(double(pl.normal[j]) * double(d[j]));
        grazing += std::abs(nd.dot(d.template cast<double>())) <= 40 * g5 * sdd;
        const std::vector<Plane<T>> p = {pl};
        const Ray<T> r{o, d};
        SCOPED_TRACE(repro(r, p));
        EXPECT_EQ(intersect(r, ConvexPolyhedron<T>{p}, conservative).verdict, Verdict::miss);
        EXPECT_EQ(intersect(r, ConvexPolyhedron<T>{p}, certified).verdict, Verdict::miss);
        if (::testing::Test::HasFailure()) FAIL();
    }
    // Float origins lie a float's spacing off the plane, on either side: about a quarter
    // of the cases are judged (5,061 with the default seed); double ones nearly all.
    EXPECT_GT(judged, (std::is_same_v<T, double> ? 15000 : 3000));
    if constexpr (std::is_same_v<T, double>) {
        EXPECT_GT(grazing, 2000);
    }
}

TYPED_TEST(RayPolyhedron, FlatSlabFromTwoOppositePlanes) {
    using T = TypeParam;
    // x <= 1 and -x <= -1: the plane x == 1 as a solid.
    const std::vector<Plane<T>> p = {{v<T>(1, 0, 0), T(1)}, {v<T>(-1, 0, 0), T(-1)}};
    const ConvexPolyhedron<T> c{p};
    check(Ray<T>{v<T>(-3, 0, 0), v<T>(2, 0, 0)}, c, hit<T>(2, 2, 1));
    check(Ray<T>{v<T>(5, 0, 0), v<T>(-2, 1, 0)}, c, hit<T>(2, 2, 0));
    check(Ray<T>{v<T>(1, 0, 0), v<T>(0, 1, 0)}, c, hit<T>(0, std::numeric_limits<T>::infinity(), -1));  // lies in it
    check(Ray<T>{v<T>(1, 0, 0), v<T>(1, 0, 0)}, c, hit<T>(0, 0, -1));    // leaves at once
    check(Ray<T>{v<T>(1.5, 0, 0), v<T>(0, 1, 0)}, c, miss<T>());
    check(Ray<T>{v<T>(-3, 0, 0), v<T>(2, 0, 0), 0, 1}, c, miss<T>());
    // A non-axis flat slab: x + y == 3, crossings at t = 1/3 (not representable).
    const std::vector<Plane<T>> q = {{v<T>(-1, -1, 0), T(-3)}, {v<T>(1, 1, 0), T(3)}};
    const ConvexPolyhedron<T> cq{q};
    const Ray<T> r{v<T>(0, 0, 0), v<T>(6, 3, 0)};
    const Hit<T> h = intersect(r, cq, certified);
    ASSERT_EQ(h.verdict, Verdict::hit) << h;
    EXPECT_TRUE(same_bits(h.t_enter, h.t_exit)) << h;
    EXPECT_EQ(h.face, 0) << h;
    EXPECT_TRUE(is_faithful(h.t_enter, [](T x) { return int(3 * double(x) > 1) - int(3 * double(x) < 1); })) << h;
    self_consistent(r, cq);
}

TYPED_TEST(RayPolyhedron, InvalidInputs) {
    using T = TypeParam;
    constexpr T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
    const Ray<T> r{v<T>(-4, 0, 0), v<T>(1, 0, 0)};
    const Plane<T> good{v<T>(1, 0, 0), T(1)};
    for (const Plane<T>& bad : {Plane<T>{v<T>(0, 0, 0), T(1)}, Plane<T>{v<T>(-0.0, 0, -0.0), T(0)},
                                Plane<T>{v<T>(1, 0, 0), nan}, Plane<T>{v<T>(1, 0, 0), inf},
                                Plane<T>{v<T>(1, inf, 0), T(1)}, Plane<T>{v<T>(nan, 0, 1), T(1)}}) {
        // Every mode's pass stops at the first plane that proves a miss (aside: parallel
        // and outside; behind: an exit before the entry) and vouches for the planes after
        // it by the rules: an invalid plane there is still found (check() runs fast,
        // conservative and certified).
        const Plane<T> aside{v<T>(0, 1, 0), T(-1)}, behind{v<T>(1, 0, 0), T(-5)};
        for (const std::vector<Plane<T>>& p :
             {std::vector<Plane<T>>{bad}, std::vector<Plane<T>>{good, bad}, std::vector<Plane<T>>{bad, good, good},
              std::vector<Plane<T>>{aside, bad}, std::vector<Plane<T>>{good, behind, good, bad}}) {
            const ConvexPolyhedron<T> c{p};
            check(r, c, invalid<T>());
            EXPECT_EQ(verdict(r, c, certified), Verdict::invalid);
            EXPECT_EQ(verdict(r, c, fast), Verdict::invalid);
        }
    }
    // A valid plane whose num overflows (offset - n·o = +inf): the pass's finiteness
    // probe fails, and the rules, not the probe, decide: valid, so no mode answers invalid.
    {
        constexpr T big = std::numeric_limits<T>::max();
        const std::vector<Plane<T>> p = {Plane<T>{v<T>(big, 0, 0), T(0)}, good};
        const ConvexPolyhedron<T> c{p};
        EXPECT_NE(intersect(r, c, fast).verdict, Verdict::invalid);
        EXPECT_NE(verdict(r, c, fast), Verdict::invalid);
        EXPECT_NE(intersect(r, c, conservative).verdict, Verdict::invalid);
        EXPECT_NE(intersect(r, c, certified).verdict, Verdict::invalid);
        EXPECT_NE(verdict(r, c, certified), Verdict::invalid);
    }
    // The ray's own classes, against a valid polyhedron and against no planes.
    const std::vector<Plane<T>> p = {good};
    for (const ConvexPolyhedron<T>& c : {ConvexPolyhedron<T>{p}, ConvexPolyhedron<T>{}}) {
        check(Ray<T>{v<T>(-4, 0, 0), v<T>(0, 0, 0)}, c, invalid<T>());
        check(Ray<T>{v<T>(-4, nan, 0), v<T>(1, 0, 0)}, c, invalid<T>());
        check(Ray<T>{v<T>(-4, 0, 0), v<T>(1, inf, 0)}, c, invalid<T>());
        check(Ray<T>{v<T>(-4, 0, 0), v<T>(1, 0, 0), 2, 1}, c, invalid<T>());
        check(Ray<T>{v<T>(-4, 0, 0), v<T>(1, 0, 0), nan, 1}, c, invalid<T>());
        check(Ray<T>{v<T>(-4, 0, 0), v<T>(1, 0, 0), inf, inf}, c, invalid<T>());
    }
}

TYPED_TEST(RayPolyhedron, BatchEqualsScalar) {
    using T = TypeParam;
    auto rng = make_rng();
    RAYPROOF_SEED_TRACE(base_seed());
    std::uniform_real_distribution<double> unit(-1, 1);
    // A random polyhedron of 20 planes around the origin, and the hard scenes' rays.
    std::vector<Plane<T>> p;
    for (int k = 0; k < 20; ++k) p.push_back({Vec3<T>{T(unit(rng)), T(unit(rng)), T(unit(rng))}, T(2 + unit(rng))});
    const ConvexPolyhedron<T> c{p};
    std::vector<Ray<T>> rays;
    for (int n = 0; n < 3000; ++n) rays.push_back(hard_scene<T>(rng).ray);
    rays.push_back(Ray<T>{v<T>(0, 0, 0), v<T>(0, 0, 0)});  // invalid
    std::vector<Hit<T>> out(rays.size());
    std::vector<Verdict> vout(rays.size());
    intersect(std::span<const Ray<T>>(rays), c, certified, std::span<Hit<T>>(out));
    verdict(std::span<const Ray<T>>(rays), c, certified, std::span<Verdict>(vout));
    int hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit<T> h = intersect(rays[i], c, certified);
        ASSERT_TRUE(same_hit(out[i], h)) << i << ": " << repro(rays[i], p);
        ASSERT_EQ(vout[i], h.verdict) << i << ": " << repro(rays[i], p);
        hits += h.verdict == Verdict::hit;
        self_consistent(rays[i], c);
        if (::testing::Test::HasFailure()) FAIL() << i << ": " << repro(rays[i], p);
    }
    EXPECT_GT(hits, 100);
    intersect(std::span<const Ray<T>>(rays), c, conservative, std::span<Hit<T>>(out));
    for (std::size_t i = 0; i < rays.size(); ++i) EXPECT_EQ(out[i].verdict, intersect(rays[i], c, conservative).verdict);
    std::vector<Hit<T>> short_out(1);
    EXPECT_THROW(intersect(std::span<const Ray<T>>(rays), c, certified, std::span<Hit<T>>(short_out)), std::invalid_argument);
}

namespace {
template <class T>
[[gnu::noinline]] void answers(const std::vector<Ray<T>>& rays, const ConvexPolyhedron<T>& c, std::vector<Hit<T>>& out) {
    out.clear();
    for (const Ray<T>& r : rays) {
        out.push_back(intersect(r, c, certified));
        out.push_back(intersect(r, c, conservative));
    }
}
}  // namespace

TYPED_TEST(RayPolyhedron, DirectedRoundingChangesNothing) {
    using T = TypeParam;
    auto rng = make_rng();
    RAYPROOF_SEED_TRACE(base_seed());
    std::uniform_real_distribution<double> unit(-1, 1);
    std::vector<Plane<T>> p;
    for (int k = 0; k < 12; ++k) p.push_back({Vec3<T>{T(unit(rng)), T(unit(rng)), T(unit(rng))}, T(2 + unit(rng))});
    const ConvexPolyhedron<T> c{p};
    std::vector<Ray<T>> rays;
    for (int n = 0; n < 2000; ++n) rays.push_back(hard_scene<T>(rng).ray);
    std::vector<Hit<T>> want, got;
    answers(rays, c, want);
    int hits = 0;
    for (const Hit<T>& h : want) hits += h.verdict == Verdict::hit;
    EXPECT_GT(hits, 200);
    for (const int mode : {FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO}) {
        ASSERT_EQ(std::fesetround(mode), 0);
        answers(rays, c, got);
        ASSERT_EQ(std::fesetround(FE_TONEAREST), 0);
        ASSERT_EQ(got.size(), want.size());
        for (std::size_t i = 0; i < want.size(); ++i)
            ASSERT_TRUE(same_hit(got[i], want[i])) << "rounding mode " << mode << ", " << repro(rays[i / 2], p);
    }
}
