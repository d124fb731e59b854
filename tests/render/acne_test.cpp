// Shadow acne: a lit surface with nothing that could shadow it (a tilted plane, the top
// face of a box, a face of an oriented box, a large ball), rendered in every mode. Every
// shadow ray that finds its light blocked is then a self-intersection, and shows as a
// speckle: a surface pixel less than half as bright as its brightest neighbour.
//   error-bound offset: no blocked shadow ray and no speckle, near the origin and with
//     the scene moved out to 2^42 (doubles 2^-10 apart), every surface, every mode.
//   naive fixed t_min = 1e-4 (the usual "small epsilon"), scene at 2^42: acne on the
//     tilted plane, the oriented face and the ball in every mode — a fixed epsilon does
//     not scale. (The box's top face lies on a coordinate plane: o + t·d rounds exactly
//     onto it there, so it shows none — but with t_min = 0 every shadow ray starts on
//     the closed box and all its pixels are shadowed.)
//   the far side: a translucent sheet lit from behind sends its shadow rays from the
//     side the eye does not see; none is blocked either.
//   naive t_min = 0 near the origin: acne on every surface in the fast and certified
//     modes. (Not asserted for conservative: its t_enter is a lower bound, which puts
//     the computed point in front of the surface.)
#include "render_support.hpp"

#include <algorithm>
#include <vector>

namespace rayproof::render::testing {
namespace {

constexpr int W = 48, H = 36;

struct Acne {
    int surface = 0;   // pixels whose primary ray met the surface and cast a shadow ray
    int shadowed = 0;  // of those, pixels whose shadow ray found the light blocked
    int speckles = 0;  // surface pixels darker than half their brightest surface neighbour
};

Acne count(const Scene& s, const TraceOptions& opt) {
    std::vector<double> lum(W * H, -1);
    Acne a;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            Stats st;
            const auto c = radiance(s, x + 0.5, y + 0.5, opt, &st);
            if (st.shadow == 0) continue;
            ++a.surface;
            if (st.shadowed) ++a.shadowed;
            lum[y * W + x] = c.mean();
        }
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const double l = lum[y * W + x];
            if (l < 0) continue;
            double brightest = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx >= 0 && xx < W && yy >= 0 && yy < H) brightest = std::max(brightest, lum[yy * W + xx]);
                }
            if (l < 0.5 * brightest) ++a.speckles;
        }
    return a;
}

enum class Surface { plane, box_top, obb_face, ball };
const char* name(Surface s) {
    switch (s) {
        case Surface::plane: return "plane";
        case Surface::box_top: return "box_top";
        case Surface::obb_face: return "obb_face";
        case Surface::ball: return "ball";
    }
    return "?";
}

// The surface fills most of the view; the light is high above it. `at` moves the
// whole scene (eye, light, surface).
Scene lit_surface(Surface kind, Mode mode, const Vec3d& at) {
    Scene s = scene_with(Camera{at + Vec3d(0.3, 3, 2.5), at, {0, 1, 0}, 50}, W, H, mode);
    s.settings.depth = 1;
    s.ambient_light = Color::Constant(0.05);
    s.lights.push_back(Light{at + Vec3d(-1, 8, 2), Color(1, 1, 1), 1, 0, 0});
    const Material m = matte(Color(0.7, 0.7, 0.7), Color(1, 1, 1));
    switch (kind) {
        case Surface::plane: {
            const Vec3d n(0.1, 1, 0.05);
            add(s, Plane<double>{n, n.dot(at)}, m);
            break;
        }
        case Surface::box_top:
            add(s, Aabb<double>{at - Vec3d(6, 1, 6), at + Vec3d(6, 0.5, 6)}, m);
            break;
        case Surface::obb_face: {
            Obb<double> b;
            b.center = at;
            b.axes = Eigen::Matrix3d(Eigen::AngleAxisd(0.3, Vec3d(1, 0, 1).normalized()));
            b.half_extent = Vec3d(5, 0.5, 5);
            add(s, b, m);
            break;
        }
        case Surface::ball:
            add(s, Sphere<double>{at - Vec3d(0, 20, 0), 20}, m);
            break;
    }
    return s;
}

