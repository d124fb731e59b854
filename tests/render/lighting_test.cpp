// Analytic pixel tests of the lighting model, in every mode the kernel has: a single lit
// sphere and a single lit plane where the colour at the centre pixel is worked out by
// hand from I = I_a·K_a + f_att·I_l·(K_d·(N·L) + K_s·(R·V)^n) (and the Blinn variant);
// the attenuation clamp; a light behind the surface; opaque and transparent shadows;
// a mirror reflecting the background; the camera's ray through a corner pixel.
#include "render_support.hpp"

#include <cmath>

namespace rayproof::render::testing {
namespace {

class Lighting : public ::testing::TestWithParam<Mode> {};

// Centre pixel of a 5×5 image: (2.5, 2.5) maps to the view direction itself.
constexpr int side = 5;
constexpr double centre = 2.5;

Material lit_material(Highlight h) {
    Material m;
    m.ambient = Color(0.1, 0.2, 0.3);
    m.diffuse = Color(0.5, 0.4, 0.3);
    m.specular = Color(0.2, 0.25, 0.3);
    m.shininess = 10;
    m.highlight = h;
    return m;
}

// Sphere centre (0,0,-5), radius 1, eye at the origin looking down -z: the centre ray
// meets it at (0,0,-4) with N = (0,0,1) and V = (0,0,1). The light at (0,3,0) is at
// distance 5 along L = (0, 0.6, 0.8): N·L = 0.8, R = 2(N·L)N - L = (0,-0.6,0.8), R·V = 0.8;
// H = (L+V)/|L+V| = (0, 0.6, 1.8)/sqrt(3.6), N·H = 1.8/sqrt(3.6).
// f_att = 1/(1 + 0.1·5 + 0.01·25) = 1/1.75.
Scene sphere_scene(Mode mode, Highlight h) {
    Scene s = scene_with(Camera{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40}, side, side, mode);
    s.ambient_light = Color(0.2, 0.2, 0.2);
    s.lights.push_back(Light{{0, 3, 0}, Color(1, 0.9, 0.8), 1, 0.1, 0.01});
    add(s, Sphere<double>{{0, 0, -5}, 1}, lit_material(h));
    return s;
}

TEST_P(Lighting, SpherePhongByHand) {
    const Scene s = sphere_scene(GetParam(), Highlight::phong);
    const Color ia(0.2, 0.2, 0.2), il(1, 0.9, 0.8), ka(0.1, 0.2, 0.3), kd(0.5, 0.4, 0.3), ks(0.2, 0.25, 0.3);
    const Color want = ia * ka + (1 / 1.75) * il * (kd * 0.8 + ks * std::pow(0.8, 10));
    expect_color(radiance(s, centre, centre), want);
}

TEST_P(Lighting, SphereBlinnByHand) {
    const Scene s = sphere_scene(GetParam(), Highlight::blinn);
    const Color ia(0.2, 0.2, 0.2), il(1, 0.9, 0.8), ka(0.1, 0.2, 0.3), kd(0.5, 0.4, 0.3), ks(0.2, 0.25, 0.3);
    const double nh = 1.8 / std::sqrt(3.6);
    const Color want = ia * ka + (1 / 1.75) * il * (kd * 0.8 + ks * std::pow(nh, 10));
    expect_color(radiance(s, centre, centre), want);
}

// The eye at (0,1,0) looking straight down at the floor y = 0, which the centre ray meets
// at (0,0,0) with N = V = (0,1,0).
Scene looking_down(Mode mode) { return scene_with(Camera{{0, 1, 0}, {0, 0, 0}, {0, 0, -1}, 40}, side, side, mode); }

// Floor y = 0 seen straight down from (0,1,0): hit (0,0,0), N = V = (0,1,0). Light at
// (3,4,0): distance 5, L = (0.6,0.8,0), N·L = 0.8, R = (-0.6,0.8,0), R·V = 0.8.
// c1 = 0.5 makes 1/(c1 + ...) = 2, which the model clamps to 1.
TEST_P(Lighting, PlaneWithAttenuationClampByHand) {
    Scene s = looking_down(GetParam());
    s.ambient_light = Color(0.1, 0.1, 0.1);
    s.lights.push_back(Light{{3, 4, 0}, Color(0.9, 0.8, 0.7), 0.5, 0, 0});
    Material m = lit_material(Highlight::phong);
    m.shininess = 3;
    add(s, Plane<double>{{0, 1, 0}, 0}, m);
    const Color want = Color(0.1, 0.1, 0.1) * Color(0.1, 0.2, 0.3) +
                       Color(0.9, 0.8, 0.7) * (Color(0.5, 0.4, 0.3) * 0.8 + Color(0.2, 0.25, 0.3) * std::pow(0.8, 3));
    expect_color(radiance(s, centre, centre), want);
}

// Two lights add; the second one's attenuation is 1/(1 + 0.5·5) = 1/3.5.
TEST_P(Lighting, TwoLightsAdd) {
    Scene s = looking_down(GetParam());
    s.lights.push_back(Light{{3, 4, 0}, Color(1, 1, 1), 1, 0, 0});
    s.lights.push_back(Light{{0, 4, 3}, Color(0.5, 0.25, 1), 1, 0.5, 0});
    add(s, Plane<double>{{0, 1, 0}, 0}, matte(Color(0.5, 0.5, 0.5)));
    const Color want = 0.5 * 0.8 * Color(1, 1, 1) + (1 / 3.5) * 0.5 * 0.8 * Color(0.5, 0.25, 1);
    expect_color(radiance(s, centre, centre), want);
}

// A light below the floor: N·L < 0, so no diffuse, no specular and no shadow ray.
TEST_P(Lighting, LightBehindSurfaceGivesAmbientOnly) {
    Scene s = looking_down(GetParam());
    s.ambient_light = Color(0.3, 0.3, 0.3);
    s.lights.push_back(Light{{3, -4, 0}, Color(1, 1, 1), 1, 0, 0});
    add(s, Plane<double>{{0, 1, 0}, 0}, lit_material(Highlight::phong));
    Stats st;
    const auto got = radiance(s, centre, centre, {}, &st);
    expect_color(got, Color(0.3, 0.3, 0.3) * Color(0.1, 0.2, 0.3));
    EXPECT_EQ(st.shadow, 0u);
}

// A ball between the floor point and the light: opaque, only ambient remains;
// transparent with K_t = 0.25, K_t² of the direct light passes (two surfaces crossed).
TEST_P(Lighting, ShadowsOpaqueAndTransparent) {
    for (double kt : {0.0, 0.25}) {
        SCOPED_TRACE(kt);
        Scene s = looking_down(GetParam());
        s.ambient_light = Color(0.2, 0.2, 0.2);
        s.lights.push_back(Light{{3, 4, 0}, Color(1, 1, 1), 1, 0, 0});
        add(s, Plane<double>{{0, 1, 0}, 0}, matte(Color(0.5, 0.5, 0.5), Color(0.5, 0.5, 0.5)));
        Material blocker = matte(Color(1, 0, 0));
        blocker.transparency = kt;
        blocker.ior = 1;
        add(s, Sphere<double>{{1.5, 2, 0}, 0.5}, blocker);  // on the segment from (0,0,0) to (3,4,0)
        expect_color(radiance(s, centre, centre), Color::Constant(0.2 * 0.5 + kt * kt * 0.5 * 0.8));
    }
}

// A perfect mirror plane facing the eye, nothing else: the background, scaled by k_r.
TEST_P(Lighting, MirrorReflectsBackground) {
    Scene s = scene_with(Camera{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40}, side, side, GetParam());
    s.settings.background = Color(0.2, 0.4, 0.8);
    Material mirror;
    mirror.reflectivity = Color(0.9, 0.5, 0.25);
    add(s, Plane<double>{{0, 0, 1}, -3}, mirror);
    Stats st;
    const auto got = radiance(s, centre, centre, {}, &st);
    expect_color(got, Color(0.9 * 0.2, 0.5 * 0.4, 0.25 * 0.8));
    EXPECT_EQ(st.reflection, 1u);
    // depth 1: primary rays only, so the mirror shows its (zero) local colour
    s.settings.depth = 1;
    const auto flat = radiance(s, centre, centre);
    expect_color(flat, Color::Zero());
}

// The primary ray through the corner of the image: f + sx·r + sy·u with
// sx = -tan(fov/2)·aspect, sy = tan(fov/2).
TEST(Camera, CornerRayByHand) {
    const Camera cam{{1, 2, 3}, {1, 2, 2}, {0, 1, 0}, 90};  // looks down -z; tan(45°) = 1
    const Ray<double> r = camera_ray(cam, 40, 20, 0, 0);
    EXPECT_EQ(r.origin, Vec3d(1, 2, 3));
    const Vec3d d = r.direction;
    EXPECT_NEAR(d[0], -2, 1e-15);  // left: -tan·(40/20)
    EXPECT_NEAR(d[1], 1, 1e-15);   // top
    EXPECT_NEAR(d[2], -1, 1e-15);
    EXPECT_EQ(r.t_min, 0);
}

INSTANTIATE_TEST_SUITE_P(Modes, Lighting, ::testing::ValuesIn(every_mode()),
                         [](const auto& info) { return std::string(mode_name(info.param)); });

}  // namespace
}  // namespace rayproof::render::testing
