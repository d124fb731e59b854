// rayproof/render/tracer.hpp — a Whitted-style recursive ray tracer on top of the kernel.
//
// Which objects a ray asks is decided by a BVH over the scene (rayproof::Bvh, built once
// per render; planes and unbounded polyhedra sit beside its tree): camera, reflected,
// refracted and shadow rays, and the visible lights' spheres, all go through it.
// Every ray query is a kernel call in the scene's mode: rayproof::intersect for primary,
// reflected and refracted rays and the spheres of visible lights, rayproof::verdict (the
// yes/no query) for shadow rays against opaque solids, which need no t (against a plane
// or a transparent solid the full answer, to tell a segment lying in the plane from one
// crossing it, and to count the surfaces crossed). Lighting per RGB channel:
//   I_local = I_a·K_a + Σ_lights f_att·I_l·S·(K_d·(N·L) + K_s·(R·V)^n)   [or K_s·(N·H)^n, Blinn]
//             (N·L < 0 instead: f_att·I_l·S'·K_d·k_dt·(-N·L), the translucency k_dt)
//   f_att   = min(1 / (c1 + c2·d + c3·d²), 1)
//   S       = 0 if an opaque object blocks the segment to the light, else K_t for each
//             surface of a transparent object the segment crosses (S': the segment that
//             leaves on the far side)
//   I       = (1 - K_t)·(I_local + k_r·I_reflected) + K_t·I_transmitted
// A reflected or refracted node of the ray tree is weighed by the scene's tree attenuation
// of its distance from its parent (scene.hpp); a ray that meets a visible light's sphere
// first takes the light's colour.
// Terms whose angle exceeds 90° are dropped (N·L <= 0: no diffuse, no specular and no
// shadow ray unless translucent; R·V < 0 or N·H < 0: no specular). Recursion stops at
// the maximum depth, when a ray leaves the scene (background colour) or meets a light,
// or when the weight of a secondary ray falls below RenderSettings::min_contribution.
// Shadow rays are traced only towards lights, reflected rays only for reflective
// materials, refracted rays only for transparent ones.
//
// Inside and outside: a solid (sphere, box, polyhedron) whose interval starts at the
// ray's t_min (boxes, polyhedra: face == -1) contains the ray's origin; the ray then meets
// the surface where it leaves, at t_exit (boxes, polyhedra: the exit face is the entry
// face of rayproof::reversed(ray)), and refraction goes from the solid's index to 1.
// Planes are surfaces, not solids: a transparent plane is a thin sheet that lets rays
// through undeviated; a ray lying in a
// plane does not see it.
//
// Secondary-ray origins: see SurfacePoint::offset below (no fixed epsilon).
#pragma once

#include <rayproof/bvh.hpp>
#include <rayproof/closest.hpp>
#include <rayproof/detail/rounding.hpp>
#include <rayproof/surface_point.hpp>
#include <rayproof/render/image.hpp>
#include <rayproof/render/progress.hpp>
#include <rayproof/render/scene.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace rayproof::render {

// How secondary rays leave a surface.
//   error_bound: the origin is moved off the surface along the normal by a distance
//                derived from error bounds (see SurfacePoint), t_min = 0.
//   naive:       the origin is the computed point o + t·d, unmoved, and the ray
//                starts at the fixed t_min `naive_t_min` (unit direction). Kept only
//                to show, in the tests, the shadow acne it produces.
enum class OffsetPolicy { error_bound, naive };

struct TraceOptions {
    OffsetPolicy offset = OffsetPolicy::error_bound;
    double naive_t_min = 1e-4;
    // The bounding-sphere pre-filter of convex polyhedra (polyhedron.hpp), certified mode
    // only (where it pays, see tracer.cpp): a ray whose certified verdict on the ball is a
    // miss is not asked against the planes. Off: every plane is asked. The image is the
    // same either way (the ball holds the solid exactly); switchable to measure it.
    bool polyhedron_prefilter = true;
    // Which objects a ray asks: those the scene's BVH (rayproof/bvh.hpp, one per render)
    // offers as candidates, or, off, every object in turn (the brute force the BVH must
    // equal; kept for the tests and to measure it). In certified mode the image is the
    // same bit for bit either way (tracer.cpp derives why); fast and conservative promise
    // no agreement with the exact answer, so neither can the BVH's culling of them.
    bool bvh = true;
};

