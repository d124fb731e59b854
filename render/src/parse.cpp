// Scene files: JSON text to Scene. Syntax errors come from nlohmann-json (with the line
// and column computed from its byte offset); the schema is checked here, key by key,
// so that every error names the key path and what was expected. Duplicate keys, which
// nlohmann-json accepts (the last one winning), are found by a scan of the accepted
// text, and the line and column of a schema error come from a walk of the text along
// its key path (both in the Text scanner below). Nothing escapes parse_scene: every
// exception is caught and turned into a ParseError.
#include <rayproof/render/parse.hpp>

#include <rayproof/render/memory.hpp>

#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <iterator>
#include <map>
#include <sstream>
#include <utility>
#include <vector>

namespace rayproof::render {

namespace {

using json = nlohmann::json;

// Geometry and colours are limited to this magnitude so that squares and products in the
// tracer stay finite; the kernel itself takes any finite input.
constexpr double max_magnitude = 1e100;
constexpr int max_nesting = 64;
constexpr int max_image_side = 16384;
constexpr long long max_pixels = 1LL << 26;
// The largest scene file load_scene reads: 100,000 objects take 15 to 20 MB of JSON.
constexpr long long max_scene_bytes = 64'000'000;

struct SchemaError {
    std::string key;
    std::string message;
    bool at_key = false;  // the position to report is the key's, not its value's (an unknown key)
};

[[noreturn]] void fail(const std::string& key, const std::string& message) { throw SchemaError{key, message}; }
[[noreturn]] void fail_at_key(const std::string& key, const std::string& message) {
    throw SchemaError{key, message, true};
}

std::string type_name(const json& j) {
    switch (j.type()) {
        case json::value_t::null: return "null";
        case json::value_t::boolean: return "a boolean";
        case json::value_t::number_integer:
        case json::value_t::number_unsigned:
        case json::value_t::number_float: return "a number";
        case json::value_t::string: return "a string";
        case json::value_t::array: return "an array";
        case json::value_t::object: return "an object";
        default: return "a value of another kind";
    }
}

std::string show(const json& j) {
    std::string s = j.dump();
    if (s.size() > 40) s = s.substr(0, 37) + "...";
    return s;
}

// Appends a key to a key path, as every error writes it: "a.b", an empty key shown as "".
void append_key(std::string& path, const std::string& key) {
    if (!path.empty()) path += '.';
    path += key.empty() ? "\"\"" : key;
}

std::string join_path(const std::string& parent, const std::string& key) {
    std::string path = parent;
    append_key(path, key);
    return path;
}

// One JSON object of the schema: its keys are checked against the allowed ones (a typo
// is an error, not a silently ignored setting); "comment" is allowed everywhere.
class Obj {
public:
    Obj(const json& j, std::string path, std::initializer_list<const char*> allowed) : j_(j), path_(std::move(path)) {
        if (!j.is_object()) fail(path_.empty() ? "(top level)" : path_, "expected an object, got " + type_name(j));
        for (const auto& item : j.items()) {
            bool ok = item.key() == "comment";
            for (const char* a : allowed) ok = ok || item.key() == a;
            if (!ok) {
                std::string list;
                for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
                fail_at_key(join_path(path_, item.key()), "unknown key (expected one of: " + list + ")");
            }
        }
    }
    bool has(const char* key) const { return j_.contains(key); }
    const json& get(const char* key) const {
        if (!j_.contains(key)) fail(join_path(path_, key), "missing (required)");
        return j_.at(key);
    }
    std::string path(const char* key) const { return join_path(path_, key); }
    const std::string& path() const { return path_; }

private:
    const json& j_;
    std::string path_;
};

double number(const json& j, const std::string& path) {
    if (!j.is_number()) fail(path, "expected a number, got " + type_name(j) + " " + show(j));
    const double v = j.get<double>();
    if (!std::isfinite(v) || std::abs(v) > max_magnitude)
        fail(path, "expected a finite number of magnitude at most 1e100, got " + show(j));
    return v;
}

double number_in(const json& j, const std::string& path, double lo, double hi, const char* what) {
    const double v = number(j, path);
    if (!(v >= lo && v <= hi)) fail(path, std::string("expected ") + what + ", got " + show(j));
    return v;
}

int integer_in(const json& j, const std::string& path, long long lo, long long hi) {
    if (!j.is_number_integer()) fail(path, "expected an integer, got " + type_name(j) + " " + show(j));
    bool ok;
    long long v = 0;
    if (j.is_number_unsigned()) {  // nlohmann-json stores non-negative integers as unsigned
        const unsigned long long u = j.get<unsigned long long>();
        ok = u <= static_cast<unsigned long long>(hi);
        v = ok ? static_cast<long long>(u) : 0;
        ok = ok && v >= lo;
    } else {
        v = j.get<long long>();
        ok = v >= lo && v <= hi;
    }
    if (!ok) fail(path, "expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got " + show(j));
    return int(v);
}

Vec3d vec3(const json& j, const std::string& path) {
    if (!j.is_array() || j.size() != 3)
        fail(path, "expected an array of 3 numbers [x, y, z], got " + type_name(j) + " " + show(j));
    Vec3d v;
    for (std::size_t i = 0; i < 3; ++i) v[int(i)] = number(j[i], path + "[" + std::to_string(i) + "]");
    return v;
}

// A colour: [r, g, b] or one number for a grey; every channel >= 0 (and <= hi).
Color color(const json& j, const std::string& path, double hi = max_magnitude) {
    Color c;
    if (j.is_number()) {
        c = Color::Constant(number(j, path));
    } else if (j.is_array() && j.size() == 3) {
        for (std::size_t i = 0; i < 3; ++i) c[int(i)] = number(j[i], path + "[" + std::to_string(i) + "]");
    } else {
        fail(path, "expected a colour: [r, g, b] or a single number, got " + type_name(j) + " " + show(j));
    }
    for (int i = 0; i < 3; ++i)
        if (!(c[i] >= 0 && c[i] <= hi))
            fail(path, hi == 1 ? "expected every channel in [0, 1], got " + show(j)
                               : "expected every channel >= 0, got " + show(j));
    return c;
}

std::string string(const json& j, const std::string& path) {
    if (!j.is_string()) fail(path, "expected a string, got " + type_name(j) + " " + show(j));
    return j.get<std::string>();
}

Camera read_camera(const json& j) {
    const Obj o(j, "camera", {"position", "look_at", "up", "fov"});
    Camera c;
    c.position = vec3(o.get("position"), o.path("position"));
    c.look_at = vec3(o.get("look_at"), o.path("look_at"));
    if (o.has("up")) c.up = vec3(o.get("up"), o.path("up"));
    if (o.has("fov")) c.fov = number_in(o.get("fov"), o.path("fov"), 1e-3, 179, "a vertical field of view in degrees, in [0.001, 179]");
    const Vec3d f = c.look_at - c.position;
    if (!(f.norm() > 0) || !std::isfinite(f.norm()))
        fail(o.path("look_at"), "must differ from camera.position (and the difference must be finite)");
    const Vec3d side = f.normalized().cross(c.up);
    if (!(side.norm() > 1e-9 * c.up.norm())) fail(o.path("up"), "must not be zero nor parallel to the view direction");
    return c;
}

RenderSettings read_render(const json& j) {
    const Obj o(j, "render", {"width", "height", "depth", "supersample", "mode", "background", "min_contribution"});
    RenderSettings r;
    if (o.has("width")) r.width = integer_in(o.get("width"), o.path("width"), 1, max_image_side);
    if (o.has("height")) r.height = integer_in(o.get("height"), o.path("height"), 1, max_image_side);
    if ((long long)r.width * r.height > max_pixels)
        fail(o.path("height"), "width * height must be at most " + std::to_string(max_pixels) + " pixels");
    if (o.has("depth")) r.depth = integer_in(o.get("depth"), o.path("depth"), 1, 64);
    if (o.has("supersample")) r.supersample = integer_in(o.get("supersample"), o.path("supersample"), 1, 16);
    if (o.has("mode")) {
        const std::string m = string(o.get("mode"), o.path("mode"));
        const auto mode = parse_mode(m);
        if (!mode) fail(o.path("mode"), "expected \"fast\", \"conservative\" or \"certified\", got \"" + m + "\"");
        r.mode = *mode;
    }
    if (o.has("background")) r.background = color(o.get("background"), o.path("background"));
    if (o.has("min_contribution"))
        r.min_contribution = number_in(o.get("min_contribution"), o.path("min_contribution"), 0, 1, "a number in [0, 1]");
    return r;
}

Light read_light(const json& j, const std::string& path) {
    const Obj o(j, path, {"position", "color", "attenuation", "radius", "name"});
    Light l;
    l.position = vec3(o.get("position"), o.path("position"));
    if (o.has("color")) l.color = color(o.get("color"), o.path("color"));
    if (o.has("attenuation")) {
        const std::string p = o.path("attenuation");
        const Vec3d c = vec3(o.get("attenuation"), p);
        if (!(c.minCoeff() >= 0)) fail(p, "expected [c1, c2, c3] with every coefficient >= 0, got " + show(o.get("attenuation")));
        l.c1 = c[0], l.c2 = c[1], l.c3 = c[2];
    }
    if (o.has("radius")) l.radius = number_in(o.get("radius"), o.path("radius"), 0, max_magnitude, "a radius >= 0");
    if (o.has("name")) string(o.get("name"), o.path("name"));
    return l;
}

// false, true, or [c1, c2, c3] (each >= 0).
TreeAttenuation read_tree_attenuation(const json& j) {
    const std::string path = "tree_attenuation";
    TreeAttenuation t;
    if (j.is_boolean()) {
        t.enabled = j.get<bool>();
        return t;
    }
    if (!j.is_array())
        fail(path, "expected false, true or [c1, c2, c3], got " + type_name(j) + " " + show(j));
    const Vec3d c = vec3(j, path);
    if (!(c.minCoeff() >= 0)) fail(path, "expected [c1, c2, c3] with every coefficient >= 0, got " + show(j));
    t.c1 = c[0], t.c2 = c[1], t.c3 = c[2];
    return t;
}

Material read_material(const json& j, const std::string& path, std::string name) {
    const Obj o(j, path, {"ambient", "diffuse", "specular", "shininess", "highlight", "reflectivity", "transparency", "ior",
                           "translucency"});
    Material m;
    m.name = std::move(name);
    if (o.has("diffuse")) m.diffuse = color(o.get("diffuse"), o.path("diffuse"));
    m.ambient = m.diffuse;  // K_a defaults to K_d
    if (o.has("ambient")) m.ambient = color(o.get("ambient"), o.path("ambient"));
    if (o.has("specular")) m.specular = color(o.get("specular"), o.path("specular"));
    if (o.has("shininess")) m.shininess = number_in(o.get("shininess"), o.path("shininess"), 0, 1e6, "an exponent in [0, 1e6]");
    if (o.has("highlight")) {
        const std::string h = string(o.get("highlight"), o.path("highlight"));
        if (h == "phong") m.highlight = Highlight::phong;
        else if (h == "blinn") m.highlight = Highlight::blinn;
        else fail(o.path("highlight"), "expected \"phong\" or \"blinn\", got \"" + h + "\"");
    }
    if (o.has("reflectivity")) m.reflectivity = color(o.get("reflectivity"), o.path("reflectivity"), 1);
    if (o.has("transparency"))
        m.transparency = number_in(o.get("transparency"), o.path("transparency"), 0, 1, "a number in [0, 1]");
    if (o.has("ior")) m.ior = number_in(o.get("ior"), o.path("ior"), 1e-3, 1e3, "an index of refraction in [0.001, 1000]");
    if (o.has("translucency"))
        m.translucency = number_in(o.get("translucency"), o.path("translucency"), 0, 1, "a number in [0, 1]");
    return m;
}

// Rotation by rx about x, then ry about y, then rz about z (degrees; POV-Ray's rotate <rx, ry, rz>).
Eigen::Matrix3d rotation(const Vec3d& deg) {
    const double k = 3.14159265358979323846 / 180;
    const Eigen::Matrix3d r = (Eigen::AngleAxisd(deg[2] * k, Vec3d::UnitZ()) * Eigen::AngleAxisd(deg[1] * k, Vec3d::UnitY()) *
                               Eigen::AngleAxisd(deg[0] * k, Vec3d::UnitX()))
                                  .toRotationMatrix();
    return r;
}

Vec3d nonnegative_vec3(const json& j, const std::string& path) {
    const Vec3d v = vec3(j, path);
    if (!(v.minCoeff() >= 0)) fail(path, "expected 3 numbers >= 0, got " + show(j));
    return v;
}

// "polyhedron": exactly one of "planes" (each {"normal": [x, y, z], "offset": o}, the
// solid normal·p <= offset, normals out), "vertices" (the exact convex hull of the points,
// polyhedron.hpp) or "preset" (with "center" and "size": the hull of the preset's points
// center + size·v, each coordinate the double nearest its value). Errors name the key
// path of the object and, when it has one, its name.
Polyhedron read_polyhedron(const json& j, const std::string& path) {
    const Obj o(j, path, {"type", "name", "material", "planes", "vertices", "preset", "center", "size"});
    std::string who;
    if (j.contains("name") && j.at("name").is_string()) who = " (polyhedron \"" + j.at("name").get<std::string>() + "\")";
    if (int(o.has("planes")) + int(o.has("vertices")) + int(o.has("preset")) != 1)
        fail(o.path("planes"), "give exactly one of \"planes\", \"vertices\" or \"preset\"" + who);
    if (!o.has("preset"))
        for (const char* k : {"center", "size"})
            if (o.has(k)) fail_at_key(o.path(k), std::string("only with \"preset\"") + who);
    Polyhedron poly;
    if (o.has("planes")) {
        const std::string pp = o.path("planes");
        const json& ps = o.get("planes");
        if (!ps.is_array() || ps.empty())
            fail(pp, "expected a non-empty array of planes {\"normal\": [x, y, z], \"offset\": o}, got " + type_name(ps) + " " +
                         show(ps) + who);
        if (ps.size() > max_polyhedron_planes)
            fail(pp, "at most " + std::to_string(max_polyhedron_planes) + " planes per polyhedron, got " +
                         std::to_string(ps.size()) + who);
        for (std::size_t i = 0; i < ps.size(); ++i) {
            const Obj q(ps[i], pp + "[" + std::to_string(i) + "]", {"normal", "offset"});
            Plane<double> pl{vec3(q.get("normal"), q.path("normal")), number(q.get("offset"), q.path("offset"))};
            if (pl.normal.isZero()) fail(q.path("normal"), "must not be the zero vector" + who);
            poly.planes.push_back(pl);
        }
        return poly;
    }
    std::vector<Vec3d> points;
    std::string at;
    if (o.has("vertices")) {
        at = o.path("vertices");
        const json& vs = o.get("vertices");
        if (!vs.is_array())
            fail(at, "expected an array of points [x, y, z], got " + type_name(vs) + " " + show(vs) + who);
        if (vs.size() > max_hull_points)
            fail(at, "at most " + std::to_string(max_hull_points) + " vertices per polyhedron, got " +
                         std::to_string(vs.size()) + who);
        for (std::size_t i = 0; i < vs.size(); ++i) points.push_back(vec3(vs[i], at + "[" + std::to_string(i) + "]"));
    } else {
        at = o.path("preset");
        const std::string name = string(o.get("preset"), at);
        points = preset_points(name);
        if (points.empty()) fail(at, std::string("expected one of ") + preset_names + ", got \"" + name + "\"" + who);
        const Vec3d c = o.has("center") ? vec3(o.get("center"), o.path("center")) : Vec3d::Zero();
        const double size =
            o.has("size") ? number_in(o.get("size"), o.path("size"), 0x1p-500, max_magnitude, "a size > 0") : 1.0;
        for (Vec3d& p : points)
            for (int i = 0; i < 3; ++i) p[i] = std::fma(size, p[i], c[i]);  // the double nearest c_i + size·v_i
        if (!o.has("size") && !o.has("center")) at = o.path("preset");
        else at = o.has("size") ? o.path("size") : o.path("center");
    }
    HullResult h = convex_hull(points);
    if (!h.error.empty()) fail(at, "no convex polyhedron: " + h.error + who);
    poly.planes = std::move(h.planes);
    poly.exact = h.exact;
    poly.slack = h.slack;
    if (h.exact) poly.bound = enclosing_sphere(points);
    return poly;
}

Shape read_shape(const json& j, const std::string& path, const std::string& type) {
    if (type == "sphere") {
        const Obj o(j, path, {"type", "name", "material", "center", "radius"});
        Sphere<double> s{vec3(o.get("center"), o.path("center")), 0};
        s.radius = number_in(o.get("radius"), o.path("radius"), 0, max_magnitude, "a radius >= 0");
        return s;
    }
    if (type == "box") {
        const Obj o(j, path, {"type", "name", "material", "min", "max"});
        Aabb<double> b{vec3(o.get("min"), o.path("min")), vec3(o.get("max"), o.path("max"))};
        for (int i = 0; i < 3; ++i)
            if (!(b.lo[i] <= b.hi[i])) fail(o.path("max"), "every coordinate of max must be >= the one of min");
        return b;
    }
    if (type == "cube") {
        const Obj o(j, path, {"type", "name", "material", "side", "center"});
        const double side = number_in(o.get("side"), o.path("side"), 0, max_magnitude, "a side length >= 0");
        const Vec3d c = o.has("center") ? vec3(o.get("center"), o.path("center")) : Vec3d::Zero();
        const Vec3d h = Vec3d::Constant(side / 2);
        return Aabb<double>{c - h, c + h};
    }
    if (type == "oriented_box") {
        const Obj o(j, path, {"type", "name", "material", "center", "size", "rotation"});
        Obb<double> b;
        b.center = vec3(o.get("center"), o.path("center"));
        b.half_extent = nonnegative_vec3(o.get("size"), o.path("size")) / 2;
        b.axes = rotation(o.has("rotation") ? vec3(o.get("rotation"), o.path("rotation")) : Vec3d::Zero());
        if (!b.axes.allFinite()) fail(o.path("rotation"), "angles too large to evaluate");
        return b;
    }
    if (type == "plane") {
        const Obj o(j, path, {"type", "name", "material", "normal", "offset", "point"});
        Plane<double> p{vec3(o.get("normal"), o.path("normal")), 0};
        if (p.normal.isZero()) fail(o.path("normal"), "must not be the zero vector");
        if (o.has("offset") == o.has("point"))
            fail(o.path("offset"), "give exactly one of \"offset\" (normal·p == offset) or \"point\" (a point of the plane)");
        if (o.has("offset")) {
            p.offset = number(o.get("offset"), o.path("offset"));
        } else {
            p.offset = p.normal.dot(vec3(o.get("point"), o.path("point")));
            if (!std::isfinite(p.offset)) fail(o.path("point"), "normal·point overflows");
        }
        return p;
    }
    if (type == "polyhedron") return read_polyhedron(j, path);
    fail(path + ".type",
         "expected \"sphere\", \"box\", \"cube\", \"oriented_box\", \"plane\" or \"polyhedron\", got \"" + type + "\"");
}

int nesting_depth_error_offset(std::string_view text) {
    int depth = 0;
    bool in_string = false, escape = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_string) {
            if (escape) escape = false;
            else if (c == '\\') escape = true;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > max_nesting) return int(i);
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return -1;
}

void line_column(std::string_view text, std::size_t offset, int& line, int& column) {
    line = 1;
    column = 1;
    for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
}

Scene read_scene(const json& root, Progress* progress) {
    const Obj top(root, "", {"camera", "render", "ambient_light", "lights", "materials", "objects", "description",
                                     "tree_attenuation"});
    Scene s;
    s.camera = read_camera(top.get("camera"));
    if (top.has("render")) s.settings = read_render(top.get("render"));
    if (top.has("ambient_light")) s.ambient_light = color(top.get("ambient_light"), "ambient_light");
    if (top.has("description")) string(top.get("description"), "description");
    if (top.has("tree_attenuation")) s.tree_attenuation = read_tree_attenuation(top.get("tree_attenuation"));
    if (top.has("lights")) {
        const json& ls = top.get("lights");
        if (!ls.is_array()) fail("lights", "expected an array of lights, got " + type_name(ls));
        for (std::size_t i = 0; i < ls.size(); ++i) s.lights.push_back(read_light(ls[i], "lights[" + std::to_string(i) + "]"));
    }
    std::map<std::string, int> by_name;
    if (top.has("materials")) {
        const json& ms = top.get("materials");
        if (!ms.is_object()) fail("materials", "expected an object mapping names to materials, got " + type_name(ms));
        for (const auto& item : ms.items()) {
            by_name[item.key()] = int(s.materials.size());
            s.materials.push_back(read_material(item.value(), join_path("materials", item.key()), item.key()));
        }
    }
    const json& os = top.get("objects");
    if (!os.is_array()) fail("objects", "expected an array of objects, got " + type_name(os));
    s.objects.reserve(os.size());  // no reallocation (and no moving of every object) as it grows
    if (progress) progress->phase("checking", os.size());
    for (std::size_t i = 0; i < os.size(); ++i) {
        const std::string path = "objects[" + std::to_string(i) + "]";
        const json& oj = os[i];
        if (!oj.is_object()) fail(path, "expected an object, got " + type_name(oj));
        if (!oj.contains("type")) fail(path + ".type", "missing (required): one of sphere, box, cube, oriented_box, plane, polyhedron");
        Object obj;
        obj.shape = read_shape(oj, path, string(oj.at("type"), path + ".type"));
        if (oj.contains("name")) obj.name = string(oj.at("name"), path + ".name");
        if (!oj.contains("material")) fail(path + ".material", "missing (required): a material name or a material object");
        const json& mj = oj.at("material");
        if (mj.is_string()) {
            const auto it = by_name.find(mj.get<std::string>());
            if (it == by_name.end()) {
                std::string names;
                for (const auto& [n, k] : by_name) names += (names.empty() ? "" : ", ") + n;
                fail(path + ".material", "unknown material \"" + mj.get<std::string>() + "\" (defined: " +
                                             (names.empty() ? "none" : names) + ")");
            }
            obj.material = it->second;
        } else if (mj.is_object()) {
            obj.material = int(s.materials.size());
            s.materials.push_back(read_material(mj, path + ".material", path + ".material"));
        } else {
            fail(path + ".material", "expected a material name or a material object, got " + type_name(mj));
        }
        s.objects.push_back(std::move(obj));
        if (progress && (i & 1023) == 1023) progress->set(i + 1);
    }
    if (progress) progress->finish();
    return s;
}

// The text scanner. It walks JSON text that nlohmann-json has accepted (all of it, or,
// after a number overflow, the prefix up to that number, which nlohmann-json read in
// order before it stopped), so it needs to tell apart only strings, numbers, literals
// and brackets, and it keeps the key path of the value it is in exactly as the schema
// errors write it (join_path, "[i]" for an array element). Should it ever fall out of
// step with the text, it throws OutOfStep and stops: a duplicate key
// found so far is reported, and an error gets the deepest position found so far.
struct OutOfStep {};

class Text {
public:
    explicit Text(std::string_view t) : t_(t) {
        if (t_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = 3;  // nlohmann-json skips a UTF-8 byte-order mark
    }
    std::size_t pos() const { return pos_; }
    // The next character that is not JSON white space ('\0' at the end); the position moves onto it.
    char peek() {
        while (pos_ < t_.size() && (t_[pos_] == ' ' || t_[pos_] == '\t' || t_[pos_] == '\n' || t_[pos_] == '\r'))
            ++pos_;
        return pos_ < t_.size() ? t_[pos_] : '\0';
    }
    void expect(char c) {
        if (peek() != c) throw OutOfStep{};
        ++pos_;
    }
    // A string, quotes included; the position moves past it.
    std::string_view string_token() {
        const std::size_t begin = pos_;
        expect('"');
        while (pos_ < t_.size() && t_[pos_] != '"') pos_ += t_[pos_] == '\\' ? 2 : 1;
        if (pos_ >= t_.size()) throw OutOfStep{};
        ++pos_;
        return t_.substr(begin, pos_ - begin);
    }
    // A number or a literal (true, false, null).
    std::string_view scalar_token() {
        peek();
        const std::size_t begin = pos_;
        while (pos_ < t_.size() && (std::isalnum(static_cast<unsigned char>(t_[pos_])) || t_[pos_] == '-' ||
                                    t_[pos_] == '+' || t_[pos_] == '.'))
            ++pos_;
        if (pos_ == begin) throw OutOfStep{};
        return t_.substr(begin, pos_ - begin);
    }
    void skip_value() {
        const char c = peek();
        if (c == '"') {
            string_token();
        } else if (c == '{' || c == '[') {
            int depth = 0;
            do {
                const char d = peek();
                if (d == '"') {
                    string_token();
                    continue;
                }
                if (d == '\0') throw OutOfStep{};
                if (d == '{' || d == '[') ++depth;
                else if (d == '}' || d == ']') --depth;
                ++pos_;
            } while (depth > 0);
        } else {
            scalar_token();
        }
    }

private:
    std::string_view t_;
    std::size_t pos_ = 0;
};

// The key a string token stands for: its bytes, or nlohmann-json's reading of its escapes.
std::string key_of(std::string_view token) {
    const std::string_view inner = token.substr(1, token.size() - 2);
    if (inner.find('\\') == std::string_view::npos) return std::string(inner);
    return json::parse(token).get<std::string>();
}

void append_index(std::string& path, std::size_t i) {
    path += '[';
    path += std::to_string(i);
    path += ']';
}

// What the scan looks for: the earliest second occurrence of a key in an object (nlohmann-json
// keeps the last value without a word), or the first number that overflows a double.
struct Finding {
    std::string path;
    std::size_t at = 0;     // byte offset of the second key, or of the number
    std::size_t first = 0;  // duplicate keys: byte offset of the first occurrence
    std::string token;      // the number as written
};

class Scan {
public:
    enum class Find { duplicate_key, overflowing_number };
    Scan(std::string_view text, Find find) : x_(text), find_(find) {}
    std::optional<Finding> run() {
        try {
            value();
        } catch (const Stop&) {
        } catch (const OutOfStep&) {  // never seen; what was found so far stands
        } catch (const json::exception&) {
        }
        return found_;
    }

private:
    struct Stop {};

