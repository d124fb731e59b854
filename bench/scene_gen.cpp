// bench/scene_gen.cpp — rayproof_scene_gen: writes a generated scene (bvh_scenes.hpp) as a
// tracer scene file (render/scenes/README.md), for the BVH timings of the trade run:
//
//   rayproof_scene_gen --kind mixed --objects 2000 --seed 1 -o mixed_2000.json
//   rayproof_scene_gen --kind spheres --objects 100000 --seed 1 -o spheres.json
//
// mixed: the field of spheres, boxes, rotated boxes, glass, chrome and mirror panels on a
// floor; spheres: the ray benchmark's sphere set (rayproof_bvh_bench builds the same balls
// from the same seed), seen from outside its cube. Both at 640×480, depth 5, certified,
// the ray tree's distance attenuation off (POV-Ray has none: the export is then exact up
// to the rounding of the rotated boxes' axes), lights without attenuation.
#include "bvh_scenes.hpp"

#include <rayproof/cli.hpp>

#include <charconv>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>

namespace {

using rayproof::bench::MixedScene;
using rayproof::bench::ObjectKind;
using rayproof::Vec3;

// The shortest decimal that reads back as the same double.
std::string num(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}
std::string vec(const Vec3<double>& v) { return "[" + num(v[0]) + ", " + num(v[1]) + ", " + num(v[2]) + "]"; }

// The head of a scene file: camera, render settings, lights, materials; then "objects": [.
std::string head(const std::string& description, const Vec3<double>& camera, const Vec3<double>& look_at,
                 double fov, const Vec3<double>& key, const Vec3<double>& fill) {
    std::string s = "{\n  \"description\": \"" + description + "\",\n";
    s += "  \"camera\": {\"position\": " + vec(camera) + ", \"look_at\": " + vec(look_at) + ", \"up\": [0, 1, 0], \"fov\": " +
         num(fov) + "},\n";
    s += "  \"render\": {\"width\": 640, \"height\": 480, \"depth\": 5, \"mode\": \"certified\", \"background\": [0.04, 0.05, "
         "0.09]},\n";
    s += "  \"tree_attenuation\": false,\n";
    s += "  \"ambient_light\": [0.12, 0.12, 0.14],\n";
    s += "  \"lights\": [\n";
    s += "    {\"name\": \"key\", \"position\": " + vec(key) + ", \"color\": [0.85, 0.75, 0.6]},\n";
    s += "    {\"name\": \"fill\", \"position\": " + vec(fill) + ", \"color\": [0.35, 0.42, 0.6]}\n  ],\n";
    s += R"(  "materials": {
    "floor": {"diffuse": [0.5, 0.49, 0.46], "specular": 0.15, "shininess": 40, "reflectivity": 0.1},
    "red": {"diffuse": [0.78, 0.16, 0.12], "specular": 0.35, "shininess": 60, "highlight": "blinn"},
    "orange": {"diffuse": [0.85, 0.45, 0.1], "specular": 0.3, "shininess": 40},
    "yellow": {"diffuse": [0.85, 0.75, 0.2], "specular": 0.2, "shininess": 30},
    "green": {"diffuse": [0.28, 0.68, 0.22]},
    "teal": {"diffuse": [0.1, 0.55, 0.52], "specular": 0.3, "shininess": 40},
    "blue": {"diffuse": [0.16, 0.25, 0.75], "specular": 0.5, "shininess": 90},
    "violet": {"diffuse": [0.5, 0.2, 0.65], "specular": 0.3, "shininess": 50},
    "white": {"diffuse": [0.8, 0.8, 0.78], "specular": 0.2, "shininess": 20},
    "chrome": {"diffuse": [0.12, 0.12, 0.13], "specular": 0.9, "shininess": 200, "reflectivity": 0.7},
    "mirror": {"diffuse": [0.04, 0.04, 0.05], "specular": 0.3, "shininess": 100, "reflectivity": 0.88},
    "glass": {"diffuse": [0.05, 0.05, 0.05], "ambient": 0, "specular": 0.9, "shininess": 300, "reflectivity": 0.08,
              "transparency": 0.88, "ior": 1.5}
  },
  "objects": [
)";
    return s;
}

