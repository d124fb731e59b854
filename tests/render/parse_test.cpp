// Scene files: the example scenes parse; a full scene maps onto the Scene fields
// (defaults included, the cube, the oriented box's rotation, a plane given by a point,
// inline materials); and every class of bad input gives its own message — a missing
// file, syntax errors with their line and column, nesting too deep, and schema errors
// naming the key path and what was expected (missing key, wrong type, out of range,
// unknown key, unknown type, material or mode, inconsistent geometry); the example in
// the schema's documentation parses.
#include "render_support.hpp"

#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>

namespace rayproof::render::testing {
namespace {

const char* const minimal = R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]}, "objects": []})";

TEST(SceneFiles, ExampleScenesParse) {
    for (const char* name : {"default.json", "cube.json", "hostile.json", "notes.json"}) {
        const ParseResult r = load_scene(scene_path(name));
        EXPECT_TRUE(r) << r.error.to_string();
    }
}

TEST(SceneFiles, FieldsAndDefaults) {
    const Scene s = parse_or_die(R"({
      "camera": {"position": [1, 2, 3], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 30},
      "render": {"width": 20, "height": 10, "depth": 3, "supersample": 2, "mode": "conservative",
                 "background": 0.5, "min_contribution": 0.01},
      "ambient_light": [0.1, 0.2, 0.3],
      "lights": [{"position": [0, 5, 0], "color": [1, 0.5, 0.25], "attenuation": [1, 0.5, 0.25]},
                 {"position": [1, 1, 1]}],
      "materials": {"m": {"diffuse": [0.5, 0.6, 0.7], "specular": 0.2, "shininess": 8, "highlight": "blinn",
                          "reflectivity": [0.1, 0.2, 0.3], "transparency": 0.5, "ior": 1.33, "comment": "ok"}},
      "objects": [
        {"type": "cube", "side": 2, "material": "m"},
        {"type": "cube", "side": 1, "center": [5, 5, 5], "material": "m"},
        {"type": "oriented_box", "center": [1, 2, 3], "size": [2, 4, 6], "rotation": [0, 90, 0], "material": "m"},
        {"type": "plane", "normal": [0, 2, 0], "point": [7, 3, 9], "material": {"diffuse": 1}},
        {"type": "sphere", "name": "ball", "center": [0, 1, 0], "radius": 0.5, "material": "m"},
        {"type": "box", "min": [-1, -2, -3], "max": [1, 2, 3], "material": "m"}
      ]})");
    EXPECT_EQ(s.camera.up, Vec3d(0, 0, 1));
    EXPECT_EQ(s.camera.fov, 30);
    EXPECT_EQ(s.settings.width, 20);
    EXPECT_EQ(s.settings.supersample, 2);
    EXPECT_EQ(s.settings.mode, Mode::conservative);
    EXPECT_EQ(s.settings.background[1], 0.5);
    ASSERT_EQ(s.lights.size(), 2u);
    EXPECT_EQ(s.lights[0].c3, 0.25);
    EXPECT_TRUE(same_color(s.lights[1].color, Color(1, 1, 1)));  // defaults
    EXPECT_EQ(s.lights[1].c1, 1);
    ASSERT_EQ(s.materials.size(), 2u);  // "m" and the inline one
    EXPECT_TRUE(same_color(s.materials[0].ambient, s.materials[0].diffuse));  // K_a defaults to K_d
    EXPECT_EQ(s.materials[0].highlight, Highlight::blinn);
    EXPECT_EQ(s.materials[0].ior, 1.33);
    ASSERT_EQ(s.objects.size(), 6u);
    const auto& cube = std::get<Aabb<double>>(s.objects[0].shape);
    EXPECT_EQ(cube.lo, Vec3d(-1, -1, -1));
    EXPECT_EQ(cube.hi, Vec3d(1, 1, 1));
    EXPECT_EQ(std::get<Aabb<double>>(s.objects[1].shape).lo, Vec3d(4.5, 4.5, 4.5));
    const auto& obb = std::get<Obb<double>>(s.objects[2].shape);
    EXPECT_EQ(obb.half_extent, Vec3d(1, 2, 3));
    EXPECT_NEAR((obb.axes.col(0) - Vec3d(0, 0, -1)).norm(), 0, 1e-15);  // x turned 90° about y
    const auto& plane = std::get<Plane<double>>(s.objects[3].shape);
    EXPECT_EQ(plane.offset, 6);  // (0,2,0)·(7,3,9)
    EXPECT_EQ(s.objects[3].material, 1);
    EXPECT_EQ(s.objects[4].name, "ball");
}

struct Bad {
    const char* what;
    std::string text;
    ParseError::Kind kind;
    std::string key;      // schema errors: the key path
    int line, column;     // syntax errors
    std::string message;  // a fragment of the message
};

void PrintTo(const Bad& b, std::ostream* os) { *os << b.what; }