    void value() {
        const char c = x_.peek();
        if (c == '{') object();
        else if (c == '[') array();
        else if (c == '"') x_.string_token();
        else number_or_literal();
    }
    void number_or_literal() {
        const std::size_t at = x_.pos();
        const std::string_view tok = x_.scalar_token();
        if (find_ != Find::overflowing_number || !(tok[0] == '-' || std::isdigit(static_cast<unsigned char>(tok[0]))))
            return;
        // nlohmann-json reads a number with strtod (an integer too large for 64 bits as well)
        // and rejects it when the result is not finite.
        if (std::isfinite(std::strtod(std::string(tok).c_str(), nullptr))) return;
        found_ = Finding{path_.empty() ? "(top level)" : path_, at, 0, std::string(tok)};
        throw Stop{};
    }
    void object() {
        const std::size_t len = path_.size();
        // Each key and its byte offset; one list per nesting depth, reused from object to object.
        // (Indexed, not held by reference: a nested object may grow keys_.)
        const std::size_t d = depth_++;
        if (keys_.size() <= d) keys_.resize(d + 1);
        keys_[d].clear();
        x_.expect('{');
        if (x_.peek() != '}') {
            for (;;) {
                x_.peek();
                const std::size_t at = x_.pos();
                std::string key = key_of(x_.string_token());
                x_.expect(':');
                path_.resize(len);
                append_key(path_, key);
                value();
                if (find_ == Find::duplicate_key) keys_[d].emplace_back(std::move(key), at);
                if (x_.peek() != ',') break;
                x_.expect(',');
            }
        }
        x_.expect('}');
        --depth_;
        path_.resize(len);
        auto& keys = keys_[d];
        if (keys.size() < 2) return;
        std::sort(keys.begin(), keys.end());  // by key, then by position
        for (std::size_t i = 1; i < keys.size(); ++i)
            if (keys[i].first == keys[i - 1].first && (!found_ || keys[i].second < found_->at)) {
                std::string path = path_;
                append_key(path, keys[i].first);
                found_ = Finding{std::move(path), keys[i].second, keys[i - 1].second, ""};
            }
    }
    void array() {
        const std::size_t len = path_.size();
        x_.expect('[');
        if (x_.peek() != ']') {
            for (std::size_t i = 0;; ++i) {
                path_.resize(len);
                append_index(path_, i);
                value();
                if (x_.peek() != ',') break;
                x_.expect(',');
            }
        }
        x_.expect(']');
        path_.resize(len);
    }