struct Stats {
    std::uint64_t primary = 0, shadow = 0, reflection = 0, refraction = 0;  // rays traced, by kind
    std::uint64_t kernel_queries = 0;  // rayproof::intersect calls
    std::uint64_t invalid = 0;         // queries answered Verdict::invalid (treated as a miss)
    std::uint64_t culled = 0;          // secondary rays not traced: weight below min_contribution
    std::uint64_t shadowed = 0;        // shadow rays that found the light fully blocked
    Stats& operator+=(const Stats& o);
};

struct RenderOptions {
    int threads = 0;        // threads rendering rows (0: every hardware thread), never more than rows
    bool progress = false;  // draw a progress bar on stderr if the render lasts over a second
    Progress* reporter = nullptr;  // or report the rows here (progress.hpp), the phase "rendering"
    TraceOptions trace;
};

struct RenderResult {
    Image image;
    Stats stats;
    double seconds = 0;
    int threads = 0;  // the threads that rendered it: RenderOptions::threads, at most the rows
};

// Renders scene.settings.width × height pixels in scene.settings.mode, the rows shared
// out among the threads. The image and the counts are the same for any number of threads.
RenderResult render(const Scene& scene, const RenderOptions& options = {});

// The width of the tracer's BVH nodes, Bvh<double, scene_bvh_width>: the kernel's
// bvh_native_width (bvh.hpp, with the measurement), 8 where the build targets AVX2 and 4
// otherwise. The answers are the same for every width.
inline constexpr int scene_bvh_width = bvh_native_width<double>;

// The scene's objects and the spheres of its visible lights as the kernel's primitives,
// in that order (object i is primitive i; the k-th visible light's sphere is primitive
// objects + k): what the tracer's BVH is built over. A polyhedron's planes stay the
// Scene's: the Scene must outlive the primitives.
std::vector<::rayproof::Primitive<double>> scene_primitives(const Scene& scene);

// The primary ray through image point (px, py), in pixel units with y pointing down:
// the centre of pixel (x, y) is (x + 0.5, y + 0.5).
Ray<double> camera_ray(const Camera& cam, int width, int height, double px, double py);

// The colour (linear, unclamped) seen along the primary ray through (px, py), traced in
// scene.settings.mode.
Color radiance(const Scene& scene, double px, double py, const TraceOptions& options = {}, Stats* stats = nullptr);

// --- building blocks, exposed for the tests ------------------------------------------

// gamma(n) = n·u / (1 - n·u), u = 2^-53: bounds the relative error of n correctly
// rounded double operations (the kernel's rayproof::detail::gamma, detail/rounding.hpp).
constexpr double gamma_bound(int n) { return ::rayproof::detail::gamma<double>(n); }

// A point where a ray meets a surface, ready for shading and for spawning rays.
struct SurfacePoint {
    Vec3d p;             // the hit point (projected back onto the surface where the shape allows)
    Vec3d n;             // unit normal facing the side the incoming ray came from
    double offset = 0;   // distance to move secondary-ray origins off the surface (see below)
    bool inside = false; // the incoming ray travelled inside the solid (it is leaving it)
};

