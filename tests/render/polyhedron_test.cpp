// Convex polyhedra in scenes: both forms and the presets parse into the planes they
// say; the exact hull (every point on or inside every stored plane, decided exactly;
// every extreme point on at least three planes; facet counts by Euler's formula for
// seeded random points); an inexact hull contains its points; the bounding sphere holds
// every point exactly; the errors name the object and its place in the text; the
// pre-filter changes no pixel; a polyhedron of a box's planes renders as the box
// (certified mode, opaque, mirror and glass); the POV-Ray text.
#include "render_support.hpp"

#include <rayproof/detail/exact.hpp>
#include <rayproof/render/polyhedron.hpp>
#include <rayproof/render/pov.hpp>

#include <random>
#include <sstream>

namespace rayproof::render::testing {
namespace {

using E = rayproof::detail::BigDyadic;  // exact for every double input up to degree 7

// sign(n·p - offset), exact.
int side(const Plane<double>& q, const Vec3d& p) {
    const E v = E(q.normal[0]) * E(p[0]) + E(q.normal[1]) * E(p[1]) + E(q.normal[2]) * E(p[2]) - E(q.offset);
    return v.sign();
}

// The hull's properties, exactly: every point on or inside every plane, every plane
// through at least 3 points; returns how many points are on at least 3 planes (the
// extreme ones; checked to be all points that lie on any plane's corner).
int check_hull(const std::vector<Plane<double>>& planes, const std::vector<Vec3d>& pts, bool exact = true) {
    int vertices = 0;
    for (std::size_t k = 0; k < planes.size(); ++k) {
        int on = 0;
        for (const Vec3d& p : pts) {
            const int s = side(planes[k], p);
            EXPECT_LE(s, 0) << "plane " << k << " has a point outside";
            on += s == 0;
        }
        if (exact) {
            EXPECT_GE(on, 3) << "plane " << k << " holds fewer than 3 points";
        }
    }
    for (const Vec3d& p : pts) {
        int on = 0;
        for (const Plane<double>& q : planes) on += side(q, p) == 0;
        vertices += on >= 3;
    }
    return vertices;
}

std::string scene_with(const std::string& object) {
    return R"({"camera": {"position": [0, 0, 8], "look_at": [0, 0, 0]},
  "materials": {"m": {"diffuse": 0.5}},
  "objects": [)" + object + "]}";
}

const Polyhedron& only_polyhedron(const Scene& s) {
    static const Polyhedron none;
    if (s.objects.size() != 1 || !std::holds_alternative<Polyhedron>(s.objects[0].shape)) {
        ADD_FAILURE() << "expected one polyhedron";
        return none;
    }
    return std::get<Polyhedron>(s.objects[0].shape);
}

ParseError error_of(const std::string& text) {
    const ParseResult r = parse_scene(text, "test.json");
    EXPECT_FALSE(r) << "accepted: " << text;
    return r.error;
}

TEST(PolyhedronParse, PlanesAreStoredAsGiven) {
    const Scene s = parse_or_die(scene_with(R"({"type": "polyhedron", "material": "m", "planes": [
        {"normal": [1, 0, 0], "offset": 1}, {"normal": [-1, 0, 0], "offset": 1},
        {"normal": [0, 2, 0], "offset": 0.5}, {"normal": [0, 0, 1e-3], "offset": -7}]})"));
    const Polyhedron& p = only_polyhedron(s);
    ASSERT_EQ(p.planes.size(), 4u);
    EXPECT_EQ(p.planes[2].normal, Vec3d(0, 2, 0));
    EXPECT_EQ(p.planes[2].offset, 0.5);
    EXPECT_EQ(p.planes[3].normal, Vec3d(0, 0, 1e-3));
    EXPECT_EQ(p.planes[3].offset, -7);
    EXPECT_TRUE(p.exact);
    EXPECT_FALSE(p.bound);  // plane-given polyhedra may be unbounded: no pre-filter
    EXPECT_EQ(p.kernel().planes.data(), p.planes.data());  // the kernel's view does not copy
}

