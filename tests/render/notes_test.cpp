// What the ray-tracing notes add to the lighting model, worked out by hand at the centre
// pixel, in every mode: the ray tree's distance attenuation (a reflected node weighed by
// f(d) of its distance from its parent, the background not weighed, the scene switch);
// visible lights (a ray that meets a light's sphere takes its colour, a light casts no
// shadow, radius 0 is never seen); translucency (a thin sheet lit from behind, an opaque
// solid shading its own far side); and shadow rays keeping K_t at each surface crossed.
#include "render_support.hpp"

#include <rayproof/render/parse.hpp>

#include <cmath>

namespace rayproof::render::testing {
namespace {

class Notes : public ::testing::TestWithParam<Mode> {};

constexpr int side = 5;
constexpr double centre = 2.5;

Scene looking_at_minus_z(Mode mode) { return scene_with(Camera{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40}, side, side, mode); }

// A mirror plane z = -3 facing the eye and, behind the eye, a wall z = 2 that shows only its
// ambient colour: the centre ray meets the mirror at distance 3, the reflected ray the wall
// at distance 5 from the mirror. Its node is weighed by f(5) = 1 / (c1 + 5 c2 + 25 c3).
TEST_P(Notes, TreeAttenuationWeighsAReflectedNodeByItsDistance) {
    Scene s = looking_at_minus_z(GetParam());
    s.ambient_light = Color(1, 1, 1);
    Material mirror;
    mirror.reflectivity = Color(0.9, 0.8, 0.7);
    add(s, Plane<double>{{0, 0, 1}, -3}, mirror);
    add(s, Plane<double>{{0, 0, -1}, -2}, matte(Color::Zero(), Color(0.5, 0.4, 0.3)));
    const Color seen = Color(0.9, 0.8, 0.7) * Color(0.5, 0.4, 0.3);

    s.tree_attenuation = TreeAttenuation{true, 1, 0.1, 0.02};
    expect_color(radiance(s, centre, centre), seen / (1 + 0.1 * 5 + 0.02 * 25));
    s.tree_attenuation.enabled = false;
    expect_color(radiance(s, centre, centre), seen);
    // c1 < 1 and near: min(1 / x, 1) clamps to 1.
    s.tree_attenuation = TreeAttenuation{true, 0.5, 0, 0.01};
    expect_color(radiance(s, centre, centre), seen);
}

// The background is no node of the tree: a mirror shows it unweighed, however far.
TEST_P(Notes, TreeAttenuationLeavesTheBackground) {
    Scene s = looking_at_minus_z(GetParam());
    s.settings.background = Color(0.2, 0.4, 0.8);
    s.tree_attenuation = TreeAttenuation{true, 1, 1, 1};
    Material mirror;
    mirror.reflectivity = Color(1, 1, 1);
    add(s, Plane<double>{{0, 0, 1}, -3}, mirror);
    expect_color(radiance(s, centre, centre), Color(0.2, 0.4, 0.8));
}

// The default is on, with the documented constants, and a scene file turns it off.
TEST(NotesScene, TreeAttenuationDefaultAndSwitch) {
    const TreeAttenuation d;
    EXPECT_TRUE(d.enabled);
    EXPECT_DOUBLE_EQ(d.factor(10), 1 / (1 + 0.01 * 100));
    const std::string head = R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]}, "objects": [])";
    EXPECT_TRUE(parse_or_die(head + "}").tree_attenuation.enabled);
    EXPECT_FALSE(parse_or_die(head + R"(, "tree_attenuation": false})").tree_attenuation.enabled);
    const Scene c = parse_or_die(head + R"(, "tree_attenuation": [2, 0.5, 0.25]})");
    EXPECT_TRUE(c.tree_attenuation.enabled);
    EXPECT_DOUBLE_EQ(c.tree_attenuation.factor(2), 1 / (2 + 1 + 1.0));
    const ParseResult bad = parse_scene(head + R"(, "tree_attenuation": [1, -1, 0]})", "t.json");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error.key, "tree_attenuation");
}

// A light of radius 0.5 straight ahead at distance 4 is seen in its own colour, also in a
// mirror (weighed by k_r and the tree attenuation of its distance); radius 0 is not seen.
TEST_P(Notes, VisibleLightShowsItsColour) {
    Scene s = looking_at_minus_z(GetParam());
    s.settings.background = Color(0.1, 0.1, 0.1);
    s.lights.push_back(Light{{0, 0, -4}, Color(1.5, 0.6, 0.3), 1, 0, 0.5, 0.5});
    expect_color(radiance(s, centre, centre), Color(1.5, 0.6, 0.3));
    s.lights[0].radius = 0;
    expect_color(radiance(s, centre, centre), Color(0.1, 0.1, 0.1));

    // Behind the eye, seen in a mirror at z = -3: the reflected ray travels 3 + 4 - 0.5.
    Scene m = looking_at_minus_z(GetParam());
    m.tree_attenuation = TreeAttenuation{true, 1, 0, 0.01};
    m.lights.push_back(Light{{0, 0, 4}, Color(1, 0.5, 0.25), 1, 0, 0, 0.5});
    Material mirror;
    mirror.reflectivity = Color(0.8, 0.8, 0.8);
    add(m, Plane<double>{{0, 0, 1}, -3}, mirror);
    const double d = 3 + 4 - 0.5;
    expect_color(radiance(m, centre, centre), 0.8 * Color(1, 0.5, 0.25) / (1 + 0.01 * d * d), 1e-9);
}