// offset = E + K, both stated bounds on distances along the normal:
//   E is the kernel's spawn offset (rayproof/surface_point.hpp, where each bound is
//     derived): the hit point comes from rayproof::surface_point, which brings it onto
//     the surface where the shape allows and bounds per component its distance from a
//     point exactly on the surface, and rayproof::spawn_offset turns that bound into a
//     distance along the normal:
//     Aabb:   only the floor of spawn_offset — the coordinate on the face's axis is set
//             to lo or hi exactly, the others clamped into the face;
//     Sphere: p = c + v·(r/|v|), v = o + t·d - c (pbrt-v4 6.8.5 reprojection), within
//             gamma(7)·(|c_i| + |v'_i|) of a point on the sphere per coordinate;
//     Plane, Obb: a posteriori, from the residual g = n·p - offset (or (p-c)·a - h);
//     Polyhedron: as the Plane of the face met (entry face, or exit face from inside).
//   K keeps the new origin out of the band where the kernel itself, queried again from
//   there, could still report the surface just left. From the kernel's stated error
//   models: fast evaluates n operations with relative error γ(n); conservative moves
//   each interval end one step outward after round-to-nearest, 1.5 ulp <= 3u per
//   operation, so γ(3n) for the same n operations; K takes the larger, γ(3n):
//     Aabb: 0 (a slab value (lo_i - o_i)/d_i keeps the sign of lo_i - o_i, and the
//           origin is one ulp past the face);
//     Obb:  γ(12)·Σ_j|(p - c)_j·a_j| / |a| (o'_i: a difference, a product, two sums);
//     Plane: γ(12)·(|offset| + Σ|n_i p_i|) / |n| (the numerator: a product, three sums);
//     Polyhedron: the Plane's, for the face met (each plane's crossing is evaluated as a
//           plane's);
//     Sphere: γ(24)·r (the fast mode's tangency band γ(8)·|Δ|, |Δ| ≈ r there).
//   Conservative mode widens a plain evaluation by derived bounds (pbrt-v4's manner), and
//   its answer's ends can lie further out than γ(3n) allows, so there K follows from the
//   kernel's stated enclosures instead (tracer.cpp derives each): Sphere γ(105)·r, Plane
//   γ(13)·(|offset| + Σ|n_i p_i|)/|n|, Obb γ(25)·Σ_j|(p - c)_j·a_j|/|a|, Aabb 0 (the
//   widened slab value stays negative past the underflow floor), Polyhedron γ(22)·(|offset|
//   + Σ|n_i p_i|)/|n| for the face met (ray_polyhedron.hpp, poly_leaving_margin: its
//   enclosure of a crossing is 3(e_N + |q|·e_D)/|D| wide, and where D is within a few
//   times its bound e_D also the quotient of the two enclosures, so a grazing ray leaving
//   the face is answered miss on it from that distance).
// The sum is then scaled by (1 + γ(4)) to cover the rounding of these very formulas.
// The γ bounds hold only while no result underflows: a face at 0 pushed one ulp to
// 2^-1074 gives a slab or plane quotient 2^-1074/d that rounds to -0, "hit at t = 0".
// So the distance moved is at least underflow_floor(p, d) for the new direction d.
// This is the only distance by which rays leave surfaces; there is no other epsilon.
// The origin is moved by the kernel's rayproof::offset_origin (each coordinate by
// dist·n_i and one float further in the direction of n_i, pbrt-v4's OffsetRayOrigin).

// 2^-60·max(|p|_inf, |d|_inf): below one rounding unit (2^-52) of the largest
// coordinate involved, so it never outweighs a non-zero error bound there; it only
// acts where the bound is exactly 0 and a coordinate is 0 or tiny, and keeps the next
// query's quotients (|numerator| >= 2^-60·|d|, denominator <= |d|·|n|) far from
// underflow, and its inputs in the range the kernel's fast exact stage handles.
double underflow_floor(const Vec3d& p, const Vec3d& d);

// R = u - 2(u·N)N.
Vec3d reflect(const Vec3d& u, const Vec3d& n);
// Snell's law for the unit incoming direction u and the unit normal n facing u's side
// (u·n <= 0), eta = eta_incident / eta_transmitted; nullopt on total internal reflection.
std::optional<Vec3d> refract(const Vec3d& u, const Vec3d& n, double eta);

}  // namespace rayproof::render
