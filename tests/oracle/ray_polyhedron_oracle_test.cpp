// ray_polyhedron_oracle_test.cpp — the oracle's ray/ConvexPolyhedron answers:
// hand-computed rational intervals and faces (a cube and a tetrahedron made of planes,
// the lowest-index tie rule at edges and vertices and between duplicate and coincident
// planes, face -1 when t_min is in the solid), rays parallel to a plane with ±0
// components on and off it, a flat slab of two opposite planes, no planes, infeasible
// and unbounded sets, denormal and 2^±1000 scales, every invalid class, and the contract
// checker's face range; then agreement with an independent exact computation: two
// linear programs (the least and the greatest t of the solid's points on the range)
// solved by CGAL's exact simplex over Gmpq (crosscheck::answer), over the cases of every
// polyhedron generator, with the kernel's conservative and certified modes judged by
// CGAL's answer where the kernel provides them.
#include "oracle_test_support.hpp"

#include <rayproof/generators/ray_polyhedron.hpp>
#include <rayproof/oracle/contract.hpp>

#include <vector>

namespace {

using namespace rayproof;
using namespace rayproof::oracle_test;

template <class T> class PolyhedronOracle : public ::testing::Test {};
TYPED_TEST_SUITE(PolyhedronOracle, Scalars, ScalarNames);

template <class T> Plane<T> pl(T nx, T ny, T nz, T off) { return Plane<T>{Vec3<T>(nx, ny, nz), off}; }

// The unit cube [0, 1]³ as six planes, in box-face order: -x <= 0, x <= 1, -y <= 0,
// y <= 1, -z <= 0, z <= 1 (so face k here is the Aabb's face k).
template <class T> std::vector<Plane<T>> unit_cube() {
    return {pl<T>(-1, 0, 0, 0), pl<T>(1, 0, 0, 1), pl<T>(0, -1, 0, 0),
            pl<T>(0, 1, 0, 1),  pl<T>(0, 0, -1, 0), pl<T>(0, 0, 1, 1)};
}
template <class T> ConvexPolyhedron<T> view(const std::vector<Plane<T>>& p) { return ConvexPolyhedron<T>{p}; }

TYPED_TEST(PolyhedronOracle, CubeThroughTheMiddleAndTheAabbsAnswers) {
    using T = TypeParam;
    const auto cube = unit_cube<T>();
    const auto c = view(cube);
    expect_answer(oracle::exact(Ray<T>{{-1, T(0.5), T(0.5)}, {1, 0, 0}}, c), "1", "2", 0);
    expect_answer(oracle::exact(Ray<T>{{2, T(0.5), T(0.5)}, {-1, 0, 0}}, c), "1", "2", 1);
    expect_answer(oracle::exact(Ray<T>{{T(0.5), -2, T(0.5)}, {0, 3, 0}}, c), "2/3", "1", 2);
    expect_answer(oracle::exact(Ray<T>{{T(0.5), T(0.5), 5}, {0, 0, -4}}, c), "1", "5/4", 5);
    // The cube as planes answers what the Aabb answers, face for face.
    const Aabb<T> box{{0, 0, 0}, {1, 1, 1}};
    for (const Ray<T>& r : {Ray<T>{{-1, -1, -1}, {1, 1, 1}}, Ray<T>{{T(0.5), -1, 2}, {0, 1, -1}},
                            Ray<T>{{0, 2, T(0.5)}, {1, -1, 0}}, Ray<T>{{T(0.25), T(0.5), T(0.75)}, {-1, 2, 3}, -inf<T>()}}) {
        const auto a = oracle::exact(r, box), p = oracle::exact(r, c);
        EXPECT_EQ(a.verdict, p.verdict) << r;
        EXPECT_TRUE(a.t_enter == p.t_enter && a.t_exit == p.t_exit) << r << ": " << a << " vs " << p;
        EXPECT_EQ(a.face, p.face) << r;
    }
}

TYPED_TEST(PolyhedronOracle, OriginInsideAndTMinAtTheEntryGiveFaceMinusOne) {
    using T = TypeParam;
    const auto cube = unit_cube<T>();
    const auto c = view(cube);
    expect_answer(oracle::exact(Ray<T>{{T(0.5), T(0.5), T(0.5)}, {1, 0, 0}}, c), "0", "1/2", -1);
    expect_answer(oracle::exact(Ray<T>{{-1, T(0.5), T(0.5)}, {1, 0, 0}, 1}, c), "1", "2", -1);  // t_min at the entry
    expect_answer(oracle::exact(Ray<T>{{-1, T(0.5), T(0.5)}, {1, 0, 0}, T(1.5)}, c), "3/2", "2", -1);
    // The whole line: the entry is behind the origin, through plane 0.
    expect_answer(oracle::exact(Ray<T>{{T(0.5), T(0.5), T(0.5)}, {1, 0, 0}, -inf<T>(), inf<T>()}, c), "-1/2", "1/2", 0);
    // The origin on a face, leaving: a single point [0, 0].
    expect_answer(oracle::exact(Ray<T>{{1, T(0.5), T(0.5)}, {1, 0, 0}}, c), "0", "0", -1);
}

TYPED_TEST(PolyhedronOracle, TiesGoToTheLowestIndexDuplicatesIncluded) {
    using T = TypeParam;
    auto cube = unit_cube<T>();
    const Ray<T> corner{{-1, -1, -1}, {1, 1, 1}};  // enters through planes 0, 2 and 4 at t = 1
    expect_answer(oracle::exact(corner, view(cube)), "1", "2", 0);
    // The same planes listed z first: the lowest index is now the z plane's.
    std::vector<Plane<T>> zfirst = {cube[4], cube[5], cube[2], cube[3], cube[0], cube[1]};
    expect_answer(oracle::exact(corner, view(zfirst)), "1", "2", 0);
    std::vector<Plane<T>> yfirst = {cube[1], cube[3], cube[2], cube[0], cube[5], cube[4]};
    expect_answer(oracle::exact(corner, view(yfirst)), "1", "2", 2);
    // A duplicate of plane 0 appended: plane 0 keeps the face; the same plane put first
    // as a duplicate takes it (index 0), and a coincident multiple (normal scaled by 4)
    // at index 0 takes it as well.
    auto dup = cube;
    dup.push_back(cube[0]);
    expect_answer(oracle::exact(Ray<T>{{-1, T(0.5), T(0.5)}, {1, 0, 0}}, view(dup)), "1", "2", 0);
    std::vector<Plane<T>> dup_first = {cube[1], cube[0], cube[2], cube[3], cube[4], cube[5], cube[0]};
    expect_answer(oracle::exact(Ray<T>{{-1, T(0.5), T(0.5)}, {1, 0, 0}}, view(dup_first)), "1", "2", 1);
    std::vector<Plane<T>> coincident = {pl<T>(-4, 0, 0, 0)};
    coincident.insert(coincident.end(), cube.begin(), cube.end());
    expect_answer(oracle::exact(Ray<T>{{-1, T(0.5), T(0.5)}, {1, 0, 0}}, view(coincident)), "1", "2", 0);
    // Along an edge of the tetrahedron x, y, z >= 0, x + y + z <= 1: the ray on the x
    // axis lies in planes 1 and 2 (parallel, on them) and enters through plane 3.
    const std::vector<Plane<T>> tet = {pl<T>(-1, 0, 0, 0), pl<T>(0, -1, 0, 0), pl<T>(0, 0, -1, 0), pl<T>(1, 1, 1, 1)};
    for (const T z : {T(0), -T(0)})
        expect_answer(oracle::exact(Ray<T>{{2, 0, 0}, {-1, z, z}}, view(tet)), "1", "2", 3);
    // Through the vertex (0, 0, 1) from above: planes 0, 1 and 3 meet there; the ray
    // (-1, -1, -1)·t from (1, 1, 2) enters through plane 3 at t = 1 ... and exactly at
    // that point it also reaches x = 0 and y = 0 (exits): a single point.
    expect_answer(oracle::exact(Ray<T>{{1, 1, 2}, {-1, -1, -1}}, view(tet)), "1", "1", 3);
}

TYPED_TEST(PolyhedronOracle, ParallelRaysWithSignedZeros) {
    using T = TypeParam;
    const auto cube = unit_cube<T>();
    const auto c = view(cube);
    for (const T z : {T(0), -T(0)}) {
        EXPECT_EQ(oracle::exact(Ray<T>{{-1, 2, T(0.5)}, {1, z, 0}}, c).verdict, Verdict::miss);
        expect_answer(oracle::exact(Ray<T>{{-1, 1, T(0.5)}, {1, z, z}}, c), "1", "2", 0);  // in the plane y = 1
        expect_answer(oracle::exact(Ray<T>{{-1, 0, 0}, {1, z, z}}, c), "1", "2", 0);        // along an edge
        expect_answer(oracle::exact(Ray<T>{{T(0.5), 0, 1}, {z, z, -2}}, c), "0", "1/2", -1);
        // One ulp outside the plane y = 1, parallel: a miss.
        EXPECT_EQ(oracle::exact(Ray<T>{{-1, std::nextafter(T(1), T(2)), T(0.5)}, {1, z, z}}, c).verdict, Verdict::miss);
    }
}

TYPED_TEST(PolyhedronOracle, FlatSlabNoPlanesInfeasibleAndUnbounded) {
    using T = TypeParam;
    // x <= 1 and -x <= -1: the plane x = 1 as a flat solid.
    const std::vector<Plane<T>> slab = {pl<T>(1, 0, 0, 1), pl<T>(-1, 0, 0, -1)};
    expect_answer(oracle::exact(Ray<T>{{0, 5, 7}, {2, 1, 1}}, view(slab)), "1/2", "1/2", 1);
    expect_answer(oracle::exact(Ray<T>{{3, 5, 7}, {-2, 1, 1}}, view(slab)), "1", "1", 0);
    expect_answer(oracle::exact(Ray<T>{{1, 5, 7}, {0, 1, -1}}, view(slab)), "0", "+inf", -1);  // lying in it
    expect_answer(oracle::exact(Ray<T>{{1, 5, 7}, {-T(0), 1, -1}, -inf<T>()}, view(slab)), "-inf", "+inf", -1);
    EXPECT_EQ(oracle::exact(Ray<T>{{std::nextafter(T(1), T(0)), 5, 7}, {0, 1, -1}}, view(slab)).verdict, Verdict::miss);
    // No planes: all of space, the whole range.
    const std::vector<Plane<T>> none;
    expect_answer(oracle::exact(Ray<T>{{1, 2, 3}, {0, 0, 1}}, view(none)), "0", "+inf", -1);
    expect_answer(oracle::exact(Ray<T>{{1, 2, 3}, {0, 0, 1}, -inf<T>()}, view(none)), "-inf", "+inf", -1);
    expect_answer(oracle::exact(Ray<T>{{1, 2, 3}, {0, 0, 1}, -2, T(0.5)}, view(none)), "-2", "1/2", -1);
    // Infeasible: x <= 0 and x >= 1 (and a third plane): every ray misses, whatever its
    // direction, range or position.
    const std::vector<Plane<T>> empty = {pl<T>(1, 0, 0, 0), pl<T>(0, 1, 0, 5), pl<T>(-1, 0, 0, -1)};
    for (const Ray<T>& r : {Ray<T>{{0, 0, 0}, {1, 0, 0}, -inf<T>()}, Ray<T>{{1, 0, 0}, {0, 1, 0}, -inf<T>()},
                            Ray<T>{{T(0.5), 0, 0}, {0, 0, 1}, -inf<T>()}, Ray<T>{{-3, 1, 2}, {1, 2, 3}, -inf<T>()}})
        EXPECT_EQ(oracle::exact(r, view(empty)).verdict, Verdict::miss) << r;
    // Unbounded: the half space z <= 0, and the wedge z <= 0, y <= 0.
    const std::vector<Plane<T>> half = {pl<T>(0, 0, 1, 0)};
    expect_answer(oracle::exact(Ray<T>{{0, 0, 2}, {0, 1, -2}}, view(half)), "1", "+inf", 0);
    expect_answer(oracle::exact(Ray<T>{{0, 0, -2}, {0, 1, 2}}, view(half)), "0", "1", -1);
    expect_answer(oracle::exact(Ray<T>{{0, 0, -2}, {0, 1, 2}, -inf<T>()}, view(half)), "-inf", "1", -1);
    const std::vector<Plane<T>> wedge = {pl<T>(0, 0, 1, 0), pl<T>(0, 1, 0, 0)};
    expect_answer(oracle::exact(Ray<T>{{5, 3, 1}, {0, -1, -1}}, view(wedge)), "3", "+inf", 1);
    expect_answer(oracle::exact(Ray<T>{{5, 1, 3}, {0, -1, -1}}, view(wedge)), "3", "+inf", 0);
}

TYPED_TEST(PolyhedronOracle, ExtremeScales) {
    using T = TypeParam;
    using L = std::numeric_limits<T>;
    // The cube scaled to denormals: offsets m, normals ±1.
    const T m = L::denorm_min();
    const std::vector<Plane<T>> tiny = {pl<T>(-1, 0, 0, -2 * m), pl<T>(1, 0, 0, 4 * m), pl<T>(0, -1, 0, 0),
                                        pl<T>(0, 1, 0, m),       pl<T>(0, 0, -1, 0),    pl<T>(0, 0, 1, m)};
    expect_answer(oracle::exact(Ray<T>{{0, 0, 0}, {3 * m, 0, 0}}, view(tiny)), "2/3", "4/3", 0);
    // Normals of magnitude 2^e and offsets 2^(2e): the planes x = ±2^e, e near the top of
    // the range (the products n·o and the offsets near the overflow threshold).
    const int e = L::max_exponent / 2 - 1;
    const T a = std::ldexp(T(1), e), a2 = std::ldexp(T(1), 2 * e);
    const std::vector<Plane<T>> big = {pl<T>(-a, 0, 0, a2), pl<T>(a, 0, 0, a2)};
    expect_answer(oracle::exact(Ray<T>{{-2 * a, 0, 0}, {a, 1, 1}}, view(big)), "1", "3", 0);
    if constexpr (std::is_same_v<T, double>) {
        // 2^±1000: the slab 2^1000 <= x <= 2^1001 crossed from the origin along 2^-1000:
        // t = 2^2000 and 2^2001, beyond the double range (brackets [max, inf]); along
        // 2^-20, t = 2^1020 and 2^1021 exactly.
        const T p = std::ldexp(T(1), 1000), q = std::ldexp(T(1), -1000);
        const std::vector<Plane<T>> far = {pl<T>(-1, 0, 0, -p), pl<T>(1, 0, 0, 2 * p)};
        const auto x = oracle::exact(Ray<T>{{0, 0, 0}, {q, q, q}}, view(far));
        ASSERT_EQ(x.verdict, Verdict::hit);
        EXPECT_EQ(x.face, 0);
        EXPECT_EQ(x.enter_bracket().lo, L::max());
        EXPECT_EQ(x.enter_bracket().hi, inf<T>());
        EXPECT_EQ(x.exit_bracket().lo, L::max());
        const auto y = oracle::exact(Ray<T>{{0, 0, 0}, {std::ldexp(T(1), -20), 0, 0}}, view(far));
        ASSERT_EQ(y.verdict, Verdict::hit);
        EXPECT_EQ(y.face, 0);
        EXPECT_TRUE(y.enter_bracket().representable());
        EXPECT_EQ(y.enter_bracket().lo, std::ldexp(T(1), 1020));
        EXPECT_EQ(y.exit_bracket().lo, std::ldexp(T(1), 1021));
    }
}

TYPED_TEST(PolyhedronOracle, EveryInvalidClass) {
    using T = TypeParam;
    const auto cube = unit_cube<T>();
    const Ray<T> r{{-1, T(0.5), T(0.5)}, {1, 0, 0}};
    expect_invalid_ray_classes(r, view(cube));
    EXPECT_TRUE(oracle::valid(view(cube)));
    const auto broken = [&](auto edit) {
        auto p = cube;
        edit(p);
        EXPECT_FALSE(oracle::valid(view(p)));
        return oracle::exact(r, view(p)).verdict;
    };
    EXPECT_EQ(broken([](auto& p) { p[3].normal = Vec3<T>(0, -T(0), 0); }), Verdict::invalid);
    EXPECT_EQ(broken([](auto& p) { p[5].normal[2] = nan<T>(); }), Verdict::invalid);
    EXPECT_EQ(broken([](auto& p) { p[0].normal[1] = -inf<T>(); }), Verdict::invalid);
    EXPECT_EQ(broken([](auto& p) { p[2].offset = inf<T>(); }), Verdict::invalid);
    EXPECT_EQ(broken([](auto& p) { p[1].offset = nan<T>(); }), Verdict::invalid);
    // An invalid plane that the ray would never reach still makes the input invalid, and
    // so does one after an infeasible pair (no early miss before validation).
    EXPECT_EQ(broken([](auto& p) { p.push_back(pl<T>(0, 0, 0, 1)); }), Verdict::invalid);
    EXPECT_EQ(broken([](auto& p) {
                  p.insert(p.begin(), {pl<T>(1, 0, 0, 0), pl<T>(-1, 0, 0, -1)});
                  p.push_back(pl<T>(nan<T>(), 0, 1, 1));
              }),
              Verdict::invalid);
    // Valid edge values: -0 in normals and offsets, t_min = -inf, t_max = +inf, t_min == t_max.
    const std::vector<Plane<T>> signed_zeros = {pl<T>(-T(0), -1, 0, -T(0))};
    EXPECT_NE(oracle::exact(Ray<T>{r.origin, r.direction, -inf<T>(), inf<T>()}, view(signed_zeros)).verdict,
              Verdict::invalid);
    EXPECT_NE(oracle::exact(Ray<T>{r.origin, r.direction, 3, 3}, view(cube)).verdict, Verdict::invalid);
}

TYPED_TEST(PolyhedronOracle, ContractCheckerBoundsTheFaceByThePlaneCount) {
    using T = TypeParam;
    const auto cube = unit_cube<T>();
    const auto c = view(cube);
    const Ray<T> r{{-1, T(0.5), T(0.5)}, {1, 0, 0}};
    const auto e = oracle::exact(r, c);
    const auto with_face = [](int f) { return Hit<T>{Verdict::hit, 1, 2, f}; };
    EXPECT_TRUE(oracle::check_contract(r, c, with_face(0), e, certified).ok());
    for (const auto& check : {oracle::check_contract(r, c, with_face(6), e, conservative),
                              oracle::check_contract(r, c, with_face(-2), e, conservative)})
        EXPECT_TRUE(check.has(oracle::Breach::face_out_of_range)) << check.judgement;
    // Face 5 is in range but wrong: certified breaks exactness, conservative does not.
    EXPECT_TRUE(oracle::check_contract(r, c, with_face(5), e, certified).has(oracle::Breach::not_exact));
    EXPECT_TRUE(oracle::check_contract(r, c, with_face(5), e, conservative).ok());
    // No planes: only -1.
    const std::vector<Plane<T>> none;
    const auto en = oracle::exact(r, view(none));
    EXPECT_TRUE(oracle::check_contract(r, view(none), Hit<T>{Verdict::hit, 0, inf<T>(), -1}, en, certified).ok());
    EXPECT_TRUE(oracle::check_contract(r, view(none), Hit<T>{Verdict::hit, 0, inf<T>(), 0}, en, certified)
                    .has(oracle::Breach::face_out_of_range));
}

// One input judged against CGAL's linear programs x (crosscheck::answer): the oracle's
// verdict, exact t_enter and t_exit and face must equal x's, and its faithful brackets
// enclose x's values by CGAL's comparisons; where the kernel answers, certified must be
// x's verdict and face with each t faithful to x's, and conservative a hit enclosing x's
// interval wherever x hits. Returns what disagrees, empty when nothing does.
struct PolyCoverage {
    int checked = 0, hits = 0, faces = 0, unbounded = 0, failures = 0;
};
template <class T> std::string poly_disagreement(const Ray<T>& ray, const ConvexPolyhedron<T>& poly, PolyCoverage& cov) {
    std::ostringstream why;
    const auto e = oracle::exact(ray, poly);
    const auto x = oracle::crosscheck::answer(ray, poly);
    ++cov.checked;
    cov.hits += x.verdict == Verdict::hit;
    cov.faces += x.verdict == Verdict::hit && x.face >= 0;
    cov.unbounded += x.verdict == Verdict::hit && (x.t_enter.kind() == oracle::ExactValue::Kind::minus_infinity ||
                                                   x.t_exit.kind() == oracle::ExactValue::Kind::plus_infinity);
    if (x.verdict != e.verdict) why << "verdicts: oracle " << e << " vs CGAL " << x << "; ";
    if (x.verdict == Verdict::hit && e.verdict == Verdict::hit) {
        if (!(x.t_enter == e.t_enter) || !(x.t_exit == e.t_exit) || x.face != e.face)
            why << "answers: oracle " << e << " vs CGAL " << x << "; ";
        const auto be = e.enter_bracket(), bx = e.exit_bracket();
        for (const T b : {be.lo, be.hi})
            if (const auto r = rayproof::testing::is_faithful(b, minus_cgal<T>(x.t_enter)); !r)
                why << "oracle's enter bracket: " << r.message() << "; ";
        for (const T b : {bx.lo, bx.hi})
            if (const auto r = rayproof::testing::is_faithful(b, minus_cgal<T>(x.t_exit)); !r)
                why << "oracle's exit bracket: " << r.message() << "; ";
    }
    if constexpr (Answerable<T, ConvexPolyhedron<T>, certified_t>) {
        const Hit<T> h = intersect(ray, poly, certified);
        if (h.verdict != x.verdict) {
            why << "certified verdict " << h << " vs CGAL " << x << "; ";
        } else if (h.verdict == Verdict::hit) {
            if (const auto r = rayproof::testing::is_faithful(h.t_enter, minus_cgal<T>(x.t_enter)); !r)
                why << "certified t_enter: " << r.message() << "; ";
            if (const auto r = rayproof::testing::is_faithful(h.t_exit, minus_cgal<T>(x.t_exit)); !r)
                why << "certified t_exit: " << r.message() << "; ";
            if (h.face != x.face) why << "certified face " << h.face << " vs CGAL " << x.face << "; ";
            if (why.tellp() > 0) why << "certified " << h << " CGAL " << x << "; ";
        }
    }
    if constexpr (Answerable<T, ConvexPolyhedron<T>, conservative_t>) {
        const Hit<T> hc = intersect(ray, poly, conservative);
        if ((hc.verdict == Verdict::invalid) != (x.verdict == Verdict::invalid)) {
            why << "conservative " << hc << " vs CGAL " << x << "; ";
        } else if (x.verdict == Verdict::hit) {
            if (hc.verdict != Verdict::hit || !(minus_cgal<T>(x.t_enter)(hc.t_enter) <= 0) ||
                !(minus_cgal<T>(x.t_exit)(hc.t_exit) == 0 || minus_cgal<T>(x.t_exit)(hc.t_exit) == 1))
                why << "conservative " << hc << " does not enclose CGAL's " << x << "; ";
        }
    }
    return why.str();
}

TYPED_TEST(PolyhedronOracle, AgreesWithCgalLinearProgramsOnTheHandCases) {
    using T = TypeParam;
    const auto cube = unit_cube<T>();
    const std::vector<Plane<T>> tet = {pl<T>(-1, 0, 0, 0), pl<T>(0, -1, 0, 0), pl<T>(0, 0, -1, 0), pl<T>(1, 1, 1, 1)};
    const std::vector<Plane<T>> slab = {pl<T>(1, 0, 0, 1), pl<T>(-1, 0, 0, -1)};
    const std::vector<Plane<T>> half = {pl<T>(0, 0, 1, 0)}, none;
    const std::vector<Plane<T>> empty = {pl<T>(1, 0, 0, 0), pl<T>(-1, 0, 0, -1)};
    PolyCoverage cov;
    for (const auto* planes : {&cube, &tet, &slab, &half, &none, &empty})
        for (const Ray<T>& r :
             {Ray<T>{{-1, T(0.5), T(0.5)}, {1, 0, 0}}, Ray<T>{{-1, -1, -1}, {1, 1, 1}}, Ray<T>{{2, 0, 0}, {-1, 0, -T(0)}},
              Ray<T>{{1, 1, 2}, {-1, -1, -1}}, Ray<T>{{1, 5, 7}, {0, 1, -1}, -inf<T>()},
              Ray<T>{{T(0.25), T(0.25), T(0.25)}, {3, -1, 2}, -inf<T>()}, Ray<T>{{0, 0, 2}, {0, 1, -2}, -4, 9}}) {
            const std::string why = poly_disagreement(r, view(*planes), cov);
            EXPECT_TRUE(why.empty()) << why << "\n  ray " << r << ", " << planes->size() << " planes";
        }
    EXPECT_GT(cov.hits, 10);
    EXPECT_GT(cov.faces, 5);
    EXPECT_GT(cov.unbounded, 3);
}

// Every polyhedron generator: the oracle (and the kernel where it answers) against CGAL's
// linear programs.
TYPED_TEST(PolyhedronOracle, AgreesWithCgalLinearProgramsOnEveryGenerator) {
    using T = TypeParam;
    constexpr int kCases = 150;
    for (const auto& g : gen::polyhedron_generators<T>()) {
        gen::Rng rng(0x0bac1e ^ gen::name_hash(g.name));
        PolyCoverage cov;
        int invalid = 0;
        std::size_t most_planes = 0;
        for (int i = 0; i < kCases; ++i) {
            const gen::PolyCase<T> c = g.make(rng);
            invalid += !oracle::valid(c.ray) || !oracle::valid(c.shape.view());
            most_planes = std::max(most_planes, c.shape.planes.size());
            const std::string why = poly_disagreement(c.ray, c.shape.view(), cov);
            if (!why.empty() && ++cov.failures <= 5)
                ADD_FAILURE() << g.name << " case " << i << ": " << why << "\n  " << c;
        }
        EXPECT_EQ(cov.failures, 0) << g.name;
        // Each generator delivers what its name says.
        EXPECT_EQ(invalid, g.name == "invalid" ? kCases : 0) << g.name;
        EXPECT_LE(most_planes, 64u) << g.name;
        if (g.name == "infeasible") {
            EXPECT_EQ(cov.hits, 0) << "an infeasible solid was hit";
        }
        if (g.name == "many_planes") {
            EXPECT_GE(most_planes, 40u) << "many_planes made no case of 40 planes or more";
        }
        if (g.name != "invalid" && g.name != "infeasible") {
            EXPECT_GT(cov.hits, kCases / 10) << g.name << ": too few hits cross-checked";
        }
        std::cout << g.name << ": " << cov.checked << " cases, " << cov.hits << " hits, " << cov.faces
                  << " with an entry face, " << cov.unbounded << " with an infinite end, up to " << most_planes
                  << " planes\n";
    }
}

}  // namespace
