// Scene files: the example scenes parse; a full scene maps onto the Scene fields
// (defaults included, the cube, the oriented box's rotation, a plane given by a point,
// inline materials); and every class of bad input gives its own message — a missing
// file, syntax errors with their line and column, nesting too deep, and schema errors
// naming the key path and what was expected (missing key, wrong type, out of range,
// unknown key, unknown type, material or mode, inconsistent geometry), each with the
// line and column of the offending value (of the key for an unknown key, of the object
// for a missing one), numbers that overflow a double, duplicate keys anywhere, and scene
// paths that are a directory, a fifo or too large a file; the example in the schema's
// documentation parses.
#include "render_support.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <thread>

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
    std::string at = "";  // schema errors: what the text holds at the error's line and column
};

// The byte offset of a 1-based line and column (columns count bytes), or npos when the
// text has no such place.
std::size_t offset_of(const std::string& text, int line, int column) {
    if (line < 1 || column < 1) return std::string::npos;
    std::size_t begin = 0;
    for (int l = 1; l < line; ++l) {
        begin = text.find('\n', begin);
        if (begin == std::string::npos) return begin;
        ++begin;
    }
    const std::size_t end = std::min(text.find('\n', begin), text.size());
    return begin + std::size_t(column - 1) <= end ? begin + std::size_t(column - 1) : std::string::npos;
}