TEST(PolyhedronParse, VerticesGiveTheExactHull) {
    // A cube's corners, its face centres and its centre: 6 planes, the interior points ignored.
    std::string pts;
    std::vector<Vec3d> all;
    for (int x = -1; x <= 1; x += 2)
        for (int y = -1; y <= 1; y += 2)
            for (int z = -1; z <= 1; z += 2) all.push_back(Vec3d(x, y, z) * 0.75 + Vec3d(1, 2, 3));
    all.push_back(Vec3d(1, 2, 3));
    all.push_back(Vec3d(1.75, 2, 3));
    for (const Vec3d& p : all) {
        std::ostringstream os;
        os.precision(17);
        os << (pts.empty() ? "" : ", ") << "[" << p[0] << ", " << p[1] << ", " << p[2] << "]";
        pts += os.str();
    }
    const Scene s = parse_or_die(scene_with(R"({"type": "polyhedron", "material": "m", "vertices": [)" + pts + "]}"));
    const Polyhedron& p = only_polyhedron(s);
    EXPECT_EQ(p.planes.size(), 6u);
    EXPECT_TRUE(p.exact);
    EXPECT_EQ(check_hull(p.planes, all), 8);  // the 8 corners; the face centre is on one plane
    ASSERT_TRUE(p.bound);
}

TEST(PolyhedronParse, PresetsAreExactSolids) {
    const struct {
        const char* name;
        std::size_t planes, vertices;
    } presets[] = {{"tetrahedron", 4, 4}, {"octahedron", 8, 6}, {"prism", 5, 6}, {"cube", 6, 8}, {"dodecahedron", 12, 20}};
    for (const auto& pr : presets) {
        SCOPED_TRACE(pr.name);
        const Scene s = parse_or_die(scene_with(std::string(R"({"type": "polyhedron", "material": "m", "preset": ")") +
                                                pr.name + R"(", "center": [0.5, -1, 2], "size": 1.5})"));
        const Polyhedron& p = only_polyhedron(s);
        EXPECT_EQ(p.planes.size(), pr.planes);
        EXPECT_TRUE(p.exact);
        std::vector<Vec3d> pts = preset_points(pr.name);
        for (Vec3d& v : pts) v = v * 1.5 + Vec3d(0.5, -1, 2);  // exact: dyadic, few bits
        EXPECT_EQ(std::size_t(check_hull(p.planes, pts)), pr.vertices);
        ASSERT_TRUE(p.bound);
        for (const Vec3d& v : pts) {  // |v - c|^2 <= r^2, exactly
            E d2 = E(0.0);
            for (int i = 0; i < 3; ++i) d2 = d2 + (E(v[i]) - E(p.bound->center[i])) * (E(v[i]) - E(p.bound->center[i]));
            EXPECT_LT((d2 - E(p.bound->radius) * E(p.bound->radius)).sign(), 0);
        }
    }
}

TEST(PolyhedronParse, DodecahedronPlanesAreTheStatedOnes) {
    const Scene s = parse_or_die(scene_with(R"({"type": "polyhedron", "material": "m", "preset": "dodecahedron"})"));
    const Polyhedron& p = only_polyhedron(s);
    const double h = dodecahedron_h();
    EXPECT_LE(std::abs(h - 2 / (1 + std::sqrt(5.0))), 0x1p-14);
    ASSERT_EQ(p.planes.size(), 12u);
    for (const Plane<double>& q : p.planes) {
        // (±h, ±1, 0)·p <= 1 + h and its cyclic permutations, exactly.
        EXPECT_EQ(q.offset, 1 + h);
        Vec3d a = q.normal.cwiseAbs();
        int one = -1;
        for (int i = 0; i < 3; ++i)
            if (a[i] == 1) one = i;
        ASSERT_GE(one, 0) << q.normal.transpose();
        EXPECT_EQ(a[(one + 2) % 3], h) << q.normal.transpose();
        EXPECT_EQ(a[(one + 1) % 3], 0) << q.normal.transpose();
    }
}