std::string with_objects(const std::string& objects) {
    return R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]}, "materials": {"m": {}}, "objects": [)" +
           objects + "]}";
}

class BadScene : public ::testing::TestWithParam<Bad> {};

TEST_P(BadScene, SaysWhatAndWhere) {
    const Bad& b = GetParam();
    const ParseResult r = parse_scene(b.text, "bad.json");
    ASSERT_FALSE(r) << b.what;
    const ParseError& e = r.error;
    EXPECT_EQ(e.kind, b.kind);
    EXPECT_EQ(e.source, "bad.json");
    EXPECT_NE(e.message.find(b.message), std::string::npos) << e.to_string();
    if (b.kind == ParseError::Kind::syntax) {
        EXPECT_EQ(e.line, b.line) << e.to_string();
        EXPECT_EQ(e.column, b.column) << e.to_string();
        EXPECT_EQ(e.to_string().rfind("bad.json:" + std::to_string(b.line) + ":" + std::to_string(b.column) +
                                          ": syntax error: ",
                                      0),
                  0u)
            << e.to_string();
    } else {
        EXPECT_EQ(e.key, b.key) << e.to_string();
        EXPECT_EQ(e.to_string().rfind("bad.json: " + b.key + ": ", 0), 0u) << e.to_string();
    }
}

using K = ParseError::Kind;
const Bad bad_cases[] = {
    {"empty input", "", K::syntax, "", 1, 1, "unexpected end of input"},
    {"value missing", "{\n  \"camera\": }", K::syntax, "", 2, 13, "unexpected '}'"},
    {"trailing comma", "{\"a\": 1,\n}", K::syntax, "", 2, 1, "expected string literal"},
    {"unterminated string", "{\n\n  \"camera", K::syntax, "", 3, 10, "missing closing quote"},
    {"garbage", "\x01\x02", K::syntax, "", 1, 1, "invalid literal"},
    {"nesting", std::string(100, '['), K::syntax, "", 1, 65, "nested more than 64 deep"},
    {"not an object", "[1, 2]", K::schema, "(top level)", 0, 0, "expected an object, got an array"},
    {"no camera", R"({"objects": []})", K::schema, "camera", 0, 0, "missing (required)"},
    {"no objects", R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}})", K::schema, "objects", 0, 0,
     "missing (required)"},
    {"unknown top-level key", R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "object": []})", K::schema,
     "object", 0, 0, "unknown key (expected one of: camera, render, ambient_light, lights, materials, objects"},
    {"vector of 2", R"({"camera": {"position": [0,0], "look_at": [0,0,0]}, "objects": []})", K::schema,
     "camera.position", 0, 0, "expected an array of 3 numbers"},
    {"string for number", R"({"camera": {"position": [0,"0",5], "look_at": [0,0,0]}, "objects": []})", K::schema,
     "camera.position[1]", 0, 0, "expected a number, got a string \"0\""},
    {"eye at target", R"({"camera": {"position": [1,2,3], "look_at": [1,2,3]}, "objects": []})", K::schema,
     "camera.look_at", 0, 0, "must differ from camera.position"},
    {"up along view", R"({"camera": {"position": [0,5,0], "look_at": [0,0,0]}, "objects": []})", K::schema, "camera.up",
     0, 0, "parallel to the view direction"},
    {"fov 180", R"({"camera": {"position": [0,0,5], "look_at": [0,0,0], "fov": 180}, "objects": []})", K::schema,
     "camera.fov", 0, 0, "in [0.001, 179]"},
    {"huge number", R"({"camera": {"position": [0,0,1e200], "look_at": [0,0,0]}, "objects": []})", K::schema,
     "camera.position[2]", 0, 0, "magnitude at most 1e100"},
    {"width 0", R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "render": {"width": 0}, "objects": []})",
     K::schema, "render.width", 0, 0, "expected an integer from 1 to 16384, got 0"},
    {"fractional height",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "render": {"height": 2.5}, "objects": []})", K::schema,
     "render.height", 0, 0, "expected an integer"},
    {"too many pixels",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "render": {"width": 16384, "height": 16384}, "objects": []})",
     K::schema, "render.height", 0, 0, "at most 67108864 pixels"},
    {"bad mode", R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "render": {"mode": "exact"}, "objects": []})",
     K::schema, "render.mode", 0, 0, "expected \"fast\", \"conservative\" or \"certified\", got \"exact\""},
    {"negative light colour",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "lights": [{"position": [0,1,0], "color": [1,-1,1]}], "objects": []})",
     K::schema, "lights[0].color", 0, 0, "every channel >= 0"},
    {"negative attenuation",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "lights": [{"position": [0,1,0], "attenuation": [1,-1,0]}], "objects": []})",
     K::schema, "lights[0].attenuation", 0, 0, "every coefficient >= 0"},
    {"reflectivity above 1",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "materials": {"m": {"reflectivity": 1.5}}, "objects": []})",
     K::schema, "materials.m.reflectivity", 0, 0, "every channel in [0, 1]"},
    {"bad highlight",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "materials": {"m": {"highlight": "gouraud"}}, "objects": []})",
     K::schema, "materials.m.highlight", 0, 0, "expected \"phong\" or \"blinn\""},
    {"typo in material key",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "materials": {"m": {"difuse": 1}}, "objects": []})",
     K::schema, "materials.m.difuse", 0, 0, "unknown key (expected one of: ambient, diffuse"},
    {"objects not an array",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "objects": {"type": "sphere"}})", K::schema, "objects", 0,
     0, "expected an array of objects, got an object"},
    {"no type", with_objects(R"({"center": [0,0,0], "radius": 1, "material": "m"})"), K::schema, "objects[0].type", 0,
     0, "missing (required)"},
    {"unknown type", with_objects(R"({"type": "torus", "material": "m"})"), K::schema, "objects[0].type", 0, 0,
     "got \"torus\""},
    {"typo in sphere key", with_objects(R"({"type": "sphere", "center": [0,0,0], "radus": 1, "material": "m"})"),
     K::schema, "objects[0].radus", 0, 0, "unknown key (expected one of: type, name, material, center, radius)"},
    {"negative radius", with_objects(R"({"type": "sphere", "center": [0,0,0], "radius": -1, "material": "m"})"),
     K::schema, "objects[0].radius", 0, 0, "expected a radius >= 0, got -1"},
    {"no material", with_objects(R"({"type": "sphere", "center": [0,0,0], "radius": 1})"), K::schema,
     "objects[0].material", 0, 0, "missing (required)"},
    {"unknown material", with_objects(R"({"type": "sphere", "center": [0,0,0], "radius": 1, "material": "gold"})"),
     K::schema, "objects[0].material", 0, 0, "unknown material \"gold\" (defined: m)"},
    {"material of wrong kind", with_objects(R"({"type": "sphere", "center": [0,0,0], "radius": 1, "material": 3})"),
     K::schema, "objects[0].material", 0, 0, "expected a material name or a material object"},
    {"inverted box",
     with_objects(R"({"type": "box", "min": [0,0,0], "max": [1,1,1], "material": "m"},
                     {"type": "box", "min": [0,2,0], "max": [1,1,1], "material": "m"})"),
     K::schema, "objects[1].max", 0, 0, "must be >= the one of min"},
    {"negative size", with_objects(R"({"type": "oriented_box", "center": [0,0,0], "size": [1,-1,1], "material": "m"})"),
     K::schema, "objects[0].size", 0, 0, "expected 3 numbers >= 0"},
    {"zero normal", with_objects(R"({"type": "plane", "normal": [0,0,0], "offset": 1, "material": "m"})"), K::schema,
     "objects[0].normal", 0, 0, "must not be the zero vector"},
    {"plane offset and point",
     with_objects(R"({"type": "plane", "normal": [0,1,0], "offset": 1, "point": [0,0,0], "material": "m"})"),
     K::schema, "objects[0].offset", 0, 0, "give exactly one of"},
    {"object not an object", with_objects("42"), K::schema, "objects[0]", 0, 0, "expected an object, got a number"},
};