// What the text holds from the error's position on (at most n bytes), or a note.
std::string text_at(const std::string& text, const ParseError& e, std::size_t n) {
    const std::size_t at = offset_of(text, e.line, e.column);
    return at == std::string::npos ? "(no such place in the text)" : text.substr(at, n);
}

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
        EXPECT_EQ(e.to_string().rfind("bad.json:" + std::to_string(e.line) + ":" + std::to_string(e.column) + ": " +
                                          b.key + ": ",
                                      0),
                  0u)
            << e.to_string();
        ASSERT_FALSE(b.at.empty()) << "the case names what the error points at";
        EXPECT_EQ(text_at(b.text, e, b.at.size()), b.at) << e.to_string();
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
    {"NUL after the value", std::string(minimal) + "\n  " + std::string(1, '\0') + "}", K::syntax, "", 2, 3,
     "unexpected NUL byte after the JSON value"},
    {"not an object", "[1, 2]", K::schema, "(top level)", 0, 0, "expected an object, got an array", R"([1, 2])"},
    {"no camera", R"({"objects": []})", K::schema, "camera", 0, 0, "missing (required)", R"({"objects": []})"},
    {"no objects", R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}})", K::schema, "objects", 0, 0,
     "missing (required)", R"({"camera")"},
    {"unknown top-level key", R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "object": []})", K::schema,
     "object", 0, 0, "unknown key (expected one of: camera, render, ambient_light, lights, materials, objects", R"("object")"},
    {"vector of 2", R"({"camera": {"position": [0,0], "look_at": [0,0,0]}, "objects": []})", K::schema,
     "camera.position", 0, 0, "expected an array of 3 numbers", R"([0,0])"},
    {"string for number", R"({"camera": {"position": [0,"0",5], "look_at": [0,0,0]}, "objects": []})", K::schema,
     "camera.position[1]", 0, 0, "expected a number, got a string \"0\"", R"("0")"},
    {"eye at target", R"({"camera": {"position": [1,2,3], "look_at": [1,2,3]}, "objects": []})", K::schema,
     "camera.look_at", 0, 0, "must differ from camera.position", R"([1,2,3]})"},
    {"up along view", R"({"camera": {"position": [0,5,0], "look_at": [0,0,0]}, "objects": []})", K::schema, "camera.up",
     0, 0, "parallel to the view direction", R"({"position": [0,5,0])"},
    {"fov 180", R"({"camera": {"position": [0,0,5], "look_at": [0,0,0], "fov": 180}, "objects": []})", K::schema,
     "camera.fov", 0, 0, "in [0.001, 179]", R"(180)"},
    {"huge number", R"({"camera": {"position": [0,0,1e200], "look_at": [0,0,0]}, "objects": []})", K::schema,
     "camera.position[2]", 0, 0, "magnitude at most 1e100", R"(1e200)"},
    {"width 0", R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "render": {"width": 0}, "objects": []})",
     K::schema, "render.width", 0, 0, "expected an integer from 1 to 16384, got 0", R"(0})"},
    {"fractional height",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "render": {"height": 2.5}, "objects": []})", K::schema,
     "render.height", 0, 0, "expected an integer", R"(2.5)"},
    {"too many pixels",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "render": {"width": 16384, "height": 16384}, "objects": []})",
     K::schema, "render.height", 0, 0, "at most 67108864 pixels", R"(16384})"},
    {"bad mode", R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "render": {"mode": "exact"}, "objects": []})",
     K::schema, "render.mode", 0, 0, "expected \"fast\", \"conservative\" or \"certified\", got \"exact\"", R"("exact")"},
    {"negative light colour",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "lights": [{"position": [0,1,0], "color": [1,-1,1]}], "objects": []})",
     K::schema, "lights[0].color", 0, 0, "every channel >= 0", R"([1,-1,1])"},
    {"negative attenuation",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "lights": [{"position": [0,1,0], "attenuation": [1,-1,0]}], "objects": []})",
     K::schema, "lights[0].attenuation", 0, 0, "every coefficient >= 0", R"([1,-1,0])"},
    {"reflectivity above 1",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "materials": {"m": {"reflectivity": 1.5}}, "objects": []})",
     K::schema, "materials.m.reflectivity", 0, 0, "every channel in [0, 1]", R"(1.5)"},
    {"bad highlight",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "materials": {"m": {"highlight": "gouraud"}}, "objects": []})",
     K::schema, "materials.m.highlight", 0, 0, "expected \"phong\" or \"blinn\"", R"("gouraud")"},
    {"typo in material key",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "materials": {"m": {"difuse": 1}}, "objects": []})",
     K::schema, "materials.m.difuse", 0, 0, "unknown key (expected one of: ambient, diffuse", R"("difuse")"},
    {"objects not an array",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "objects": {"type": "sphere"}})", K::schema, "objects", 0,
     0, "expected an array of objects, got an object", R"({"type": "sphere"})"},
    {"no type", with_objects(R"({"center": [0,0,0], "radius": 1, "material": "m"})"), K::schema, "objects[0].type", 0,
     0, "missing (required)", R"({"center")"},
    {"unknown type", with_objects(R"({"type": "torus", "material": "m"})"), K::schema, "objects[0].type", 0, 0,
     "got \"torus\"", R"("torus")"},
    {"typo in sphere key", with_objects(R"({"type": "sphere", "center": [0,0,0], "radus": 1, "material": "m"})"),
     K::schema, "objects[0].radus", 0, 0, "unknown key (expected one of: type, name, material, center, radius)", R"("radus")"},
    {"negative radius", with_objects(R"({"type": "sphere", "center": [0,0,0], "radius": -1, "material": "m"})"),
     K::schema, "objects[0].radius", 0, 0, "expected a radius >= 0, got -1", R"(-1)"},
    {"no material", with_objects(R"({"type": "sphere", "center": [0,0,0], "radius": 1})"), K::schema,
     "objects[0].material", 0, 0, "missing (required)", R"({"type": "sphere", "center": [0,0,0], "radius": 1})"},
    {"unknown material", with_objects(R"({"type": "sphere", "center": [0,0,0], "radius": 1, "material": "gold"})"),
     K::schema, "objects[0].material", 0, 0, "unknown material \"gold\" (defined: m)", R"("gold")"},
    {"material of wrong kind", with_objects(R"({"type": "sphere", "center": [0,0,0], "radius": 1, "material": 3})"),
     K::schema, "objects[0].material", 0, 0, "expected a material name or a material object", R"(3})"},
    {"inverted box",
     with_objects(R"({"type": "box", "min": [0,0,0], "max": [1,1,1], "material": "m"},
                     {"type": "box", "min": [0,2,0], "max": [1,1,2], "material": "m"})"),
     K::schema, "objects[1].max", 0, 0, "must be >= the one of min", "[1,1,2]"},
    {"negative size", with_objects(R"({"type": "oriented_box", "center": [0,0,0], "size": [1,-1,1], "material": "m"})"),
     K::schema, "objects[0].size", 0, 0, "expected 3 numbers >= 0", R"([1,-1,1])"},
    {"zero normal", with_objects(R"({"type": "plane", "normal": [0,0,0], "offset": 1, "material": "m"})"), K::schema,
     "objects[0].normal", 0, 0, "must not be the zero vector", R"([0,0,0])"},
    {"plane offset and point",
     with_objects(R"({"type": "plane", "normal": [0,1,0], "offset": 1, "point": [0,0,0], "material": "m"})"),
     K::schema, "objects[0].offset", 0, 0, "give exactly one of", R"(1, "point")"},
    {"object not an object", with_objects("42"), K::schema, "objects[0]", 0, 0, "expected an object, got a number", R"(42)"},
    // Numbers that overflow a double: nlohmann-json stops without a position; the error has one.
    {"1e400", R"({"camera": {"position": [0,0,1e400], "look_at": [0,0,0]}, "objects": []})", K::schema,
     "camera.position[2]", 0, 0, "expected a finite number of magnitude at most 1e100, got 1e400", "1e400"},
    {"-1e400 after 1e400 in a string",
     R"({"description": "1e400 [", "camera": {"position": [0,0,5], "look_at": [0,-1e400,0]}, "objects": []})", K::schema,
     "camera.look_at[1]", 0, 0, "got -1e400", "-1e400"},
    {"integer of 400 digits",
     with_objects(R"({"type": "sphere", "center": [0,0,0], "radius": 1)" + std::string(400, '0') + "}"),
     K::schema, "objects[0].radius", 0, 0, "got 1" + std::string(36, '0') + "...", "1" + std::string(400, '0')},
    {"1e400 as the whole text", "1e400", K::schema, "(top level)", 0, 0, "got 1e400", "1e400"},
    {"1e400 before a syntax error", R"({"camera": {"position": [0,0,1e400] "look_at": })", K::schema,
     "camera.position[2]", 0, 0, "got 1e400", "1e400"},
    // Duplicate keys: the error names the key and points at its second occurrence.
    {"duplicate top-level key",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "objects": [], "camera": {}})", K::schema, "camera", 0, 0,
     "duplicate key (first given at line 1, column 2)", R"("camera": {})"},
    {"duplicate key in an object",
     with_objects(R"({"type": "sphere", "center": [0,0,0], "radius": 1, "material": "m"},
                     {"type": "sphere", "radius": 2, "center": [0,0,0], "radius": 3, "material": "m"})"),
     K::schema, "objects[1].radius", 0, 0, "duplicate key (first given at line 2, column 41)", R"("radius": 3)"},
    {"duplicate key spelt with an escape",
     with_objects(R"({"type": "sphere", "center": [0,0,0], "radius": 1, "r\u0061dius": 1, "material": "m"})"), K::schema,
     "objects[0].radius", 0, 0, "duplicate key", R"("r\u0061dius")"},
    {"duplicate material name",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0]}, "materials": {"m": {}, "n": {}, "m": {"diffuse": 1}}, "objects": []})",
     K::schema, "materials.m", 0, 0, "duplicate key", R"("m": {"diffuse")"},
    {"duplicate key in the camera",
     R"({"camera": {"position": [0,0,5], "look_at": [0,0,0], "up": [0,1,0], "up": [0,1,0]}, "objects": []})",
     K::schema, "camera.up", 0, 0, "duplicate key", R"("up": [0,1,0]})"},
    {"the earliest duplicate wins", R"({"a": {"b": 1, "c": 2, "b": 3}, "a": 4})", K::schema, "a.b", 0, 0,
     "duplicate key (first given at line 1, column 8)", R"("b": 3)"},
};

