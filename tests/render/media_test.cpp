// Refraction, media and "no work for unused features", in every mode the kernel has:
// Snell's law and total internal reflection of refract(); a tilted glass slab whose
// exit ray is displaced but parallel (a target placed by hand on the displaced ray is
// seen, and missed with ior 1); the camera inside a glass box (the exit face comes from
// the reversed ray); rays trapped by total internal reflection in a glass cube; the
// K_t mix by hand; and the ray counters: no shadow rays without lights, no refracted
// rays for opaque materials, no reflected rays for non-reflective ones.
#include "render_support.hpp"

#include <cmath>

namespace rayproof::render::testing {
namespace {

class Media : public ::testing::TestWithParam<Mode> {};

constexpr double pi = 3.14159265358979323846;

TEST(Refract, SnellsLaw) {
    const Vec3d n(0, 0, 1);
    for (double deg : {0.0, 10.0, 30.0, 60.0, 85.0}) {
        const double th = deg * pi / 180;
        const Vec3d u(std::sin(th), 0, -std::cos(th));
        const auto t = refract(u, n, 1 / 1.5);
        ASSERT_TRUE(t) << deg;
        EXPECT_NEAR(t->norm(), 1, 1e-15);
        const double sin_t = std::hypot((*t)[0], (*t)[1]);
        EXPECT_NEAR(1.5 * sin_t, std::sin(th), 1e-15) << deg;  // η_t sin θ_t = η_i sin θ_i
        EXPECT_LT((*t)[2], 0);                                  // continues through the surface
    }
}

TEST(Refract, TotalInternalReflectionBeyondCriticalAngle) {
    const Vec3d n(0, 0, 1);
    const double critical = std::asin(1 / 1.5);
    const auto at = [&](double th) { return refract(Vec3d(std::sin(th), 0, -std::cos(th)), n, 1.5); };
    EXPECT_TRUE(at(critical - 1e-6));
    EXPECT_FALSE(at(critical + 1e-6));
    EXPECT_FALSE(at(60 * pi / 180));
}

TEST(Reflect, MirrorsAboutTheNormal) {
    const Vec3d r = reflect(Vec3d(0.6, -0.8, 0), Vec3d(0, 1, 0));
    EXPECT_EQ(r, Vec3d(0.6, 0.8, 0));
}

// A slab of thickness 1 (an oriented box rotated 45° about y) in front of the eye; the
// centre ray meets it at 45°. Inside, sin θ_t = sin 45° / 1.5; the exit ray is parallel
// to the incoming one, displaced sideways by 1·sin(θ - θ_t)/cos θ_t. A small red ball
// sits on the displaced ray: it is seen through glass of ior 1.5 and missed with ior 1.
TEST_P(Media, TiltedSlabDisplacesButKeepsDirection) {
    const double th = pi / 4, tht = std::asin(std::sin(th) / 1.5);
    const double shift = std::sin(th - tht) / std::cos(tht);
    // The slab normal a0 = (cos45, 0, -sin45); the face the eye sees has the outward
    // normal -a0, and the ray (0,0,-1) bends towards +a0 on entry: it travels towards +x
    // inside and leaves at x = +shift.
    for (double ior : {1.5, 1.0}) {
        SCOPED_TRACE(ior);
        Scene s = scene_with(Camera{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 30}, 5, 5, GetParam());
        s.settings.background = Color(0, 0, 1);
        s.settings.depth = 4;
        s.tree_attenuation.enabled = false;  // the displacement alone (notes_test weighs the tree)
        Material glass;
        glass.transparency = 1;
        glass.ior = ior;
        Obb<double> slab;
        slab.center = Vec3d::Zero();
        slab.axes = Eigen::Matrix3d(Eigen::AngleAxisd(th, Vec3d::UnitY()));
        slab.half_extent = Vec3d(0.5, 10, 10);
        add(s, slab, glass);
        add(s, Sphere<double>{{shift, 0, -5}, 0.05}, matte(Color::Zero(), Color(1, 0, 0)));
        s.ambient_light = Color(1, 1, 1);
        const auto got = radiance(s, 2.5, 2.5);
        if (ior == 1.5)
            EXPECT_TRUE(same_color(got, Color(1, 0, 0)));  // the target, seen through two refractions
        else
            EXPECT_TRUE(same_color(got, Color(0, 0, 1)));  // undeviated: the background
    }
}

// The eye inside a glass box looking straight at a face: the primary ray starts inside
// (face -1), the exit face comes from the reversed ray, refraction goes from 1.5 to 1
// at normal incidence (undeviated). I = (1 - K_t)·I_a·K_a + K_t·background.
TEST_P(Media, EyeInsideGlassBoxLeavesThroughTheExitFace) {
    Scene s = scene_with(Camera{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 30}, 5, 5, GetParam());
    s.settings.background = Color(0.5, 0.25, 1);
    s.ambient_light = Color(1, 1, 1);
    Material glass = matte(Color::Zero(), Color(0.2, 0.2, 0.2));
    glass.transparency = 0.75;
    glass.ior = 1.5;
    add(s, Aabb<double>{{-1, -1, -2}, {1, 1, 1}}, glass);
    Stats st;
    const auto got = radiance(s, 2.5, 2.5, {}, &st);
    const Color want = 0.25 * Color(0.2, 0.2, 0.2) + 0.75 * Color(0.5, 0.25, 1);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], 1e-15);
    EXPECT_EQ(st.refraction, 1u);
}

