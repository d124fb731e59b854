// scene_fuzz.cpp — fuzz target: the tracer's scene-file parser (rayproof::render::parse_scene)
// on arbitrary bytes. Every input must give either a scene or a clear error, never a
// crash, an exception, a hang or a leak:
//   error  a non-empty message; syntax errors carry a 1-based line and column, schema
//          errors the path of the offending key and a 1-based line and column
//   scene  every material index in range, every shape valid for the kernel (its queries
//          never answer `invalid` for a valid ray), a finite camera, settings within the
//          documented limits; then a few primary rays of the scene are traced (2×2 pixels,
//          depth at most 3, a bounded number of lights and objects) so that whatever the
//          parser accepts also goes through the tracer under the sanitizers.
#include "fuzz_common.hpp"

#include <rayproof/io.hpp>
#include <rayproof/rayproof.hpp>
#include <rayproof/render/parse.hpp>
#include <rayproof/render/tracer.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <string_view>
#include <variant>

namespace {

using namespace rayproof;
using namespace rayproof::render;

[[noreturn]] void fail(const char* what, std::string_view text, const std::string& detail) {
    rayproof::fuzz::filter(what);
    std::cerr << "\n==== rayproof scene fuzz: " << what << "\n";
    if (!rayproof::fuzz::current_input().empty()) std::cerr << "input file: " << rayproof::fuzz::current_input() << '\n';
    std::cerr << detail << "\ninput (" << text.size() << " bytes, first 400):\n"
              << text.substr(0, 400) << '\n';
    std::cerr.flush();
    std::abort();
}

bool finite(const Vec3d& v) { return v.allFinite(); }

// True when the kernel accepts the shape (certified query of a fixed valid ray).
template <class S> bool shape_valid(const S& s) {
    const Ray<double> probe{Vec3d(0.25, 0.5, 0.75), Vec3d(1, 2, 3)};
    return intersect(probe, s, certified).verdict != Verdict::invalid;
}

// A polyhedron is asked through the kernel's view of its planes.
bool shape_valid(const Polyhedron& p) { return shape_valid(p.kernel()); }

void check_error(const ParseError& e, std::string_view text) {
    const std::string shown = e.to_string();
    if (e.message.empty() || shown.empty()) fail("error without a message", text, shown);
    if (e.kind == ParseError::Kind::syntax && (e.line < 1 || e.column < 1)) fail("syntax error without a position", text, shown);
    if (e.kind == ParseError::Kind::schema && e.key.empty()) fail("schema error without a key", text, shown);
    if (e.kind == ParseError::Kind::schema && (e.line < 1 || e.column < 1))
        fail("schema error without a position", text, shown);
    if (e.kind == ParseError::Kind::io) fail("io error from parse_scene", text, shown);
}

void check_scene(Scene s, std::string_view text) {
    if (!finite(s.camera.position) || !finite(s.camera.look_at) || !finite(s.camera.up) || !std::isfinite(s.camera.fov))
        fail("scene with a non-finite camera", text, "");
    const RenderSettings& r = s.settings;
    if (r.width < 1 || r.height < 1 || r.depth < 1 || r.supersample < 1 || !(r.min_contribution >= 0 && r.min_contribution <= 1))
        fail("scene with render settings out of range", text, "");
    for (std::size_t i = 0; i < s.objects.size(); ++i) {
        const Object& o = s.objects[i];
        if (o.material < 0 || std::size_t(o.material) >= s.materials.size())
            fail("object with a material index out of range", text, "object " + std::to_string(i));
        if (!std::visit([](const auto& shape) { return shape_valid(shape); }, o.shape))
            fail("scene accepted with a shape the kernel rejects as invalid", text, "object " + std::to_string(i));
    }
    for (const Light& l : s.lights)
        if (!finite(l.position)) fail("light with a non-finite position", text, "");

    // Trace a few primary rays through a bounded copy of the scene.
    if (s.lights.size() > 8) s.lights.resize(8);
    if (s.objects.size() > 32) s.objects.resize(32);
    s.settings.width = s.settings.height = 2;
    s.settings.supersample = 1;
    s.settings.depth = std::min(s.settings.depth, 3);
    for (double py : {0.5, 1.5})
        for (double px : {0.5, 1.5}) (void)radiance(s, px, py);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const ParseResult r = parse_scene(text, "fuzz.json");
    try {
        if (r.scene) check_scene(*r.scene, text);
        else check_error(r.error, text);
    } catch (const rayproof::fuzz::Filtered&) {
    }
    return 0;
}