// Seeded random integer points: in general position (checked: no 4 coplanar would break
// the count only), Euler's formula for a simplicial hull gives F = 2V - 4.
TEST(PolyhedronHull, RandomPointsEulerAndContainment) {
    const std::uint64_t seed = 20261203;
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<int> coord(-1000, 1000);
    for (int round = 0; round < 20; ++round) {
        SCOPED_TRACE("seed " + std::to_string(seed) + ", round " + std::to_string(round));
        std::vector<Vec3d> pts;
        const int n = 5 + round * 2;
        for (int i = 0; i < n; ++i) pts.push_back(Vec3d(coord(rng), coord(rng), coord(rng)) * 0.125);
        const HullResult h = convex_hull(pts);
        ASSERT_TRUE(h.error.empty()) << h.error;
        EXPECT_TRUE(h.exact);  // small dyadic points: exact planes
        const int v = check_hull(h.planes, pts);
        bool general = true;  // no 4 points coplanar on a facet: every facet a triangle
        for (const Plane<double>& q : h.planes) {
            int on = 0;
            for (const Vec3d& p : pts) on += side(q, p) == 0;
            general = general && on == 3;
        }
        if (general) {
            EXPECT_EQ(int(h.planes.size()), 2 * v - 4);
        }
        // Each stored point of a facet is extreme or on an edge; the extreme ones are on >= 3.
        EXPECT_GE(v, 4);
    }
}

// orient's two paths (exact differences with det3_sign; expansions otherwise) against
// the determinant taken in BigDyadic, on seeded points: small dyadic ones, near-coplanar
// ones and ones with full mantissas.
TEST(PolyhedronHull, OrientIsExact) {
    const std::uint64_t seed = 77;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> any(-10, 10);
    std::uniform_int_distribution<int> small(-8, 8);
    int zero = 0;
    for (int i = 0; i < 3000; ++i) {
        Vec3d p[4];
        for (Vec3d& v : p)
            v = i % 3 == 0 ? Vec3d(any(rng), any(rng), any(rng)) : Vec3d(small(rng), small(rng), small(rng)) * 0.25;
        if (i % 3 == 2) p[3] = p[0] + (p[1] - p[0]) * 0.5 + (p[2] - p[0]) * 0.25;  // coplanar when exact
        E u[3], v[3], w[3];
        for (int k = 0; k < 3; ++k) {
            u[k] = E(p[1][k]) - E(p[0][k]);
            v[k] = E(p[2][k]) - E(p[0][k]);
            w[k] = E(p[3][k]) - E(p[0][k]);
        }
        const E det = (u[1] * v[2] - u[2] * v[1]) * w[0] + (u[2] * v[0] - u[0] * v[2]) * w[1] + (u[0] * v[1] - u[1] * v[0]) * w[2];
        ASSERT_EQ(orient(p[0], p[1], p[2], p[3]), det.sign()) << "seed " << seed << ", case " << i;
        zero += det.sign() == 0;
    }
    EXPECT_GT(zero, 900);  // the coplanar cases are decided 0, not by a tolerance
}

TEST(PolyhedronHull, InexactPlanesStillHoldEveryPoint) {
    // Coordinates with full 53-bit mantissas: n = (b - a) × (c - a) needs about 106 bits.
    const std::vector<Vec3d> pts{Vec3d(0.1, 0.2, 0.3), Vec3d(1.7, 0.3, 0.1), Vec3d(0.3, 1.9, 0.7),
                                 Vec3d(0.7, 0.6, 2.3), Vec3d(1.1, 1.3, 1.9)};
    const HullResult h = convex_hull(pts);
    ASSERT_TRUE(h.error.empty()) << h.error;
    EXPECT_FALSE(h.exact);
    check_hull(h.planes, pts, false);  // every point on or inside every stored plane, exactly
    EXPECT_GT(h.slack, 0);
    EXPECT_LT(h.slack, 1e-14);
    // In a scene: no pre-filter ball is claimed for a solid larger than the hull.
    std::ostringstream os;
    os.precision(17);
    os << R"({"type": "polyhedron", "material": "m", "vertices": [)";
    for (std::size_t i = 0; i < pts.size(); ++i)
        os << (i ? ", " : "") << "[" << pts[i][0] << ", " << pts[i][1] << ", " << pts[i][2] << "]";
    os << "]}";
    const Scene s = parse_or_die(scene_with(os.str()));
    EXPECT_FALSE(only_polyhedron(s).exact);
    EXPECT_FALSE(only_polyhedron(s).bound);
}