// From the centre of a glass cube, the direction (0.7, 0.5, -0.45) meets every face at
// more than the critical angle asin(1/1.5) = 41.8° (43.9°, 59.0°, 62.4°): the ray is
// trapped by total internal reflection until the depth runs out, and the pixel is
// black. With ior 1 the same ray leaves at once and shows the background.
TEST_P(Media, TotalInternalReflectionTrapsTheRay) {
    for (double ior : {1.5, 1.0}) {
        SCOPED_TRACE(ior);
        const Vec3d dir = Vec3d(0.7, 0.5, -0.45);
        Scene s = scene_with(Camera{{0, 0, 0}, dir, {0, 1, 0}, 30}, 5, 5, GetParam());
        s.settings.background = Color(1, 1, 1);
        s.settings.depth = 12;
        s.settings.min_contribution = 0;
        Material glass;
        glass.transparency = 1;
        glass.ior = ior;
        add(s, Aabb<double>{{-1, -1, -1}, {1, 1, 1}}, glass);
        Stats st;
        const auto got = radiance(s, 2.5, 2.5, {}, &st);
        if (ior == 1.5) {
            EXPECT_TRUE(same_color(got, Color(0, 0, 0)));
            EXPECT_EQ(st.refraction, 11u);  // every level down to the maximum depth
        } else {
            EXPECT_TRUE(same_color(got, Color(1, 1, 1)));
            EXPECT_EQ(st.refraction, 1u);
        }
    }
}

// Entering and leaving a glass ball through its centre (normal incidence both times):
// I = (1-K_t)·L + K_t·((1-K_t)·L + K_t·B) with L = I_a·K_a the local colour.
TEST_P(Media, BallThroughTheCentreByHand) {
    Scene s = scene_with(Camera{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 30}, 5, 5, GetParam());
    s.settings.background = Color(0, 0.5, 1);
    s.ambient_light = Color(1, 1, 1);
    s.tree_attenuation.enabled = false;  // the K_t mix alone (notes_test weighs the tree)
    Material glass = matte(Color::Zero(), Color(0.4, 0.2, 0));
    glass.transparency = 0.6;
    glass.ior = 1.33;
    add(s, Sphere<double>{{0, 0, 0}, 1}, glass);
    const auto got = radiance(s, 2.5, 2.5);
    const Color l(0.4, 0.2, 0), b(0, 0.5, 1);
    const Color want = 0.4 * l + 0.6 * (0.4 * l + 0.6 * b);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], 1e-15);
}

// The counters show that features the scene does not use cost nothing.
TEST_P(Media, NoWorkForUnusedFeatures) {
    Scene s = load_or_die(scene_path("default.json"));
    s.settings.mode = GetParam();
    s.settings.width = 32;
    s.settings.height = 24;
    RenderOptions opt;
    opt.threads = 2;
    const RenderResult full = render(s, opt);
    EXPECT_GT(full.stats.shadow, 0u);
    EXPECT_GT(full.stats.reflection, 0u);
    EXPECT_GT(full.stats.refraction, 0u);

    Scene dark = s;
    dark.lights.clear();
    const RenderResult no_lights = render(dark, opt);
    EXPECT_EQ(no_lights.stats.shadow, 0u);
    EXPECT_GT(no_lights.stats.reflection, 0u);

    Scene opaque = s;
    for (Material& m : opaque.materials) m.transparency = 0;
    const RenderResult no_glass = render(opaque, opt);
    EXPECT_EQ(no_glass.stats.refraction, 0u);

    Scene matte_only = opaque;
    for (Material& m : matte_only.materials) m.reflectivity = Color::Zero();
    const RenderResult no_mirrors = render(matte_only, opt);
    EXPECT_EQ(no_mirrors.stats.reflection, 0u);
    EXPECT_EQ(no_mirrors.stats.refraction, 0u);
    // Without the BVH, each primary ray queries every object and every visible light; a
    // shadow ray at most every object (it stops at the first opaque blocker; lights cast
    // no shadow); nothing else queries. The BVH asks no more than that.
    RenderOptions brute = opt;
    brute.trace.bvh = false;
    const RenderResult no_mirrors_brute = render(matte_only, brute);
    if (GetParam() == Mode::certified) {
        EXPECT_TRUE(no_mirrors_brute.image.rgb == no_mirrors.image.rgb);
    }
    std::size_t bulbs = 0;
    for (const Light& l : s.lights) bulbs += l.visible();
    EXPECT_GT(bulbs, 0u);
    const auto& st = no_mirrors_brute.stats;
    EXPECT_GE(st.kernel_queries, st.primary * (s.objects.size() + bulbs));
    EXPECT_LE(st.kernel_queries, st.primary * (s.objects.size() + bulbs) + st.shadow * s.objects.size());
    EXPECT_LE(no_mirrors.stats.kernel_queries, st.kernel_queries);
    // Without visible lights, the lights' spheres cost nothing.
    Scene points = matte_only;
    for (Light& l : points.lights) l.radius = 0;
    for (const RenderOptions& o : {opt, brute}) {
        const RenderResult no_bulbs = render(points, o);
        EXPECT_LE(no_bulbs.stats.kernel_queries, (no_bulbs.stats.primary + no_bulbs.stats.shadow) * s.objects.size());
    }
}

INSTANTIATE_TEST_SUITE_P(Modes, Media, ::testing::ValuesIn(every_mode()),
                         [](const auto& info) { return std::string(mode_name(info.param)); });

}  // namespace
}  // namespace rayproof::render::testing
