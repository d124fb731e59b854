// Shared by the tracer's tests: building small scenes in code, the list of modes (every
// mode: the kernel answers each shape in each), and scratch-file paths.
#pragma once

#include <rayproof/render/parse.hpp>
#include <rayproof/render/tracer.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <filesystem>
#include <iterator>
#include <string>
#include <vector>

namespace rayproof::render {
// GoogleTest prints test parameters with this (found by argument-dependent lookup).
inline void PrintTo(Mode m, std::ostream* os) { *os << mode_name(m); }
}  // namespace rayproof::render

namespace rayproof::render::testing {

// Every mode, in the order of all_modes, as a vector for the parameterized tests.
inline std::vector<Mode> every_mode() { return {std::begin(all_modes), std::end(all_modes)}; }

inline std::string scene_path(const std::string& name) { return std::string(RAYPROOF_SCENES_DIR) + "/" + name; }

inline Scene load_or_die(const std::string& path) {
    ParseResult r = load_scene(path);
    if (!r) ADD_FAILURE() << r.error.to_string();
    return r ? *r.scene : Scene{};
}

inline Scene parse_or_die(const std::string& text) {
    ParseResult r = parse_scene(text, "test.json");
    if (!r) ADD_FAILURE() << r.error.to_string();
    return r ? *r.scene : Scene{};
}

// A scratch file name in the test's working directory, unique per test.
inline std::string scratch(const std::string& suffix) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "_" + info->name() + "_" + suffix;
    for (char& c : name)
        if (c == '/') c = '_';
    return (std::filesystem::temp_directory_path() / ("rayproof_render_" + name)).string();
}

// EXPECT_TRUE(same_color(a, b)): exact equality of all three channels, printed on failure.
inline ::testing::AssertionResult same_color(const Color& a, const Color& b) {
    if ((a == b).all()) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "(" << a.transpose() << ") != (" << b.transpose() << ")";
}

// Every channel of got within tol of want (an absolute tolerance: the hand-worked colours
// of the lighting tests are O(1), and 1e-12 leaves room for a few roundings).
inline void expect_color(const Color& got, const Color& want, double tol = 1e-12) {
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], tol) << "channel " << i;
}

inline Material matte(Color kd, Color ka = Color::Zero()) {
    Material m;
    m.diffuse = kd;
    m.ambient = ka;
    return m;
}

// A scene with one material per object, in the given mode.
inline Scene scene_with(Camera cam, int w, int h, Mode mode) {
    Scene s;
    s.camera = cam;
    s.settings.width = w;
    s.settings.height = h;
    s.settings.mode = mode;
    return s;
}

inline int add(Scene& s, Shape shape, const Material& m) {
    s.materials.push_back(m);
    Object o;
    o.shape = shape;
    o.material = int(s.materials.size()) - 1;
    s.objects.push_back(o);
    return int(s.objects.size()) - 1;
}

}  // namespace rayproof::render::testing
