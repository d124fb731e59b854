// Scene files: JSON text to Scene. Syntax errors come from nlohmann-json (with the line
// and column computed from its byte offset); the schema is checked here, key by key,
// so that every error names the key path and what was expected. Nothing escapes
// parse_scene: every exception is caught and turned into a ParseError.
#include <rayproof/render/parse.hpp>

#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <map>
#include <sstream>

namespace rayproof::render {

namespace {

using json = nlohmann::json;

// Geometry and colours are limited to this magnitude so that squares and products in the
// tracer stay finite; the kernel itself takes any finite input.
constexpr double max_magnitude = 1e100;
constexpr int max_nesting = 64;
constexpr int max_image_side = 16384;
constexpr long long max_pixels = 1LL << 26;

struct SchemaError {
    std::string key;
    std::string message;
};

[[noreturn]] void fail(const std::string& key, const std::string& message) { throw SchemaError{key, message}; }

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

std::string join_path(const std::string& parent, const std::string& key) {
    const std::string shown = key.empty() ? "\"\"" : key;  // an empty key is still named
    return parent.empty() ? shown : parent + "." + shown;
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
                fail(join_path(path_, item.key()), "unknown key (expected one of: " + list + ")");
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
    fail(path + ".type", "expected \"sphere\", \"box\", \"cube\", \"oriented_box\" or \"plane\", got \"" + type + "\"");
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

Scene read_scene(const json& root) {
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
            s.materials.push_back(read_material(item.value(), "materials." + item.key(), item.key()));
        }
    }
    const json& os = top.get("objects");
    if (!os.is_array()) fail("objects", "expected an array of objects, got " + type_name(os));
    for (std::size_t i = 0; i < os.size(); ++i) {
        const std::string path = "objects[" + std::to_string(i) + "]";
        const json& oj = os[i];
        if (!oj.is_object()) fail(path, "expected an object, got " + type_name(oj));
        if (!oj.contains("type")) fail(path + ".type", "missing (required): one of sphere, box, cube, oriented_box, plane");
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
    }
    return s;
}

}  // namespace

std::string ParseError::to_string() const {
    std::ostringstream os;
    os << source;
    switch (kind) {
        case Kind::io: os << ": " << message; break;
        case Kind::syntax: os << ':' << line << ':' << column << ": syntax error: " << message; break;
        case Kind::schema: os << ": " << key << ": " << message; break;
    }
    return os.str();
}

ParseResult parse_scene(std::string_view text, std::string_view source_name) noexcept {
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
            root = json::parse(text.begin(), text.end());
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
        }
        try {
            r.scene = read_scene(root);
        } catch (const SchemaError& e) {
            r.error.kind = ParseError::Kind::schema;
            r.error.key = e.key;
            r.error.message = e.message;
        }
    } catch (const std::exception& e) {
        r.scene.reset();
        r.error.kind = ParseError::Kind::schema;
        r.error.key = "(scene)";
        r.error.message = std::string("cannot be read: ") + e.what();
    } catch (...) {
        r.scene.reset();
        r.error.kind = ParseError::Kind::schema;
        r.error.key = "(scene)";
        r.error.message = "cannot be read";
    }
    return r;
}

ParseResult load_scene(const std::string& path) noexcept {
    try {
        std::ifstream in(path, std::ios::binary);
        if (!in) {
            ParseResult r;
            r.error.kind = ParseError::Kind::io;
            r.error.source = path;
            r.error.message = "cannot open the file";
            return r;
        }
        std::ostringstream ss;
        ss << in.rdbuf();
        return parse_scene(ss.str(), path);
    } catch (...) {
        ParseResult r;
        r.error.kind = ParseError::Kind::io;
        r.error.source = path;
        r.error.message = "cannot read the file";
        return r;
    }
}

}  // namespace rayproof::render
