// rayproof/render/scene.hpp — the scene the tracer renders: camera, lights, materials,
// objects and render settings, all in double. A Scene is plain data; scene files are
// read by parse_scene (parse.hpp), whose schema is documented in render/scenes/README.md.
#pragma once

#include <rayproof/rayproof.hpp>
#include <rayproof/render/polyhedron.hpp>

#include <Eigen/Core>

#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace rayproof::render {

using Vec3d = Eigen::Vector3d;
using Color = Eigen::Array3d;  // linear RGB, one value per channel

// The kernel mode every ray query of a render uses: the kernel's run-time mode, named and
// parsed by the kernel's mode_name and parse_mode.
using Mode = ::rayproof::RuntimeMode;
using ::rayproof::mode_name;
using ::rayproof::parse_mode;
inline constexpr Mode all_modes[] = {Mode::fast, Mode::conservative, Mode::certified};

// Pinhole camera: the eye is the centre of projection; the projection plane is at unit
// distance along the view direction; fov is the vertical field of view in degrees.
struct Camera {
    Vec3d position{0, 0, 5};
    Vec3d look_at{0, 0, 0};
    Vec3d up{0, 1, 0};
    double fov = 45;
};

// Point light. Attenuation f_att = min(1 / (c1 + c2·d + c3·d²), 1), d the distance.
// A light with radius > 0 is also seen: camera, reflected and refracted rays that meet the
// sphere of that radius around it before any object take its colour (the notes' "a ray
// that reaches an opaque light source takes the light's colour"); it casts no shadow and
// still lights the scene from its centre. radius 0: a point, never seen.
struct Light {
    Vec3d position{0, 0, 0};
    Color color{1, 1, 1};
    double c1 = 1, c2 = 0, c3 = 0;
    double radius = 0;
    bool visible() const { return radius > 0; }
};

// The ray tree's distance attenuation (the notes: the intensity at each node of the ray
// tree is attenuated by its distance from the parent node): a reflected or refracted
// ray's colour is weighed by f = min(1 / (c1 + c2·d + c3·d²), 1), d the distance from the
// point it leaves to the point it meets (a ray that meets nothing brings the background,
// unweighed: the background is no node). Primary rays are not weighed.
struct TreeAttenuation {
    bool enabled = true;
    double c1 = 1, c2 = 0, c3 = 0.01;
    double factor(double d) const {
        if (!enabled) return 1;
        const double denominator = c1 + c2 * d + c3 * d * d;
        return denominator > 1 ? 1 / denominator : 1;  // min(1 / x, 1), and 1 for x = 0
    }
};

enum class Highlight { phong, blinn };  // K_s·(R·V)^n or K_s·(N·H)^n

struct Material {
    std::string name;
    Color ambient{0, 0, 0};   // K_a
    Color diffuse{0, 0, 0};   // K_d
    Color specular{0, 0, 0};  // K_s
    double shininess = 32;    // n
    Highlight highlight = Highlight::phong;
    Color reflectivity{0, 0, 0};  // weight of the reflected ray
    double transparency = 0;      // K_t: I = (1 - K_t)·(local + reflected) + K_t·transmitted
    double ior = 1;               // index of refraction of the solid (the outside is ior 1)
    // Diffuse transparency (translucency) k_dt: light reaching the surface from behind, from
    // the side the incoming ray did not come from, lights it by K_d·k_dt·(-N·L) (the notes'
    // diffuse refraction, the direct part only: no Monte Carlo estimate of the light
    // scattered in from other surfaces). The shadow ray then leaves on that far side.
    double translucency = 0;
    bool reflective() const { return (reflectivity > 0).any(); }
    bool transparent() const { return transparency > 0; }
};

// A Polyhedron owns its planes (polyhedron.hpp); the tracer queries the kernel's
// ConvexPolyhedron view of them, so a Scene copies and moves like plain data.
using Shape = std::variant<Sphere<double>, Aabb<double>, Obb<double>, Plane<double>, Polyhedron>;

struct Object {
    std::string name;  // "" when the file gave none
    Shape shape;
    int material = 0;  // index into Scene::materials
};

struct RenderSettings {
    int width = 320, height = 240;
    int depth = 5;        // longest ray path, in rays: 1 = primary rays (and their shadow rays) only
    int supersample = 1;  // n: n×n rays per pixel, at the centres of an n×n grid of sub-pixels
    Mode mode = Mode::fast;
    Color background{0, 0, 0};
    double min_contribution = 1.0 / 512;  // a secondary ray whose weight falls below this is not traced
};

struct Scene {
    Camera camera;
    Color ambient_light{0, 0, 0};  // I_a
    TreeAttenuation tree_attenuation;
    std::vector<Light> lights;
    std::vector<Material> materials;
    std::vector<Object> objects;
    RenderSettings settings;
};

}  // namespace rayproof::render