TEST(PolyhedronErrors, NameTheObjectAndItsPlace) {
    struct Case {
        std::string object, key, message;
    };
    std::string many = R"({"type": "polyhedron", "name": "big", "material": "m", "planes": [)";
    for (int i = 0; i < 257; ++i) many += std::string(i ? ", " : "") + R"({"normal": [1, 0, 0], "offset": 1})";
    many += "]}";
    const Case cases[] = {
        {R"({"type": "polyhedron", "name": "gem", "material": "m", "planes": [{"normal": [1, 0, 0], "offset": 1}, {"normal": [0, 0, 0], "offset": 1}]})",
         "objects[0].planes[1].normal", "must not be the zero vector (polyhedron \"gem\")"},
        {many, "objects[0].planes", "at most 256 planes per polyhedron, got 257 (polyhedron \"big\")"},
        {R"({"type": "polyhedron", "material": "m", "planes": [{"normal": [1, 0, 0], "offset": 1e400}]})",
         "objects[0].planes[0].offset", "expected a finite number"},
        {R"({"type": "polyhedron", "material": "m", "planes": []})", "objects[0].planes", "non-empty array"},
        {R"({"type": "polyhedron", "material": "m", "planes": [{"normal": [1, 0, 0]}]})", "objects[0].planes[0].offset",
         "missing"},
        {R"({"type": "polyhedron", "material": "m", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]})",
         "objects[0].vertices", "all points lie in one plane"},
        {R"({"type": "polyhedron", "material": "m", "vertices": [[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]]})",
         "objects[0].vertices", "all points lie on one line"},
        {R"({"type": "polyhedron", "name": "twice", "material": "m", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 0]]})",
         "objects[0].vertices", "points 1 and 4 are the same point (polyhedron \"twice\")"},
        {R"({"type": "polyhedron", "material": "m", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]})", "objects[0].vertices",
         "at least 4 points"},
        {R"({"type": "polyhedron", "material": "m", "preset": "icosahedron"})", "objects[0].preset", "expected one of"},
        {R"({"type": "polyhedron", "material": "m", "preset": "cube", "size": 0})", "objects[0].size", "a size > 0"},
        {R"({"type": "polyhedron", "material": "m", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], "size": 2})",
         "objects[0].size", "only with \"preset\""},
        {R"({"type": "polyhedron", "material": "m", "preset": "cube", "planes": []})", "objects[0].planes",
         "exactly one of"},
    };
    for (const Case& c : cases) {
        const ParseError e = error_of(scene_with(c.object));
        EXPECT_EQ(e.kind, ParseError::Kind::schema) << e.to_string();
        EXPECT_EQ(e.key, c.key) << e.to_string();
        EXPECT_NE(e.message.find(c.message), std::string::npos) << e.to_string();
        EXPECT_GE(e.line, 1) << e.to_string();
        EXPECT_GE(e.column, 1) << e.to_string();
    }
}

TEST(PolyhedronErrors, NaNIsASyntaxErrorAtItsPlace) {
    const std::string text = scene_with(R"({"type": "polyhedron", "material": "m", "planes": [{"normal": [NaN, 0, 0], "offset": 1}]})");
    const ParseError e = error_of(text);
    EXPECT_EQ(e.kind, ParseError::Kind::syntax) << e.to_string();
    // Line 3 of scene_with's text, at the N of NaN.
    EXPECT_EQ(e.line, 3) << e.to_string();
    const std::size_t line3 = text.find('\n', text.find('\n') + 1) + 1;
    EXPECT_EQ(std::size_t(e.column), text.find("NaN") - line3 + 1) << e.to_string();
}

TEST(PolyhedronErrors, TooManyVertices) {
    std::string v = R"({"type": "polyhedron", "material": "m", "vertices": [)";
    for (int i = 0; i < 65; ++i) v += std::string(i ? ", " : "") + "[" + std::to_string(i) + ", " + std::to_string(i * i) + ", 1]";
    v += "]}";
    const ParseError e = error_of(scene_with(v));
    EXPECT_EQ(e.key, "objects[0].vertices");
    EXPECT_NE(e.message.find("at most 64 vertices"), std::string::npos) << e.to_string();
}

// --- rendering ---------------------------------------------------------------------------