// A visible light between another light and a lit floor casts no shadow: the floor point
// under both gets the full light of the far one.
TEST_P(Notes, VisibleLightCastsNoShadow) {
    Scene s = scene_with(Camera{{0, 1, 0}, {0, 0, 0}, {0, 0, -1}, 40}, side, side, GetParam());
    s.lights.push_back(Light{{0, 4, 0}, Color(1, 1, 1), 1, 0, 0, 0});
    s.lights.push_back(Light{{0, 2, 0}, Color(0, 0, 0), 1, 0, 0, 0.5});  // dark, on the segment
    // The eye at (0,1,0) is outside the bulb (radius 0.5 around y = 2) and looks away from it.
    add(s, Plane<double>{{0, 1, 0}, 0}, matte(Color(0.5, 0.5, 0.5)));
    expect_color(radiance(s, centre, centre), Color::Constant(0.5));
}

// A thin translucent sheet (the plane z = -3, facing the eye) lit only from behind by a
// light at (0, 3, -7): distance 5 from the hit point (0, 0, -3), -N·L = 0.8. The eye sees
// I_a·K_a + f_att·I_l·K_d·k_dt·0.8; without translucency only the ambient term.
TEST_P(Notes, TranslucentSheetLitFromBehind) {
    for (double kdt : {0.0, 0.6}) {
        SCOPED_TRACE(kdt);
        Scene s = looking_at_minus_z(GetParam());
        s.ambient_light = Color(0.1, 0.1, 0.1);
        s.lights.push_back(Light{{0, 3, -7}, Color(1, 0.9, 0.8), 1, 0, 0.01, 0});
        Material paper = matte(Color(0.8, 0.7, 0.6), Color(0.5, 0.5, 0.5));
        paper.translucency = kdt;
        add(s, Plane<double>{{0, 0, 1}, -3}, paper);
        const Color want = Color::Constant(0.1 * 0.5) + Color(1, 0.9, 0.8) / (1 + 0.01 * 25) *
                                                             Color(0.8, 0.7, 0.6) * (kdt * 0.8);
        expect_color(radiance(s, centre, centre), want);
    }
}

// An opaque translucent solid does not pass light to its own front: the shadow ray from
// its far side runs through the solid. A transparent one passes K_t (one crossing).
// (The tree attenuation is off, to keep the inside path's weight 1.)
TEST_P(Notes, TranslucentSolidShadesItself) {
    for (double kt : {0.0, 0.5}) {
        SCOPED_TRACE(kt);
        Scene s = looking_at_minus_z(GetParam());
        s.lights.push_back(Light{{0, 0, -10}, Color(1, 1, 1), 1, 0, 0, 0});
        Material m = matte(Color(0.4, 0.4, 0.4));
        m.translucency = 1;
        m.transparency = kt;
        m.ior = 1;
        add(s, Aabb<double>{{-1, -1, -5}, {1, 1, -3}}, m);
        s.tree_attenuation.enabled = false;
        // Front face z = -3: N = (0,0,1), the light straight behind: -N·L = 1, and K_t of
        // the light passes. The transmitted ray (ior 1) meets the back face from inside,
        // lit from behind in full, then goes on to the black background:
        // I = (1 - K_t)·0.4·K_t + K_t·(1 - K_t)·0.4.
        expect_color(radiance(s, centre, centre), Color::Constant(2 * kt * (1 - kt) * 0.4));
    }
}

// A shadow ray keeps K_t at each surface it crosses: two for a ball on its way, one for a
// thin transparent sheet. The floor point (0,0,0) under the light (3,4,0), N·L = 0.8.
TEST_P(Notes, ShadowKeepsKtPerSurfaceCrossed) {
    const double kt = 0.25;
    for (bool sheet : {false, true}) {
        SCOPED_TRACE(sheet ? "sheet" : "ball");
        Scene s = scene_with(Camera{{0, 1, 0}, {0, 0, 0}, {0, 0, -1}, 40}, side, side, GetParam());
        s.lights.push_back(Light{{3, 4, 0}, Color(1, 1, 1), 1, 0, 0, 0});
        add(s, Plane<double>{{0, 1, 0}, 0}, matte(Color(0.5, 0.5, 0.5)));
        Material glass = matte(Color(1, 0, 0));
        glass.transparency = kt;
        glass.ior = 1;
        if (sheet)
            add(s, Plane<double>{{1, 0, 0}, 1.5}, glass);  // x = 1.5 crosses the segment once
        else
            add(s, Sphere<double>{{1.5, 2, 0}, 0.5}, glass);
        expect_color(radiance(s, centre, centre), Color::Constant((sheet ? kt : kt * kt) * 0.5 * 0.8));
    }
}

INSTANTIATE_TEST_SUITE_P(Modes, Notes, ::testing::ValuesIn(every_mode()),
                         [](const auto& info) { return std::string(mode_name(info.param)); });

}  // namespace
}  // namespace rayproof::render::testing