    Text x_;
    Find find_;
    std::string path_;
    std::optional<Finding> found_;
    std::size_t depth_ = 0;
    std::vector<std::vector<std::pair<std::string, std::size_t>>> keys_;
};

// Where the value at `target` (a key path as the schema errors write it) begins, or its
// key when at_key; when the path leads to no value (a required key is missing), the
// deepest value on the way, i.e. the object that lacks the key. Only the members whose
// path is a prefix of the target are entered, the others are skipped.
class Locate {
public:
    Locate(std::string_view text, std::string target, bool at_key)
        : x_(text), target_(std::move(target)), at_key_(at_key) {}
    std::optional<std::size_t> run() {
        try {
            if (target_ == "(top level)") {
                x_.peek();
                return x_.pos();
            }
            value(std::string_view::npos);
        } catch (const OutOfStep&) {  // never seen; the deepest value found so far stands
        } catch (const json::exception&) {
        }
        return best_;
    }

private:
    bool on_the_way() const {
        return target_.compare(0, path_.size(), path_) == 0 &&
               (target_.size() == path_.size() || target_[path_.size()] == '.' || target_[path_.size()] == '[');
    }
    // True when the target was found in this value.
    bool value(std::size_t key_at) {
        const char c = x_.peek();
        const std::size_t at = x_.pos();
        if (path_ == target_) {
            best_ = at_key_ && key_at != std::string_view::npos ? key_at : at;
            return true;
        }
        best_ = at;  // deeper than any value before: only prefixes of the target are entered
        const std::size_t len = path_.size();
        if (c == '{') {
            x_.expect('{');
            if (x_.peek() != '}') {
                for (;;) {
                    x_.peek();
                    const std::size_t k = x_.pos();
                    const std::string key = key_of(x_.string_token());
                    x_.expect(':');
                    path_.resize(len);
                    append_key(path_, key);
                    if (on_the_way()) {
                        if (value(k)) return true;
                    } else {
                        x_.skip_value();
                    }
                    if (x_.peek() != ',') break;
                    x_.expect(',');
                }
            }
            x_.expect('}');
        } else if (c == '[') {
            x_.expect('[');
            if (x_.peek() != ']') {
                for (std::size_t i = 0;; ++i) {
                    path_.resize(len);
                    append_index(path_, i);
                    if (on_the_way()) {
                        if (value(std::string_view::npos)) return true;
                    } else {
                        x_.skip_value();
                    }
                    if (x_.peek() != ',') break;
                    x_.expect(',');
                }
            }
            x_.expect(']');
        } else {
            x_.skip_value();
        }
        // The target is not in this value (a missing key): best_ keeps the deepest value
        // on the way, the one that lacks it.
        path_.resize(len);
        return false;
    }

