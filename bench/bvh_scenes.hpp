// bench/bvh_scenes.hpp — the generated scenes of the BVH benchmarks (issue #18), one
// definition shared by the scene generator (scene_gen.cpp, which writes them as tracer
// scene files) and the ray benchmark (bvh_bench.cpp, which builds them in memory):
//
//   mixed scene     n objects on a floor plane for the tracer: spheres, axis-aligned boxes,
//                   rotated boxes, glass spheres and boxes, chrome spheres, mirror panels,
//                   on a jittered grid of cells (one object per cell, so that objects
//                   seldom overlap) whose side grows as sqrt(n): the 2,000- and
//                   100,000-object scenes are the same field at two sizes. The camera
//                   looks down on the field from one corner; two lights.
//   sphere set      n balls (float) with centres uniform in the cube [-50, 50]^3 and radii
//                   uniform in [0.1, 0.6] (the ray benchmark's scene; also written as a
//                   tracer scene by the generator, same seed, same balls).
//   ray sets        rays against the sphere set, every origin outside every ball (at
//                   distance >= 110 from the centre of the cube, whose balls lie within
//                   50·sqrt(3) + 0.6 < 87.2 of it), t_min = 0, t_max = +inf:
//                     camera   origins on the sphere of radius 120 about the cube's
//                              centre, each aimed at a uniform point of the cube;
//                     grazing  each aimed at a point of the silhouette of a random ball
//                              as seen along a random direction (origin = that point
//                              − 200·direction, then rounded to float): tangent to that
//                              ball up to the rounding of the origin, the hard case of
//                              the closest-hit question.
//
// Every number comes from the seeded SplitMix64 stream below (no standard distribution,
// whose results differ between standard libraries), so a seed names the same scene on
// every platform. Tracer coordinates are rounded to multiples of 0.001 (short, exact-ish
// text; the scene's numbers are then what the file says, read back exactly).
#pragma once

#include <rayproof/types.hpp>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace rayproof::bench {

// SplitMix64 (Steele, Lea, Flood: "Fast splittable pseudorandom number generators", 2014).
class SceneRng {
public:
    explicit SceneRng(std::uint64_t seed) : s_(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ULL);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        return z ^ (z >> 31);
    }
    // Uniform in [0, 1): the top 53 bits.
    double unit() { return double(next() >> 11) * 0x1p-53; }
    double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
    std::size_t below(std::size_t n) { return std::size_t(unit() * double(n)); }
    // A uniform direction (the normalized Gaussian-free way: rejection from the cube).
    Vec3<double> direction() {
        for (;;) {
            const Vec3<double> v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
            const double n2 = v.squaredNorm();
            if (n2 > 1e-6 && n2 <= 1) return v / std::sqrt(n2);
        }
    }

private:
    std::uint64_t s_;
};

// ---- the mixed tracer scene -----------------------------------------------------------
enum class ObjectKind { sphere, box, oriented_box };

struct SceneObject {
    ObjectKind kind = ObjectKind::sphere;
    Vec3<double> a, b;     // sphere: centre, (radius, -, -); box: min, max; oriented box: centre, size
    Vec3<double> rotation{0, 0, 0};  // oriented box: degrees about x, y, z
    std::string material;
};

struct MixedScene {
    double half_side = 0;  // the field is [-half_side, half_side] in x and z
    Vec3<double> camera, look_at;
    std::vector<SceneObject> objects;
};

// Rounded to a multiple of 0.001 (the decimal the scene file holds).
inline double milli(double v) { return std::round(v * 1000) / 1000; }

