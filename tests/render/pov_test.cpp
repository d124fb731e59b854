// The POV-Ray export: the text has one POV-Ray object per scene object (spheres, boxes
// for both box kinds with a matrix for the oriented one, planes with unit normals),
// every light and material, a right-handed camera; names cannot inject POV-Ray code;
// what cannot be exported exactly is listed (and nothing else);
// and, when povray was found at configure time, every example scene's export parses
// and renders with povray at 8×6, and POV-Ray's picture of every example scene but the
// hostile one is within a mean of 3/255 per channel of rayproof's (otherwise the tests
// are skipped and say why).
#include "render_support.hpp"

#include <rayproof/render/pov.hpp>

#include <cstdlib>
#include <fstream>

namespace rayproof::render::testing {
namespace {

std::size_t occurrences(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
    return n;
}

TEST(PovExport, OnePovObjectPerSceneObject) {
    const Scene s = load_or_die(scene_path("default.json"));
    const std::string pov = export_pov(s, "default.json");
    std::size_t spheres = 0, boxes = 0, obbs = 0, planes = 0;
    for (const Object& o : s.objects) {
        spheres += std::holds_alternative<Sphere<double>>(o.shape);
        boxes += std::holds_alternative<Aabb<double>>(o.shape) || std::holds_alternative<Obb<double>>(o.shape);
        obbs += std::holds_alternative<Obb<double>>(o.shape);
        planes += std::holds_alternative<Plane<double>>(o.shape);
    }
    EXPECT_EQ(occurrences(pov, "\nsphere {"), spheres);
    EXPECT_EQ(occurrences(pov, "\nbox {"), boxes);
    EXPECT_EQ(occurrences(pov, "matrix <"), obbs);
    EXPECT_EQ(occurrences(pov, "\nplane {"), planes);
    EXPECT_EQ(occurrences(pov, "light_source {"), s.lights.size());
    EXPECT_EQ(occurrences(pov, "#declare M"), s.materials.size());
    EXPECT_NE(pov.find("right -x*"), std::string::npos);
    EXPECT_NE(pov.find("interior { ior 1.5 }"), std::string::npos);  // the glass
}

TEST(PovExport, ExactNumbersAndUnitPlaneNormal) {
    Scene s;
    s.camera = Camera{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 45};
    s.materials.push_back(matte(Color(0.5, 0.5, 0.5)));
    Object plane;
    plane.shape = Plane<double>{{0, 3, 4}, 10};  // normal·p == 10 <=> (0, 0.6, 0.8)·p == 2
    s.objects.push_back(plane);
    Object ball;
    ball.shape = Sphere<double>{{0.1, 1e-300, 123456789.125}, 0.3};
    s.objects.push_back(ball);
    const std::string pov = export_pov(s);
    EXPECT_NE(pov.find("plane {\n  <0, 0.6, 0.8>, 2\n"), std::string::npos) << pov;
    EXPECT_NE(pov.find("<0.1, 1e-300, 123456789.125>, 0.3"), std::string::npos) << pov;
}

TEST(PovExport, NamesCannotInjectCode) {
    Scene s = parse_or_die(R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]},
        "materials": {"evil\n#declare X = 1;": {"diffuse": 0.5}},
        "objects": [{"type": "sphere", "name": "x\nsphere{0,1}", "center": [0,0,0], "radius": 1,
                     "material": "evil\n#declare X = 1;"}]})");
    const std::string pov = export_pov(s, "a\nb");
    EXPECT_EQ(occurrences(pov, "\n#declare X"), 0u);  // only inside a comment line
    EXPECT_EQ(occurrences(pov, "\nsphere{"), 0u);
    EXPECT_EQ(occurrences(pov, "\nsphere {"), 1u);
}

// The example scenes export exactly once the tree attenuation is off; a linear or
// clamped attenuation law, an RGB K_s and the tree attenuation are each listed.
TEST(PovExport, ListsWhatIsNotExact) {
    for (const char* name : {"default", "cube", "hostile", "notes"}) {
        Scene s = load_or_die(scene_path(std::string(name) + ".json"));
        s.tree_attenuation.enabled = false;
        EXPECT_EQ(to_pov(s).inexact, std::vector<std::string>{}) << name;
    }
    Scene s = load_or_die(scene_path("cube.json"));
    s.tree_attenuation.enabled = true;
    EXPECT_EQ(to_pov(s).inexact.size(), 1u);
    s.tree_attenuation.enabled = false;
    s.lights.push_back(Light{{0, 5, 0}, Color(1, 1, 1), 1, 0.5, 0, 0});   // c2 != 0
    s.lights.push_back(Light{{0, 5, 0}, Color(1, 1, 1), 0.5, 0, 0.1, 0});  // c1 < 1: clamped near the light
    Material rgb_ks;
    rgb_ks.specular = Color(0.1, 0.2, 0.3);
    s.materials.push_back(rgb_ks);
    const PovScene p = to_pov(s);
    ASSERT_EQ(p.inexact.size(), 3u);
    EXPECT_NE(p.inexact[0].find("light"), std::string::npos);
    EXPECT_NE(p.inexact[1].find("c1 < 1"), std::string::npos);
    EXPECT_NE(p.inexact[2].find("K_s"), std::string::npos);
    EXPECT_EQ(p.text, export_pov(s));
}

