// Scene to POV-Ray 3.7. The scene is right-handed (x right, y up, z towards the viewer
// in the default camera); POV-Ray is left-handed, so the camera gets `right -x*aspect`,
// the documented way to use right-handed coordinates in POV-Ray, and every coordinate is
// written unchanged.
#include <rayproof/render/pov.hpp>

#include <algorithm>
#include <cmath>
#include <charconv>
#include <string>

namespace rayproof::render {

namespace {

// The shortest decimal that reads back as the same double.
std::string num(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}
// Names go into comments only; anything but printable ASCII becomes '?'.
std::string comment_text(const std::string& in) {
    std::string out;
    for (char ch : in) out += (ch >= 32 && ch < 127) ? ch : '?';
    return out;
}
// Built by appending: g++ 12 warns falsely (-Wrestrict) on "literal" + std::string&&.
std::string triple(const char* prefix, double a, double b, double c) {
    std::string s(prefix);
    s.append(num(a)).append(", ").append(num(b)).append(", ").append(num(c)).append(">");
    return s;
}
std::string vec(const Vec3d& v) { return triple("<", v[0], v[1], v[2]); }
std::string rgb(const Color& c) { return triple("rgb <", c[0], c[1], c[2]); }

std::string light_text(const Light& l) {
    std::string s = "light_source {\n  " + vec(l.position) + "\n";
    Color c = l.color;
    if (l.c2 == 0 && l.c3 == 0) {
        c *= std::min(1.0, 1.0 / l.c1);  // constant attenuation: exact
        s += "  color " + rgb(c) + "\n";
    } else {
        // rayproof: min(1 / (c1 + c2 d + c3 d^2), 1); POV-Ray: 2 / (1 + (d / fade_distance)^fade_power).
        // Matched for large d on the highest-order term.
        const bool quadratic = l.c3 > 0;
        const double fd = quadratic ? 1 / std::sqrt(2 * l.c3) : 1 / (2 * l.c2);
        s += "  color " + rgb(c) + "\n";
        s += "  // attenuation (c1, c2, c3) = (" + num(l.c1) + ", " + num(l.c2) + ", " + num(l.c3) +
             ") approximated by POV-Ray's fade law\n";
        s += "  fade_distance " + num(fd) + " fade_power " + (quadratic ? "2" : "1") + "\n";
    }
    return s + "}\n";
}

std::string material_text(const Material& m, int index) {
    std::string s = "// material \"" + comment_text(m.name) + "\"\n#declare M" + std::to_string(index) + " = material {\n  texture {\n";
    s += "    pigment { rgbt <" + num(m.diffuse[0]) + ", " + num(m.diffuse[1]) + ", " + num(m.diffuse[2]) + ", " +
         num(m.transparency) + "> }\n";
    s += "    finish {\n";
    // POV-Ray multiplies ambient by the pigment colour: K_a = ambient * K_d per channel.
    Color amb;
    bool lost = false;
    for (int i = 0; i < 3; ++i) {
        amb[i] = m.diffuse[i] > 0 ? m.ambient[i] / m.diffuse[i] : 0;
        lost = lost || (m.diffuse[i] == 0 && m.ambient[i] > 0);
    }
    s += "      ambient " + rgb(amb) + (lost ? "  // K_a where K_d is 0 cannot be expressed" : "") + "\n";
    s += "      diffuse 1\n";
    const double ks = m.specular.mean();
    if (ks > 0) {
        const bool grey = m.specular.maxCoeff() == m.specular.minCoeff();
        if (m.highlight == Highlight::phong)
            s += "      phong " + num(ks) + " phong_size " + num(m.shininess);
        else
            s += "      specular " + num(ks) + " roughness " + num(m.shininess > 0 ? 1 / m.shininess : 1);
        s += grey ? "\n" : "  // RGB K_s averaged\n";
    }
    if (m.reflective()) s += "      reflection { " + rgb(m.reflectivity) + " }\n";
    s += "    }\n  }\n";
    if (m.transparent()) s += "  interior { ior " + num(m.ior) + " }\n";
    return s + "}\n";
}

std::string object_text(const Object& o) {
    const std::string mat = "  material { M" + std::to_string(o.material) + " }\n";
    const std::string name = o.name.empty() ? "" : "// " + comment_text(o.name) + "\n";
    if (const auto* s = std::get_if<Sphere<double>>(&o.shape))
        return name + "sphere {\n  " + vec(s->center) + ", " + num(s->radius) + "\n" + mat + "}\n";
    if (const auto* b = std::get_if<Aabb<double>>(&o.shape))
        return name + "box {\n  " + vec(b->lo) + ", " + vec(b->hi) + "\n" + mat + "}\n";
    if (const auto* b = std::get_if<Obb<double>>(&o.shape)) {
        // POV-Ray's matrix maps the row vector p to p·M: the rows are the images of the
        // unit axes (the box's axes, the columns of `axes`), then the translation.
        std::string m = "  matrix <";
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) m += num(b->axes(r, c)) + ", ";
        m += num(b->center[0]) + ", " + num(b->center[1]) + ", " + num(b->center[2]) + ">\n";
        return name + "box {\n  " + vec(-b->half_extent) + ", " + vec(b->half_extent) + "\n" + m + mat + "}\n";
    }
    const auto& p = std::get<Plane<double>>(o.shape);
    const double len = p.normal.norm();
    return name + "plane {\n  " + vec(p.normal / len) + ", " + num(p.offset / len) + "\n" + mat + "}\n";
}

}  // namespace

std::string export_pov(const Scene& scene, const std::string& source_name) {
    const RenderSettings& r = scene.settings;
    const Camera& c = scene.camera;
    const double aspect = double(r.width) / r.height;
    const double hfov = 2 * std::atan(std::tan(c.fov * 3.14159265358979323846 / 360) * aspect) * 180 / 3.14159265358979323846;
    std::string s = "// POV-Ray 3.7 scene exported by rayproof export-pov";
    s += source_name.empty() ? "\n" : " from " + comment_text(source_name) + "\n";
    s += "// render with: povray +W" + std::to_string(r.width) + " +H" + std::to_string(r.height) +
         " File_Gamma=1.0 file.pov  (linear output, as rayproof writes it)\n";
    s += "#version 3.7;\n";
    s += "global_settings {\n  assumed_gamma 1.0\n  max_trace_level " + std::to_string(r.depth) +
         "\n  ambient_light " + rgb(scene.ambient_light) + "\n}\n";
    s += "background { " + rgb(r.background) + " }\n";
    s += "camera {\n  perspective\n  location " + vec(c.position) + "\n  right -x*" + num(aspect) +
         "  // right-handed coordinates\n  up y\n  sky " + vec(c.up) + "\n  angle " + num(hfov) +
         "  // horizontal; vertical " + num(c.fov) + "\n  look_at " + vec(c.look_at) + "\n}\n";
    for (const Light& l : scene.lights) s += light_text(l);
    for (std::size_t i = 0; i < scene.materials.size(); ++i) s += material_text(scene.materials[i], int(i));
    for (const Object& o : scene.objects) s += object_text(o);
    return s;
}

}  // namespace rayproof::render