inline MixedScene mixed_scene(std::size_t n, std::uint64_t seed) {
    SceneRng rng(seed);
    MixedScene s;
    const double cell = 2.0;
    const std::size_t per_side = std::size_t(std::ceil(std::sqrt(double(n))));
    s.half_side = cell * double(per_side) / 2;
    // Cells in a random order: the first n of them hold an object.
    std::vector<std::size_t> cells(per_side * per_side);
    for (std::size_t i = 0; i < cells.size(); ++i) cells[i] = i;
    for (std::size_t i = cells.size(); i > 1; --i) std::swap(cells[i - 1], cells[rng.below(i)]);
    static const char* const diffuse[] = {"red", "orange", "yellow", "green", "teal", "blue", "violet", "white"};
    for (std::size_t k = 0; k < n; ++k) {
        const double x0 = -s.half_side + cell * double(cells[k] % per_side);
        const double z0 = -s.half_side + cell * double(cells[k] / per_side);
        const double size = rng.uniform(0.35, 0.85);  // the object's half width, below cell / 2
        const double cx = milli(x0 + cell / 2 + rng.uniform(-1, 1) * (cell / 2 - size));
        const double cz = milli(z0 + cell / 2 + rng.uniform(-1, 1) * (cell / 2 - size));
        // One object in four floats above the floor (up to 3 units).
        const double lift = rng.unit() < 0.25 ? rng.uniform(0.2, 3.0) : 0.0;
        const double pick = rng.unit(), look = rng.unit();
        SceneObject o;
        if (pick < 0.03) {  // a mirror panel: a thin upright box, turned about y
            o.kind = ObjectKind::oriented_box;
            const double h = rng.uniform(1.2, 2.4);
            o.a = Vec3<double>(cx, milli(h / 2), cz);
            o.b = Vec3<double>(milli(2 * size * 1.2), milli(h), 0.05);
            o.rotation = Vec3<double>(0, milli(rng.uniform(0, 180)), 0);
            o.material = "mirror";
        } else if (pick < 0.48) {
            o.kind = ObjectKind::sphere;
            const double r = milli(size);
            o.a = Vec3<double>(cx, milli(r + lift), cz);
            o.b = Vec3<double>(r, 0, 0);
            o.material = look < 0.10 ? "glass" : look < 0.20 ? "chrome" : diffuse[rng.below(8)];
        } else if (pick < 0.74) {
            o.kind = ObjectKind::box;
            const double h = milli(rng.uniform(0.4, 1.6) * size);
            o.a = Vec3<double>(milli(cx - size * 0.8), milli(lift), milli(cz - size * 0.8));
            o.b = Vec3<double>(milli(cx + size * 0.8), milli(lift + 2 * h), milli(cz + size * 0.8));
            o.material = look < 0.08 ? "glass" : diffuse[rng.below(8)];
        } else {
            o.kind = ObjectKind::oriented_box;
            const double e = milli(size * 1.1);  // edge; the half diagonal e·sqrt(3)/2 < size·1.1·0.87 < cell / 2
            o.a = Vec3<double>(cx, milli(e + lift), cz);
            o.b = Vec3<double>(e, e, e);
            o.rotation = Vec3<double>(milli(rng.uniform(0, 90)), milli(rng.uniform(0, 90)), milli(rng.uniform(0, 90)));
            o.material = look < 0.08 ? "glass" : diffuse[rng.below(8)];
        }
        s.objects.push_back(o);
    }
    // From one corner, above the field, looking at a point a third of the way in.
    const double h = s.half_side;
    s.camera = Vec3<double>(milli(-1.05 * h), milli(0.2 * h + 4), milli(1.05 * h));
    s.look_at = Vec3<double>(milli(-0.3 * h), 0, milli(0.3 * h));
    return s;
}

// ---- the ray benchmark's sphere set and rays ----------------------------------------
inline std::vector<Sphere<float>> sphere_set(std::size_t n, std::uint64_t seed) {
    SceneRng rng(seed);
    std::vector<Sphere<float>> out;
    out.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const float x = float(rng.uniform(-50, 50)), y = float(rng.uniform(-50, 50)), z = float(rng.uniform(-50, 50));
        out.push_back(Sphere<float>{Vec3<float>(x, y, z), float(rng.uniform(0.1, 0.6))});
    }
    return out;
}

enum class RaySet { camera, grazing };
inline const char* ray_set_name(RaySet s) { return s == RaySet::camera ? "camera" : "grazing"; }

inline std::vector<Ray<float>> ray_set(RaySet which, const std::vector<Sphere<float>>& spheres, std::size_t n,
                                       std::uint64_t seed) {
    SceneRng rng(seed);
    std::vector<Ray<float>> out;
    out.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        Vec3<double> o, d;
        if (which == RaySet::camera) {
            o = 120 * rng.direction();
            const Vec3<double> target(rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-50, 50));
            d = (target - o).normalized();
        } else {
            const Sphere<float>& s = spheres[rng.below(spheres.size())];
            d = rng.direction();
            // u: a unit vector perpendicular to d (Gram-Schmidt against a random vector).
            Vec3<double> u;
            do {
                const Vec3<double> v = rng.direction();
                u = v - v.dot(d) * d;
            } while (u.norm() < 0.1);
            u.normalize();
            const Vec3<double> p = s.center.cast<double>() + double(s.radius) * u;
            o = p - 200 * d;
        }
        Ray<float> r;
        r.origin = o.cast<float>();
        r.direction = d.cast<float>();
        out.push_back(r);
    }
    return out;
}

}  // namespace rayproof::bench