// The exact conversion of the quadratic law: colour / (2 c1), fade_distance sqrt(c1 / c3).
TEST(PovExport, QuadraticAttenuationAsFadeLaw) {
    Scene s = load_or_die(scene_path("cube.json"));
    s.lights = {Light{{0, 5, 0}, Color(1, 0.5, 0.25), 4, 0, 0.25, 0}};
    const std::string pov = export_pov(s);
    EXPECT_NE(pov.find("color rgb <0.125, 0.0625, 0.03125>"), std::string::npos) << pov;
    EXPECT_NE(pov.find("fade_distance 4 fade_power 2"), std::string::npos) << pov;
}

class PovRay : public ::testing::TestWithParam<std::string> {};

TEST_P(PovRay, ExportParsesAndRenders) {
#ifndef RAYPROOF_POVRAY
    GTEST_SKIP() << "povray was not found when the build was configured";
#else
    const Scene s = load_or_die(scene_path(GetParam() + ".json"));
    const std::string pov = scratch("scene.pov"), png = scratch("scene.png"), log = scratch("povray.log");
    std::ofstream(pov) << export_pov(s, GetParam() + ".json");
    std::remove(png.c_str());
    const std::string cmd = std::string(RAYPROOF_POVRAY) + " +I" + pov + " +O" + png +
                            " +W8 +H6 -D -P +FN File_Gamma=1.0 > " + log + " 2>&1";
    const int rc = std::system(cmd.c_str());
    std::ifstream in(log);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(rc, 0) << text;
    EXPECT_EQ(text.find("Parse Error"), std::string::npos) << text;
    Image img;
    ASSERT_EQ(read_image(png, img), "") << text;
    EXPECT_EQ(img.width, 8);
    EXPECT_EQ(img.height, 6);
#endif
}

INSTANTIATE_TEST_SUITE_P(Scenes, PovRay, ::testing::Values("default", "cube", "hostile", "notes", "polyhedra"));

// POV-Ray renders the export as rayproof renders the scene (tree attenuation off, the one
// feature it lacks): a mean absolute difference of at most 3/255 per channel at 96×72,
// certified mode. The hostile scene is left out: it sits at 2^44, where POV-Ray's own
// fixed minimum intersection distance, not the lighting, decides what it sees.
class PovParity : public ::testing::TestWithParam<std::string> {};

TEST_P(PovParity, RendersAsRayproof) {
#ifndef RAYPROOF_POVRAY
    GTEST_SKIP() << "povray was not found when the build was configured";
#else
    Scene s = load_or_die(scene_path(GetParam() + ".json"));
    s.tree_attenuation.enabled = false;
    s.settings.width = 96;
    s.settings.height = 72;
    s.settings.mode = Mode::certified;
    s.settings.supersample = 1;
    RenderOptions opt;
    opt.threads = 2;
    const Image ours = render(s, opt).image;
    const std::string pov = scratch("parity.pov"), png = scratch("parity.png"), log = scratch("parity.log");
    std::ofstream(pov) << export_pov(s, GetParam() + ".json");
    std::remove(png.c_str());
    const std::string cmd = std::string(RAYPROOF_POVRAY) + " +I" + pov + " +O" + png +
                            " +W96 +H72 -D -P -A +WT2 +FN File_Gamma=1.0 > " + log + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    Image theirs;
    ASSERT_EQ(read_image(png, theirs), "");
    const ImageComparison c = compare(ours, theirs);
    ASSERT_TRUE(c.same_size);
    EXPECT_LE(c.mean_abs_difference, 3.0) << GetParam() << ": largest channel difference " << c.max_channel_difference
                                          << ", " << c.differing_pixels << " pixels differ";
#endif
}

INSTANTIATE_TEST_SUITE_P(Scenes, PovParity, ::testing::Values("default", "cube", "notes", "polyhedra"));

}  // namespace
}  // namespace rayproof::render::testing