void write_mixed(std::ostream& out, std::size_t n, std::uint64_t seed) {
    const MixedScene m = rayproof::bench::mixed_scene(n, seed);
    const double h = m.half_side;
    out << head("Generated (rayproof_scene_gen --kind mixed --objects " + std::to_string(n) + " --seed " +
                    std::to_string(seed) + "): spheres, boxes, rotated boxes, glass, chrome and mirrors on a floor.",
                m.camera, m.look_at, 50, Vec3<double>(rayproof::bench::milli(-0.5 * h), rayproof::bench::milli(0.6 * h + 10), rayproof::bench::milli(0.8 * h)),
                Vec3<double>(rayproof::bench::milli(0.6 * h), rayproof::bench::milli(0.4 * h + 8), rayproof::bench::milli(0.2 * h)));
    out << "    {\"type\": \"plane\", \"name\": \"floor\", \"normal\": [0, 1, 0], \"offset\": 0, \"material\": \"floor\"}";
    for (const auto& o : m.objects) {
        out << ",\n    ";
        switch (o.kind) {
            case ObjectKind::sphere:
                out << "{\"type\": \"sphere\", \"center\": " << vec(o.a) << ", \"radius\": " << num(o.b[0]);
                break;
            case ObjectKind::box:
                out << "{\"type\": \"box\", \"min\": " << vec(o.a) << ", \"max\": " << vec(o.b);
                break;
            case ObjectKind::oriented_box:
                out << "{\"type\": \"oriented_box\", \"center\": " << vec(o.a) << ", \"size\": " << vec(o.b)
                    << ", \"rotation\": " << vec(o.rotation);
                break;
        }
        out << ", \"material\": \"" << o.material << "\"}";
    }
    out << "\n  ]\n}\n";
}

void write_spheres(std::ostream& out, std::size_t n, std::uint64_t seed) {
    const auto spheres = rayproof::bench::sphere_set(n, seed);
    out << head("Generated (rayproof_scene_gen --kind spheres --objects " + std::to_string(n) + " --seed " +
                    std::to_string(seed) + "): the ray benchmark's balls in the cube [-50, 50]^3.",
                Vec3<double>(120, 70, 150), Vec3<double>(0, 0, 0), 40, Vec3<double>(100, 200, 150),
                Vec3<double>(-150, 50, 100));
    static const char* const colours[] = {"red", "orange", "yellow", "green", "teal", "blue", "violet", "white"};
    for (std::size_t i = 0; i < spheres.size(); ++i) {
        const auto& s = spheres[i];
        // Each float coordinate is written as the shortest decimal of its double value,
        // which reads back as the same double: the file holds exactly the benchmark's balls.
        out << (i ? ",\n    " : "    ") << "{\"type\": \"sphere\", \"center\": " << vec(s.center.cast<double>())
            << ", \"radius\": " << num(double(s.radius)) << ", \"material\": \"" << colours[i % 8] << "\"}";
    }
    out << "\n  ]\n}\n";
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Writes a generated scene as a tracer scene file (JSON).", "rayproof_scene_gen"};
    std::string kind = "mixed", output;
    std::size_t objects = 2000;
    std::uint64_t seed = 1;
    app.add_option("--kind", kind, "mixed (the tracer's field of objects) or spheres (the ray benchmark's balls)")
        ->check(CLI::IsMember({"mixed", "spheres"}));
    app.add_option("--objects", objects, "how many objects (besides the floor)")
        ->check(rayproof::cli::positive)
        ->check(CLI::Range(std::size_t(1), std::size_t(1000000)));
    app.add_option("--seed", seed, "the generator's seed")->check(rayproof::cli::non_negative);
    app.add_option("-o,--output", output, "the scene file to write (default: stdout)");
    if (const auto stop = rayproof::cli::parse(app, argc, argv)) return *stop;
    std::ofstream file;
    if (!output.empty()) {
        file.open(output);
        if (!file) {
            std::fprintf(stderr, "rayproof_scene_gen: cannot write '%s'\n", output.c_str());
            return 1;
        }
    }
    std::ostream& out = output.empty() ? std::cout : file;
    if (kind == "mixed") write_mixed(out, objects, seed);
    else write_spheres(out, objects, seed);
    out.flush();
    if (!out) {
        std::fprintf(stderr, "rayproof_scene_gen: writing failed\n");
        return 1;
    }
    return 0;
}
