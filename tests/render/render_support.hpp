// Shared by the tracer's tests: building small scenes in code, the list of modes (every
// mode: the kernel answers each shape in each), and scratch-file paths.
#pragma once

#include <rayproof/render/parse.hpp>
#include <rayproof/render/tracer.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <random>
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

// A scene file of n objects drawn with the seed: spheres, boxes, cubes, oriented boxes,
// one plane in 1,000 and one preset polyhedron in 500, scattered in a cube of side
// `spread` in front of the camera, with opaque, mirror and glass materials, two lights
// (one visible, radius 0.5). Coordinates are multiples of 1/64, so that every number is
// read back exactly. kinds[i] is object i's "type".
struct GeneratedScene {
    std::string text;
    std::vector<std::string> kinds;
};
inline GeneratedScene generated_scene(std::size_t n, std::uint64_t seed, double spread = 100) {
    std::mt19937_64 rng(seed);
    const auto coord = [&](double range) {
        return double(std::int64_t(std::uniform_int_distribution<std::int64_t>(-32, 32)(rng) * range)) / 64;
    };
    const auto size = [&](int lo, int hi) { return double(std::uniform_int_distribution<int>(lo, hi)(rng)) / 64; };
    const auto vec = [](double x, double y, double z) {
        char b[128];
        std::snprintf(b, sizeof b, "[%.17g, %.17g, %.17g]", x, y, z);
        return std::string(b);
    };
    GeneratedScene g;
    g.text = "{\"camera\": {\"position\": [0, 0, " + std::to_string(int(spread * 1.2)) +
             "], \"look_at\": [0, 0, 0], \"fov\": 50},\n"
             "\"lights\": [{\"position\": " + vec(spread, spread, spread) + "},"
             " {\"position\": " + vec(-spread / 2, spread / 4, spread / 2) + ", \"color\": [0.5, 0.5, 0.6], \"radius\": 0.5}],\n"
             "\"materials\": {\"red\": {\"diffuse\": [0.8, 0.2, 0.2], \"specular\": 0.3},"
             " \"mirror\": {\"diffuse\": 0.2, \"reflectivity\": 0.6},"
             " \"glass\": {\"diffuse\": 0.1, \"transparency\": 0.7, \"ior\": 1.5},"
             " \"sheet\": {\"diffuse\": [0.3, 0.5, 0.3], \"transparency\": 0.4, \"translucency\": 0.5}},\n"
             "\"objects\": [\n";
    static const char* materials[] = {"red", "mirror", "glass", "red"};
    for (std::size_t i = 0; i < n; ++i) {
        const double x = coord(spread), y = coord(spread), z = coord(spread);
        const std::string m = materials[std::uniform_int_distribution<int>(0, 3)(rng)];
        std::string o;
        std::string kind;
        if (i % 1000 == 999) {
            kind = "plane";
            o = "{\"type\": \"plane\", \"normal\": " + vec(size(-8, 8), 1, size(-8, 8)) + ", \"point\": " +
                vec(0, -spread / 2, 0) + ", \"material\": \"sheet\"}";
        } else if (i % 500 == 499) {
            kind = "polyhedron";
            static const char* presets[] = {"tetrahedron", "octahedron", "prism", "cube", "dodecahedron"};
            o = std::string("{\"type\": \"polyhedron\", \"preset\": \"") + presets[(i / 500) % 5] +
                "\", \"center\": " + vec(x, y, z) + ", \"size\": 0.75, \"material\": \"" + m + "\"}";
        } else {
            switch (i % 4) {
                case 0:
                    kind = "sphere";
                    o = "{\"type\": \"sphere\", \"center\": " + vec(x, y, z) + ", \"radius\": " +
                        std::to_string(size(8, 64)) + ", \"material\": \"" + m + "\"}";
                    break;
                case 1:
                    kind = "box";
                    o = "{\"type\": \"box\", \"min\": " + vec(x, y, z) + ", \"max\": " +
                        vec(x + size(8, 64), y + size(8, 64), z + size(8, 64)) + ", \"material\": \"" + m + "\"}";
                    break;
                case 2:
                    kind = "cube";
                    o = "{\"type\": \"cube\", \"center\": " + vec(x, y, z) + ", \"side\": " +
                        std::to_string(size(8, 64)) + ", \"material\": \"" + m + "\"}";
                    break;
                default:
                    kind = "oriented_box";
                    o = "{\"type\": \"oriented_box\", \"center\": " + vec(x, y, z) + ", \"size\": " +
                        vec(size(8, 64), size(8, 64), size(8, 64)) + ", \"rotation\": " +
                        vec(size(0, 5760), size(0, 5760), size(0, 5760)) + ", \"material\": \"" + m + "\"}";
                    break;
            }
        }
        g.text += o;
        g.text += i + 1 < n ? ",\n" : "\n";
        g.kinds.push_back(kind);
    }
    g.text += "]}\n";
    return g;
}

}  // namespace rayproof::render::testing