struct Case {
    Surface surface;
    Mode mode;
};

void PrintTo(const Case& c, std::ostream* os) { *os << name(c.surface) << "/" << mode_name(c.mode); }

class ShadowAcne : public ::testing::TestWithParam<Case> {};

TEST_P(ShadowAcne, ErrorBoundOffsetHasNoneNaiveTminHasSome) {
    const auto [kind, mode] = GetParam();
    const Vec3d origin = Vec3d::Zero(), far = Vec3d::Constant(0x1p42);

    const Acne bound_near = count(lit_surface(kind, mode, origin), TraceOptions{});
    const Acne bound_far = count(lit_surface(kind, mode, far), TraceOptions{});
    EXPECT_GT(bound_near.surface, W * H / 2);
    EXPECT_GT(bound_far.surface, W * H / 2);
    EXPECT_EQ(bound_near.shadowed, 0);
    EXPECT_EQ(bound_near.speckles, 0);
    EXPECT_EQ(bound_far.shadowed, 0);
    EXPECT_EQ(bound_far.speckles, 0);

    if (kind == Surface::box_top) {
        const Acne on_face = count(lit_surface(kind, mode, far), TraceOptions{OffsetPolicy::naive, 0.0});
        EXPECT_EQ(on_face.shadowed, on_face.surface);
    } else {
        const Acne naive_eps = count(lit_surface(kind, mode, far), TraceOptions{OffsetPolicy::naive, 1e-4});
        EXPECT_GT(naive_eps.shadowed, 0);
        EXPECT_GT(naive_eps.speckles, 0);
    }
    if (mode != Mode::conservative) {
        const Acne naive_zero = count(lit_surface(kind, mode, origin), TraceOptions{OffsetPolicy::naive, 0.0});
        EXPECT_GT(naive_zero.shadowed, 0);
        EXPECT_GT(naive_zero.speckles, 0);
    }
}

std::vector<Case> cases() {
    std::vector<Case> v;
    for (Surface s : {Surface::plane, Surface::box_top, Surface::obb_face, Surface::ball})
        for (Mode m : every_mode()) v.push_back({s, m});
    return v;
}

INSTANTIATE_TEST_SUITE_P(Surfaces, ShadowAcne, ::testing::ValuesIn(cases()), [](const auto& info) {
    return std::string(name(info.param.surface)) + "_" + mode_name(info.param.mode);
});

// The far side: a translucent sheet (the tilted plane) lit only from below, so every
// shadow ray leaves on the side the eye does not see. With the error-bound offset none
// finds its light blocked, near the origin and at 2^42, in every mode.
class FarSideAcne : public ::testing::TestWithParam<Mode> {};

TEST_P(FarSideAcne, TranslucentSheetLitFromBehindHasNone) {
    for (const Vec3d& at : {Vec3d::Zero().eval(), Vec3d::Constant(0x1p42).eval()}) {
        SCOPED_TRACE(at.x());
        Scene s = lit_surface(Surface::plane, GetParam(), at);
        s.lights[0].position = at + Vec3d(-1, -8, 2);
        s.materials[0].translucency = 1;
        const Acne a = count(s, TraceOptions{});
        EXPECT_GT(a.surface, W * H / 2);
        EXPECT_EQ(a.shadowed, 0);
        EXPECT_EQ(a.speckles, 0);
    }
}

INSTANTIATE_TEST_SUITE_P(Modes, FarSideAcne, ::testing::ValuesIn(every_mode()),
                         [](const auto& info) { return std::string(mode_name(info.param)); });

}  // namespace
}  // namespace rayproof::render::testing
