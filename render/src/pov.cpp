// Scene to POV-Ray 3.7. The scene is right-handed (x right, y up, z towards the viewer
// in the default camera); POV-Ray is left-handed, so the camera gets `right -x*aspect`,
// the documented way to use right-handed coordinates in POV-Ray, and every coordinate is
// written unchanged.
#include <rayproof/render/pov.hpp>

#include <algorithm>
#include <cmath>
#include <charconv>
#include <string>
#include <vector>

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

// What cannot be written exactly is said in `inexact`, one line each.
using Notes = std::vector<std::string>;

std::string light_text(const Light& l, std::size_t index, Notes& inexact) {
    const std::string which = "light " + std::to_string(index);
    std::string s = "light_source {\n  " + vec(l.position) + "\n";
    Color c = l.color;
    if (l.c2 == 0 && l.c3 == 0) {
        c *= std::min(1.0, 1.0 / l.c1);  // constant attenuation: exact
        s += "  color " + rgb(c) + "\n";
    } else if (l.c2 == 0 && l.c1 > 0) {
        // POV-Ray: 2 / (1 + (d / fd)^2); scaled by 1 / (2 c1) with fd = sqrt(c1 / c3) it is
        // 1 / (c1 + c3 d^2), rayproof's law, exactly while rayproof's min(., 1) does not act:
        // for every d when c1 >= 1.
        c /= 2 * l.c1;
        s += "  color " + rgb(c) + "\n";
        s += "  fade_distance " + num(std::sqrt(l.c1 / l.c3)) + " fade_power 2\n";
        if (l.c1 < 1)
            inexact.push_back(which + ": attenuation c1 < 1, clamped to 1 within " +
                              num(std::sqrt((1 - l.c1) / l.c3)) + " of the light by rayproof, not by POV-Ray");
    } else {
        const bool quadratic = l.c3 > 0;
        const double fd = quadratic ? 1 / std::sqrt(2 * l.c3) : 1 / (2 * l.c2);
        s += "  color " + rgb(c) + "\n";
        s += "  // attenuation (c1, c2, c3) = (" + num(l.c1) + ", " + num(l.c2) + ", " + num(l.c3) +
             ") approximated by POV-Ray's fade law\n";
        s += "  fade_distance " + num(fd) + " fade_power " + (quadratic ? "2" : "1") + "\n";
        inexact.push_back(which + ": attenuation (c1, c2, c3) = (" + num(l.c1) + ", " + num(l.c2) + ", " +
                          num(l.c3) + ") has no POV-Ray equivalent (only c2 = 0 with c1 > 0 has); approximated");
    }
    if (l.visible()) {
        // Seen as a sphere of the light's own colour: emission is not scaled by
        // ambient_light, diffuse 0 takes no light, no_shadow lets the light out.
        s += "  looks_like { sphere { <0, 0, 0>, " + num(l.radius) + " pigment { " + rgb(l.color) +
             " } finish { emission 1 ambient 0 diffuse 0 } no_shadow } }\n";
    }
    return s + "}\n";
}

std::string material_text(const Material& m, int index, Notes& inexact) {
    const std::string which = "material \"" + comment_text(m.name) + "\"";
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
    if (lost) inexact.push_back(which + ": an ambient K_a where K_d is 0 cannot be expressed (POV-Ray's is K_a·K_d)");
    // POV-Ray's second diffuse value lights the back side by that fraction of the pigment:
    // K_d·k_dt·(-N·L), as rayproof's translucency.
    s += m.translucency > 0 ? "      diffuse 1, " + num(m.translucency) + "\n" : "      diffuse 1\n";
    // rayproof weighs the whole surface term, highlights and mirror reflection included, by
    // (1 - K_t) (tracer.hpp); POV-Ray weighs only ambient and diffuse by (1 - transmit),
    // so highlights and reflection are written already weighted.
    const double opaque = 1 - m.transparency;
    const double ks = m.specular.mean() * opaque;
    if (ks > 0) {
        const bool grey = m.specular.maxCoeff() == m.specular.minCoeff();
        if (m.highlight == Highlight::phong)
            s += "      phong " + num(ks) + " phong_size " + num(m.shininess);
        else
            s += "      specular " + num(ks) + " roughness " + num(m.shininess > 0 ? 1 / m.shininess : 1);
        s += grey ? "\n" : "  // RGB K_s averaged\n";
        if (!grey) inexact.push_back(which + ": an RGB K_s is written as its mean (POV-Ray's highlight is grey)");
    }
    if (m.reflective()) s += "      reflection { " + rgb(m.reflectivity * opaque) + " }\n";
    s += "    }\n  }\n";
    if (m.transparent()) s += "  interior { ior " + num(m.ior) + " }\n";
    return s + "}\n";
}

// "<n/|n|>, offset/|n|": POV-Ray takes a unit normal and the distance along it; both are
// rounded to the nearest double of the quotient (the planes' one inexact step).
std::string plane_args(const Plane<double>& p) {
    const double len = p.normal.norm();
    return vec(p.normal / len) + ", " + num(p.offset / len);
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
    // A polyhedron: the intersection of its half-spaces; POV-Ray's plane { n, d } is the
    // solid n·p <= d for a unit n (its inside is opposite the normal), as rayproof's.
    if (const auto* poly = std::get_if<Polyhedron>(&o.shape)) {
        if (poly->planes.size() == 1) return name + "plane {\n  " + plane_args(poly->planes[0]) + "\n" + mat + "}\n";
        std::string s = name + "intersection {\n";
        for (const Plane<double>& p : poly->planes) s += "  plane { " + plane_args(p) + " }\n";
        return s + mat + "}\n";
    }
    const auto& p = std::get<Plane<double>>(o.shape);
    return name + "plane {\n  " + plane_args(p) + "\n" + mat + "}\n";
}

}  // namespace

PovScene to_pov(const Scene& scene, const std::string& source_name) {
    PovScene out;
    Notes& inexact = out.inexact;
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
         "\n  adc_bailout " + num(r.min_contribution) + "\n  ambient_light " + rgb(scene.ambient_light) + "\n}\n";
    if (scene.tree_attenuation.enabled)
        inexact.push_back("the ray tree's distance attenuation has no POV-Ray equivalent: the export renders "
                          "without it (turn it off in rayproof with \"tree_attenuation\": false or "
                          "--no-tree-attenuation to compare)");
    s += "background { " + rgb(r.background) + " }\n";
    s += "camera {\n  perspective\n  location " + vec(c.position) + "\n  right -x*" + num(aspect) +
         "  // right-handed coordinates\n  up y\n  sky " + vec(c.up) + "\n  angle " + num(hfov) +
         "  // horizontal; vertical " + num(c.fov) + "\n  look_at " + vec(c.look_at) + "\n}\n";
    for (std::size_t i = 0; i < scene.lights.size(); ++i) s += light_text(scene.lights[i], i, inexact);
    for (std::size_t i = 0; i < scene.materials.size(); ++i) s += material_text(scene.materials[i], int(i), inexact);
    for (const Object& o : scene.objects) s += object_text(o);
    out.text = std::move(s);
    return out;
}

std::string export_pov(const Scene& scene, const std::string& source_name) { return to_pov(scene, source_name).text; }

}  // namespace rayproof::render