INSTANTIATE_TEST_SUITE_P(Classes, BadScene, ::testing::ValuesIn(bad_cases), [](const auto& info) {
    std::string n = info.param.what;
    for (char& c : n)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return n;
});

TEST(SceneFiles, MissingFileIsAnIoError) {
    const ParseResult r = load_scene("/nonexistent/dir/scene.json");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error.kind, ParseError::Kind::io);
    EXPECT_EQ(r.error.to_string(), "/nonexistent/dir/scene.json: cannot open the file");
}

// The example in the schema's documentation parses and renders.
TEST(SceneFiles, DocumentedExampleParses) {
    std::ifstream in(scene_path("README.md"));
    const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto begin = doc.find("```json\n"), end = doc.find("```", begin + 8);
    ASSERT_NE(begin, std::string::npos);
    ASSERT_NE(end, std::string::npos);
    Scene s = parse_or_die(doc.substr(begin + 8, end - begin - 8));
    EXPECT_EQ(s.objects.size(), 2u);
    s.settings.width = 8;
    s.settings.height = 6;
    const Image img = render(s).image;
    EXPECT_EQ(img.width, 8);
    EXPECT_EQ(img.height, 6);
}

TEST(SceneFiles, MinimalSceneGetsDefaults) {
    const Scene s = parse_or_die(minimal);
    EXPECT_EQ(s.settings.width, 320);
    EXPECT_EQ(s.settings.mode, Mode::fast);
    EXPECT_EQ(s.camera.up, Vec3d(0, 1, 0));
    EXPECT_TRUE(s.objects.empty());
}

}  // namespace
}  // namespace rayproof::render::testing