    Text x_;
    std::string target_;
    bool at_key_;
    std::string path_;
    std::optional<std::size_t> best_;
};

}  // namespace

std::string ParseError::to_string() const {
    std::ostringstream os;
    os << source;
    if (kind != Kind::io && line > 0) os << ':' << line << ':' << column;
    switch (kind) {
        case Kind::io:
        case Kind::memory: os << ": " << message; break;
        case Kind::syntax: os << ": syntax error: " << message; break;
        case Kind::schema: os << ": " << key << ": " << message; break;
    }
    return os.str();
}

namespace {

// The text as nlohmann-json reads it, one character at a time, telling a Progress how far
// it has come every 64 kB (one test and a rare store per character; nothing without one).
class CountingIterator {
public:
    using iterator_category = std::input_iterator_tag;
    using value_type = char;
    using difference_type = std::ptrdiff_t;
    using pointer = const char*;
    using reference = const char&;
    CountingIterator(const char* p, const char* begin, Progress* progress) : p_(p), begin_(begin), progress_(progress) {}
    reference operator*() const { return *p_; }
    CountingIterator& operator++() {
        ++p_;
        if (((p_ - begin_) & 0xFFFF) == 0 && progress_) progress_->set(std::uint64_t(p_ - begin_));
        return *this;
    }
    CountingIterator operator++(int) {
        CountingIterator old = *this;
        ++*this;
        return old;
    }
    bool operator==(const CountingIterator& o) const { return p_ == o.p_; }
    bool operator!=(const CountingIterator& o) const { return p_ != o.p_; }

private:
    const char* p_;
    const char* begin_;
    Progress* progress_;
};

}  // namespace

ParseResult parse_scene(std::string_view text, std::string_view source_name, Progress* progress) noexcept {
    ParseResult r;
    try {
        r.error.source = std::string(source_name);
        if (const int at = nesting_depth_error_offset(text); at >= 0) {
            r.error.kind = ParseError::Kind::syntax;
            line_column(text, std::size_t(at), r.error.line, r.error.column);
            r.error.message = "arrays and objects nested more than " + std::to_string(max_nesting) + " deep";
            return r;
        }
        json root;
        try {
            if (progress) {
                progress->phase("parsing", text.size());
                root = json::parse(CountingIterator(text.data(), text.data(), progress),
                                   CountingIterator(text.data() + text.size(), text.data(), progress));
                progress->finish();
            } else {
                root = json::parse(text.begin(), text.end());
            }
        } catch (const json::parse_error& e) {
            r.error.kind = ParseError::Kind::syntax;
            // e.byte is the 1-based offset of the last character read: the offending one.
            line_column(text, e.byte > 0 ? e.byte - 1 : 0, r.error.line, r.error.column);
            std::string msg = e.what();
            // "[json.exception.parse_error.101] parse error at line 1, column 2: syntax error while parsing ..."
            if (const auto p = msg.find("syntax error while "); p != std::string::npos) msg = msg.substr(p + 19);
            else if (const auto q = msg.rfind(": "); q != std::string::npos) msg = msg.substr(q + 2);
            r.error.message = msg;
            return r;
        } catch (const json::out_of_range& e) {
            // 406: a number that overflows a double (1e400); the exception carries no position,
            // so the scan finds the number.
            r.error.kind = ParseError::Kind::schema;
            const std::optional<Finding> f = Scan(text, Scan::Find::overflowing_number).run();
            if (!f) {
                r.error.key = "(scene)";
                r.error.message = std::string("cannot be read: ") + e.what();
                return r;
            }
            r.error.key = f->path;
            line_column(text, f->at, r.error.line, r.error.column);
            const std::string shown = f->token.size() > 40 ? f->token.substr(0, 37) + "..." : f->token;
            r.error.message = "expected a finite number of magnitude at most 1e100, got " + shown;
            return r;
        }
        // nlohmann-json takes a NUL byte for the end of the input: whatever follows a complete
        // value after one would be ignored without a word.
        if (const std::size_t nul = text.find('\0'); nul != std::string_view::npos) {
            r.error.kind = ParseError::Kind::syntax;
            line_column(text, nul, r.error.line, r.error.column);
            r.error.message = "unexpected NUL byte after the JSON value";
            return r;
        }
        if (const std::optional<Finding> d = Scan(text, Scan::Find::duplicate_key).run()) {
            r.error.kind = ParseError::Kind::schema;
            r.error.key = d->path;
            line_column(text, d->at, r.error.line, r.error.column);
            int line = 0, column = 0;
            line_column(text, d->first, line, column);
            r.error.message = "duplicate key (first given at line " + std::to_string(line) + ", column " +
                              std::to_string(column) + ")";
            return r;
        }
        try {
            r.scene = read_scene(root, progress);
        } catch (const SchemaError& e) {
            r.error.kind = ParseError::Kind::schema;
            r.error.key = e.key;
            r.error.message = e.message;
            if (const std::optional<std::size_t> at = Locate(text, e.key, e.at_key).run())
                line_column(text, *at, r.error.line, r.error.column);
        }
    } catch (const std::exception& e) {
        r.scene.reset();
        r.error.kind = ParseError::Kind::schema;
        r.error.key = "(scene)";
        r.error.line = r.error.column = 0;
        r.error.message = std::string("cannot be read: ") + e.what();
    } catch (...) {
        r.scene.reset();
        r.error.kind = ParseError::Kind::schema;
        r.error.key = "(scene)";
        r.error.line = r.error.column = 0;
        r.error.message = "cannot be read";
    }
    return r;
}

namespace {

ParseResult io_error(const std::string& path, std::string message) {
    ParseResult r;
    r.error.kind = ParseError::Kind::io;
    r.error.source = path;
    r.error.message = std::move(message);
    return r;
}

const char* file_kind(mode_t mode) {
    if (S_ISFIFO(mode)) return "a fifo";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "a special file";
}

struct Fd {
    int fd;
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
};

}  // namespace

// The file is opened without blocking (a fifo with no writer would block open(2)) and
// checked with fstat before a byte is read: a directory, a fifo or a device, and a file
// over max_scene_bytes, get their own message.
ParseResult load_scene(const std::string& path, Progress* progress) noexcept {
    try {
        const Fd f{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY)};
        if (f.fd < 0) return io_error(path, std::string("cannot open the file: ") + std::strerror(errno));
        struct stat st {};
        if (::fstat(f.fd, &st) != 0)
            return io_error(path, std::string("cannot read the file: ") + std::strerror(errno));
        if (S_ISDIR(st.st_mode)) return io_error(path, "is a directory, not a scene file");
        if (!S_ISREG(st.st_mode))
            return io_error(path, std::string("is not a regular file (") + file_kind(st.st_mode) + ")");
        auto too_large = [&](long long bytes) {
            const long long mb = 1'000'000;
            return io_error(path, "is " + std::to_string((bytes + mb - 1) / mb) + " MB, over the limit of " +
                                      std::to_string(max_scene_bytes / mb) + " MB for a scene file");
        };
        if (st.st_size > max_scene_bytes) return too_large(st.st_size);
        std::string text(std::size_t(st.st_size), '\0');
        std::size_t got = 0;
        if (progress) progress->phase("reading", std::uint64_t(st.st_size));
        for (;;) {
            if (got == text.size()) {  // the file may have grown since fstat
                if (text.size() > std::size_t(max_scene_bytes)) return too_large((long long)text.size());
                text.resize(text.size() + 65536);
            }
            const ssize_t n = ::read(f.fd, text.data() + got, text.size() - got);
            if (n < 0 && errno == EINTR) continue;
            if (n < 0) return io_error(path, std::string("cannot read the file: ") + std::strerror(errno));
            if (n == 0) break;
            got += std::size_t(n);
            if (progress) progress->set(got);
        }
        text.resize(got);
        if (progress) progress->finish();
        if (const std::string no = refusal(scene_text_need(text), available_memory(), "parse it"); !no.empty()) {
            ParseResult r = io_error(path, no);
            r.error.kind = ParseError::Kind::memory;
            return r;
        }
        return parse_scene(text, path, progress);
    } catch (...) {
        return io_error(path, "cannot read the file");
    }
}

}  // namespace rayproof::render