INSTANTIATE_TEST_SUITE_P(Classes, BadScene, ::testing::ValuesIn(bad_cases), [](const auto& info) {
    std::string n = info.param.what;
    for (char& c : n)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return n;
});

// The scan for duplicate keys keeps in step with real scene files to their last byte: a
// key given twice just before the final brace of each example scene is found there.
TEST(SceneFiles, DuplicateKeyAtTheEndOfEveryExampleIsFound) {
    for (const char* name : {"default.json", "cube.json", "hostile.json"}) {
        std::ifstream in(scene_path(name), std::ios::binary);
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const std::size_t end = text.rfind('}');
        ASSERT_NE(end, std::string::npos) << name;
        const std::string second = "\"zz\": [{\"a\": \"}\\\"\"}]";
        text.insert(end, ", \"zz\": 1,\n " + second + "\n");
        const ParseResult r = parse_scene(text, name);
        ASSERT_FALSE(r) << name;
        EXPECT_EQ(r.error.key, "zz") << r.error.to_string();
        EXPECT_EQ(text_at(text, r.error, second.size()), second) << r.error.to_string();
    }
}

TEST(SceneFiles, MissingFileIsAnIoError) {
    const ParseResult r = load_scene("/nonexistent/dir/scene.json");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error.kind, ParseError::Kind::io);
    EXPECT_EQ(r.error.to_string(), "/nonexistent/dir/scene.json: cannot open the file: No such file or directory");
}

// The documentation's example of a schema error, on a multi-line file: the value's line
// and column, counted from 1.
TEST(SceneFiles, SchemaErrorsGiveLineAndColumn) {
    const std::string text = "{\n"
                             "  \"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},\n"
                             "  \"materials\": {\"m\": {}},\n"
                             "  \"objects\": [\n"
                             "    {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"material\": \"m\"},\n"
                             "    {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"material\": \"m\"},\n"
                             "    {\"type\": \"sphere\",\n"
                             "     \"radius\":      -1, \"center\": [0, 0, 0], \"material\": \"m\"}\n"
                             "  ]\n"
                             "}\n";
    const ParseResult r = parse_scene(text, "scene.json");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error.to_string(), "scene.json:8:21: objects[2].radius: expected a radius >= 0, got -1");
}