std::string box_scene(const std::string& object, const std::string& material) {
    return R"({"camera": {"position": [2.5, 2, 4], "look_at": [0, 0, 0], "fov": 50},
  "render": {"width": 48, "height": 36, "depth": 4, "mode": "certified", "background": [0.1, 0.1, 0.2]},
  "ambient_light": 0.1,
  "lights": [{"position": [3, 5, 2]}],
  "materials": {"m": )" + material + R"(, "floor": {"diffuse": [0.6, 0.5, 0.4], "reflectivity": 0.2}},
  "objects": [)" + object + R"(,
    {"type": "sphere", "center": [1.5, 0.5, -1.5], "radius": 0.5, "material": "floor"},
    {"type": "plane", "normal": [0, 1, 0], "offset": -1, "material": "floor"}]})";
}

// A polyhedron of a box's six planes renders the same image as the box (certified mode):
// the kernel answers the two alike, bit for bit, and the tracer shades and spawns from
// the same face.
TEST(PolyhedronRender, BoxPlanesRenderAsTheBox) {
    const std::string box = R"({"type": "box", "min": [-1, -1, -0.75], "max": [0.5, 0.25, 1], "material": "m"})";
    const std::string poly = R"({"type": "polyhedron", "material": "m", "planes": [
      {"normal": [-1, 0, 0], "offset": 1}, {"normal": [1, 0, 0], "offset": 0.5},
      {"normal": [0, -1, 0], "offset": 1}, {"normal": [0, 1, 0], "offset": 0.25},
      {"normal": [0, 0, -1], "offset": 0.75}, {"normal": [0, 0, 1], "offset": 1}]})";
    for (const char* material : {R"({"diffuse": [0.8, 0.3, 0.2], "specular": 0.4})",
                                 R"({"diffuse": [0.3, 0.3, 0.3], "reflectivity": 0.5})",
                                 R"({"diffuse": 0.05, "transparency": 0.9, "ior": 1.5})"}) {
        SCOPED_TRACE(material);
        RenderOptions opt;
        opt.threads = 2;
        const RenderResult a = render(parse_or_die(box_scene(box, material)), opt);
        const RenderResult b = render(parse_or_die(box_scene(poly, material)), opt);
        const ImageComparison c = compare(a.image, b.image);
        EXPECT_EQ(c.differing_pixels, 0) << "largest channel difference " << c.max_channel_difference;
        EXPECT_EQ(a.stats.invalid + b.stats.invalid, 0u);
        EXPECT_EQ(a.stats.refraction, b.stats.refraction);
    }
}

// The pre-filter changes nothing in certified mode (the ball holds the solid exactly), and
// the showcase scene renders with no invalid query in every mode.
TEST(PolyhedronRender, PrefilterChangesNoPixel) {
    Scene s = load_or_die(scene_path("polyhedra.json"));
    s.settings.width = 80;
    s.settings.height = 60;
    for (Mode m : all_modes) {
        SCOPED_TRACE(mode_name(m));
        s.settings.mode = m;
        RenderOptions with, without;
        with.threads = without.threads = 2;
        without.trace.polyhedron_prefilter = false;
        const RenderResult a = render(s, with);
        const RenderResult b = render(s, without);
        EXPECT_EQ(compare(a.image, b.image).differing_pixels, 0);
        EXPECT_EQ(a.stats.invalid, 0u);
        EXPECT_GT(a.stats.refraction, 0u);  // the glass dodecahedron refracts
    }
}

TEST(PolyhedronPov, IntersectionOfUnitPlanes) {
    const Scene s = parse_or_die(scene_with(R"({"type": "polyhedron", "name": "t", "material": "m", "preset": "tetrahedron"},
      {"type": "polyhedron", "material": "m", "planes": [{"normal": [0, 3, 4], "offset": 10}]})"));
    const std::string pov = export_pov(s);
    EXPECT_NE(pov.find("// t\nintersection {\n  plane { <"), std::string::npos) << pov;
    std::size_t planes = 0;
    for (std::size_t p = pov.find("  plane { "); p != std::string::npos; p = pov.find("  plane { ", p + 1)) ++planes;
    EXPECT_EQ(planes, 4u) << pov;
    EXPECT_NE(pov.find("material { M0 }\n}\n"), std::string::npos);
    // A one-plane polyhedron is a POV-Ray plane (a half-space), with its unit normal.
    EXPECT_NE(pov.find("plane {\n  <0, 0.6, 0.8>, 2\n  material { M0 }\n}"), std::string::npos) << pov;
}

}  // namespace
}  // namespace rayproof::render::testing