// Seeded property: a scene of n objects written with random white space (spaces, tabs,
// line breaks) between the tokens, one value of one object broken in one of several
// ways: the error names that object's key and its line and column hold the broken value.
TEST(SceneFiles, EveryValueErrorPointsAtTheValue) {
    struct Breakage {
        const char* key;
        const char* value;
        const char* message;
    };
    const Breakage breakages[] = {{"radius", "-1", "expected a radius >= 0"},
                                  {"radius", "1e400", "expected a finite number"},
                                  {"radius", "\"1\"", "expected a number"},
                                  {"radius", "1e101", "magnitude at most 1e100"},
                                  {"center", "[0, 0]", "expected an array of 3 numbers"},
                                  {"material", "\"gold\"", "unknown material"},
                                  {"material", "7", "expected a material name"}};
    std::mt19937 rng(20261202);
    for (int trial = 0; trial < 300; ++trial) {
        const auto space = [&] {
            static const char* const ws[] = {"", " ", "  ", "\n", "\t", "\r\n", "\n    "};
            return std::string(ws[rng() % std::size(ws)]);
        };
        const int n = 1 + int(rng() % 12), broken = int(rng() % std::size_t(n));
        const Breakage& b = breakages[rng() % std::size(breakages)];
        std::string text = "{" + space() + "\"camera\":" + space() + R"({"position": [0, 0, 5], "look_at": [0, 0, 0]})" +
                           "," + space() + R"("materials": {"m": {}},)" + space() + "\"objects\":" + space() + "[";
        for (int i = 0; i < n; ++i) {
            std::string fields[] = {"\"type\":" + space() + "\"sphere\"", "\"center\":" + space() + "[1, 2, 3]",
                                    "\"radius\":" + space() + "0.5", "\"material\":" + space() + "\"m\""};
            if (i == broken)
                for (auto& f : fields)
                    if (f.rfind(std::string("\"") + b.key + "\"", 0) == 0)
                        f = std::string("\"").append(b.key).append("\":").append(space()).append(b.value);
            std::shuffle(std::begin(fields), std::end(fields), rng);
            // Appended piece by piece: g++ 12 warns falsely (-Wrestrict) on "literal" + std::string&&.
            text.append(i ? "," : "").append(space()).append("{").append(space());
            for (int k = 0; k < 4; ++k) {
                if (k) text.append(",").append(space());
                text.append(fields[k]).append(space());
            }
            text += "}";
        }
        text += space() + "]" + space() + "}";
        const ParseResult r = parse_scene(text, "random.json");
        ASSERT_FALSE(r) << "seed 20261202, trial " << trial << ":\n" << text;
        const std::string key = "objects[" + std::to_string(broken) + "]." + b.key;
        EXPECT_EQ(r.error.key, key) << "trial " << trial << ": " << r.error.to_string() << "\n" << text;
        EXPECT_NE(r.error.message.find(b.message), std::string::npos) << r.error.to_string();
        EXPECT_EQ(text_at(text, r.error, std::strlen(b.value)), b.value)
            << "seed 20261202, trial " << trial << ": " << r.error.to_string() << "\n" << text;
    }
}

// A directory, a fifo (which must not be waited on) and a file over the size limit are
// refused before reading, each with its own message.
TEST(SceneFiles, DirectoriesFifosAndHugeFilesAreRefused) {
    const std::filesystem::path dir = scratch("dir");
    std::filesystem::remove_all(dir);
    std::filesystem::create_directory(dir);
    ParseResult r = load_scene(dir.string());
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error.kind, ParseError::Kind::io);
    EXPECT_EQ(r.error.to_string(), dir.string() + ": is a directory, not a scene file");

    const std::string fifo = (dir / "fifo.json").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
    // Should load_scene block on the fifo, this writer opens it after 5 s and lets it go.
    std::atomic<bool> done{false};
    std::thread unblock([&] {
        for (int i = 0; i < 500 && !done; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
        if (done) return;
        const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
        if (fd >= 0) ::close(fd);
    });
    const auto start = std::chrono::steady_clock::now();
    r = load_scene(fifo);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    done = true;
    unblock.join();
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error.to_string(), fifo + ": is not a regular file (a fifo)");
    EXPECT_LT(seconds, 4.0) << "load_scene waited for a writer on the fifo";

    const std::string huge = (dir / "huge.json").string();
    std::ofstream(huge) << minimal;
    std::filesystem::resize_file(huge, 64'000'001);  // sparse: no disk space used
    r = load_scene(huge);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error.to_string(), huge + ": is 65 MB, over the limit of 64 MB for a scene file");
    std::filesystem::resize_file(huge, 64'000'000);  // at the limit: read, then rejected as JSON
    r = load_scene(huge);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error.to_string(), huge + ":1:" + std::to_string(std::strlen(minimal) + 1) +
                                       ": syntax error: unexpected NUL byte after the JSON value");
    std::filesystem::remove_all(dir);
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
