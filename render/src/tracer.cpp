// The tracer: camera rays, closest hits, shading, secondary rays and the threaded image
// loop. See tracer.hpp for the lighting model and the offset derivation.
#include <rayproof/render/tracer.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

namespace rayproof::render {

std::vector<Primitive<double>> scene_primitives(const Scene& s) {
    std::vector<Primitive<double>> prims;
    prims.reserve(s.objects.size() + s.lights.size());
    for (const Object& o : s.objects)
        std::visit(
            [&](const auto& sh) {
                if constexpr (std::is_same_v<std::decay_t<decltype(sh)>, Polyhedron>)
                    prims.emplace_back(sh.kernel());
                else
                    prims.emplace_back(sh);
            },
            o.shape);
    for (const Light& l : s.lights)
        if (l.visible()) prims.emplace_back(Sphere<double>{l.position, l.radius});
    return prims;
}

namespace {

using Rayd = Ray<double>;
using Hitd = Hit<double>;

constexpr double inf = std::numeric_limits<double>::infinity();

double max3(const Color& c) { return c.maxCoeff(); }

// Which solid-ness a shape has: planes are surfaces, the rest are closed solids.
bool is_plane(const Shape& s) { return std::holds_alternative<Plane<double>>(s); }

struct Candidate {
    int object = -1;
    double t = inf;
    bool inside = false;
    Hitd hit;
};

// The scene's BVH over scene_primitives (tracer.hpp). Planes and unbounded polyhedra sit
// beside the tree (bvh.hpp).
struct SceneBvh {
    std::size_t objects = 0;
    Bvh<double, scene_bvh_width> bvh;
};

SceneBvh build_bvh(const Scene& s) {
    return SceneBvh{s.objects.size(), Bvh<double, scene_bvh_width>(scene_primitives(s))};
}

template <class M> class Tracer {
public:
    // index: the scene's BVH, or null to ask every object (TraceOptions::bvh).
    Tracer(const Scene& scene, const TraceOptions& opt, Stats& stats, const SceneBvh* index = nullptr)
        : s_(scene), opt_(opt), st_(stats), index_(index) {
        for (std::size_t i = 0; i < scene.lights.size(); ++i)
            if (scene.lights[i].visible()) bulbs_.push_back({int(i), {scene.lights[i].position, scene.lights[i].radius}});
    }

    // The colour seen along `ray`, a node of the ray tree at `depth` (1: a primary ray).
    // Below the root a node is weighed by the tree attenuation of its distance from its
    // parent, the ray's origin (scene.hpp); the background is no node and is not weighed.
    Color trace(const Rayd& ray, int depth, double weight) {
        Candidate c;
        BulbHit bulb;
        if (index_) {
            nearest(ray, c, bulb);
        } else {
            c = closest(ray);
            bulb = nearest_bulb(ray, c.t);
        }
        if (c.object < 0 && bulb.light < 0) return s_.settings.background;
        const double t = bulb.light >= 0 ? bulb.t : c.t;
        const double f = depth > 1 ? s_.tree_attenuation.factor(t * ray.direction.norm()) : 1;
        if (bulb.light >= 0) return f * s_.lights[std::size_t(bulb.light)].color;
        return f * shade(ray, c, depth, weight * f);
    }

private:
    Color shade(const Rayd& ray, const Candidate& c, int depth, double weight) {
        const Object& obj = s_.objects[std::size_t(c.object)];
        const Material& mat = s_.materials[std::size_t(obj.material)];
        const SurfacePoint sp = surface(obj.shape, ray, c);
        const Vec3d u = ray.direction.normalized();

        Color local = s_.ambient_light * mat.ambient;
        for (const Light& l : s_.lights) local += light(l, mat, sp, u);

        const bool deeper = depth < s_.settings.depth;
        const double kt = mat.transparency;
        Color reflected = Color::Zero();
        if (deeper && mat.reflective()) {
            const double w = weight * max3(mat.reflectivity) * (1 - kt);
            if (w >= s_.settings.min_contribution) {
                ++st_.reflection;
                reflected = mat.reflectivity * trace(spawn(sp, reflect(u, sp.n), +1), depth + 1, w);
            } else {
                ++st_.culled;
            }
        }
        if (kt <= 0) return local + reflected;

        Color transmitted = Color::Zero();
        if (deeper) {
            const double w = weight * kt;
            if (w >= s_.settings.min_contribution) {
                ++st_.refraction;
                transmitted = trace(transmit(obj, mat, sp, u), depth + 1, w);
            } else {
                ++st_.culled;
            }
        }
        return (1 - kt) * (local + reflected) + kt * transmitted;
    }

    // The visible light whose sphere the ray meets first, before t_limit (the closest
    // object's t), and where; light -1 if none. A ray starting inside a light's sphere
    // sees it.
    struct BulbHit {
        int light = -1;
        double t = inf;
    };
    BulbHit nearest_bulb(const Rayd& ray, double t_limit) {
        BulbHit best{-1, t_limit};
        for (const Bulb& b : bulbs_) {
            const Hitd h = query(ray, Shape(b.sphere));
            if (h && h.t_enter < best.t) best = {b.light, h.t_enter};
        }
        return best;
    }

    Hitd query(const Rayd& r, const Shape& shape) {
        ++st_.kernel_queries;
        const Hitd h = std::visit([&](const auto& sh) { return kernel_hit(r, sh); }, shape);
        if (h.verdict == Verdict::invalid) ++st_.invalid;
        return h;
    }

    // The kernel's answers, in the scene's mode. A polyhedron is asked through its
    // ConvexPolyhedron view, in certified mode after the bounding-sphere pre-filter of the
    // ray-tracing notes when it has a ball (polyhedron.hpp: the ball holds the stored
    // solid exactly, and the certified verdict on it is exact, so a miss of the ball is a
    // miss of the solid: the pre-filter never loses a hit). Measured on
    // scenes/polyhedra.json (render/README.md), it pays only there: in fast and
    // conservative modes asking the ball (conservatively: fast promises nothing) costs
    // more than the few planes it saves, and those modes ask the planes directly.
    template <class S> static Hitd kernel_hit(const Rayd& r, const S& s) { return rayproof::intersect(r, s, M{}); }
    template <class S> static Verdict kernel_verdict(const Rayd& r, const S& s) { return rayproof::verdict(r, s, M{}); }
    bool ball_misses(const Rayd& r, const Polyhedron& p) const {
        if constexpr (!std::is_same_v<M, certified_t>) {
            return false;
        } else {
            if (!p.bound || !opt_.polyhedron_prefilter) return false;
            return rayproof::verdict(r, *p.bound, certified) == Verdict::miss;
        }
    }
    Hitd kernel_hit(const Rayd& r, const Polyhedron& p) const {
        if (ball_misses(r, p)) return Hitd{};
        return rayproof::intersect(r, p.kernel(), M{});
    }
    Verdict kernel_verdict(const Rayd& r, const Polyhedron& p) const {
        if (ball_misses(r, p)) return Verdict::miss;
        return rayproof::verdict(r, p.kernel(), M{});
    }

    // How many times a shadow segment crosses the object's surface: 0 when it misses (a
    // segment lying in a plane does not see it, as in closest()); a plane 1; a solid 2,
    // or 1 when the segment starts or ends inside it (its interval begins at t_min or
    // ends at t_max). A light keeps K_t at each crossing. For an opaque object only
    // "at least one" matters, and solids answer it with the verdict alone.
    int crossings(const Rayd& r, const Object& obj) {
        ++st_.kernel_queries;
        const bool opaque = !s_.materials[std::size_t(obj.material)].transparent();
        return std::visit(
            [&](const auto& sh) -> int {
                constexpr bool plane = std::is_same_v<std::decay_t<decltype(sh)>, Plane<double>>;
                if constexpr (!plane) {
                    if (opaque) {
                        const Verdict v = kernel_verdict(r, sh);
                        if (v == Verdict::invalid) ++st_.invalid;
                        return v == Verdict::hit ? 1 : 0;
                    }
                }
                const Hitd h = kernel_hit(r, sh);
                if (h.verdict == Verdict::invalid) ++st_.invalid;
                if (!h) return 0;
                if constexpr (plane) {
                    return lies_in_plane(r, h) ? 0 : 1;
                } else {
                    return int(h.t_enter > r.t_min) + int(h.t_exit < r.t_max);
                }
            },
            obj.shape);
    }

    // A plane hit that covers the whole range is the ray lying in the plane: not seen.
    static bool lies_in_plane(const Rayd& r, const Hitd& h) {
        return h.t_enter == r.t_min && h.t_exit == r.t_max && h.t_enter < h.t_exit;
    }

    // Object i as a candidate for the closest surface: its key t (where the ray meets the
    // surface: t_enter, or t_exit for a ray starting inside the solid), or none (a miss,
    // or a plane the ray lies in).
    std::optional<Candidate> candidate(const Rayd& ray, std::size_t i) {
        const Shape& shape = s_.objects[i].shape;
        const Hitd h = query(ray, shape);
        if (!h) return std::nullopt;
        Candidate c;
        c.object = int(i);
        c.hit = h;
        if (is_plane(shape)) {
            if (lies_in_plane(ray, h)) return std::nullopt;
            c.t = h.t_enter;
        } else {
            // The interval starts at t_min exactly when the origin is in the solid
            // (boxes say so with face == -1): the surface is then met on the way out.
            c.inside = std::holds_alternative<Sphere<double>>(shape) ? h.t_enter == ray.t_min : h.face < 0;
            c.t = c.inside ? h.t_exit : h.t_enter;
        }
        return c;
    }

    // The brute force: every object in turn, the smallest t, ties to the lowest index.
    Candidate closest(const Rayd& ray) {
        Candidate best;
        for (std::size_t i = 0; i < s_.objects.size(); ++i)
            if (const std::optional<Candidate> c = candidate(ray, i); c && c->t < best.t) best = *c;
        return best;
    }

    // The same answers as closest() and nearest_bulb(ray, closest(ray).t), from the
    // objects and bulbs the BVH offers: the object with the smallest t, ties to the lowest
    // index (whatever the order of the offers), and the bulb with the smallest t_enter
    // (ties to the lowest light) when it is strictly before that object.
    // Culling, certified mode: after each offer the BVH's range is lowered to
    // t_limit = next_up(b), b the smallest key so far (object t or bulb t_enter). An
    // object that could still win or tie has key t <= b. If the ray starts inside it,
    // it is met at t_min <= t_limit. Otherwise t is the faithfully rounded exact entry E
    // (a certified hit, so t_min <= E), and faithful rounding puts E below next_up(t):
    // E = t when E is a double, else E lies strictly between t's two neighbours. So
    // t_min <= E < next_up(t) <= next_up(b) = t_limit: the ray meets the object on
    // [t_min, t_limit] exactly, and the BVH never culls such a primitive (bvh.hpp).
    // A bulb that could win has t_enter <= b likewise. Every possible winner is thus
    // asked, with the very query (the same Ray) brute force asks, so the answer is
    // brute force's bit for bit. In fast and conservative modes t is no exact entry and
    // the same limit only makes agreement likely (those modes promise none).
    void nearest(const Rayd& ray, Candidate& best, BulbHit& bulb) {
        best = Candidate{};
        bulb = BulbHit{};
        double limit = ray.t_max;
        const PreparedRay<double> prepared(ray);
        index_->bvh.for_each_candidate(prepared, M{}, limit, [&](std::size_t i) {
            if (i < index_->objects) {
                const std::optional<Candidate> c = candidate(ray, i);
                if (c && (c->t < best.t || (c->t == best.t && best.object >= 0 && c->object < best.object))) best = *c;
            } else {
                const Bulb& b = bulbs_[i - index_->objects];
                const Hitd h = query(ray, Shape(b.sphere));
                if (h && (h.t_enter < bulb.t || (h.t_enter == bulb.t && bulb.light >= 0 && b.light < bulb.light)))
                    bulb = {b.light, h.t_enter};
            }
            const double b = std::min(best.t, bulb.t);
            if (b < inf) {
                const double up = std::nextafter(b, inf);
                if (up < limit) limit = up;
            }
            return true;
        });
        if (!(bulb.t < best.t)) bulb = BulbHit{-1, best.t};
    }

    // --- the hit point, its normal and its error bound (tracer.hpp: offset = E + K) ----

    SurfacePoint surface(const Shape& shape, const Rayd& ray, const Candidate& c) {
        SurfacePoint sp = std::visit([&](const auto& sh) { return at(sh, ray, c); }, shape);
        sp.offset *= 1 + gamma_bound(4);
        sp.inside = c.inside;
        if (c.inside) sp.n = -sp.n;  // face the side the ray came from (the inside)
        if (opt_.offset == OffsetPolicy::naive) sp.p = ray.origin + c.t * ray.direction;
        return sp;
    }

    // The kernel's surface point (rayproof/surface_point.hpp) at c.t, its bound E as the
    // kernel's spawn offset, and the margin K of tracer.hpp on top.
    SurfacePoint at(const Sphere<double>& s, const Rayd& ray, const Candidate& c) {
        Hitd h = c.hit;
        h.t_enter = c.t;  // the point where the ray meets the surface (t_exit from inside)
        const rayproof::SurfacePoint<double> k = surface_point(ray, s, h);
        SurfacePoint sp;
        sp.p = k.p;
        sp.n = k.n;
        sp.offset = spawn_offset(k) + sphere_margin(s.radius);
        return sp;
    }

    // The margin K of tracer.hpp for a sphere of radius r. Fast (and certified, which
    // needs none): gamma(24)·r. Conservative: gamma(105)·r, beyond the slack of the
    // kernel's enclosure (ray_sphere.hpp, sphere_conservative_common, "Slack": Et, Rh),
    // derived here for a ray o + t·d leaving the sphere: o at distance ρ = r + δ from the
    // centre (δ >= K outside) and d pointing away from it (d·(o - c) >= 0, so the closest
    // approach t* <= 0). In units of t, λ² + t*² = (ρ/|d|)² and the exact answer is behind
    // o or empty. The upper end is at most T + sqrt(max(Rh² - λ², 0)), T = t* + Et:
    //   T < 0: (λ, T) is within Et of (λ, t*), so its norm is at least ρ/|d| - Et; when
    //     that exceeds Rh, sqrt(Rh² - λ²) < |T| and the upper end is negative.
    //   T >= 0: |t*| <= Et, so λ >= ρ/|d| - Et²|d|/ρ (sqrt(x² - y²) >= x - y²/x), and
    //     the kernel proves a miss (D_hi < 0) when λ > Rh, so when ρ/|d| - Et²|d|/ρ > Rh.
    // In lengths (times |d|), with |Δ| = ρ, Sb~ <= (1 + 5u)|d|ρ (Cauchy-Schwarz), M = P~/a
    // <= 2(1 + 7.1u)ρ/|d| (Σ_{i != j}|Δ_i d_j| <= 2|Δ||d|), λ <= ρ/|d| (the line passes no
    // farther from the centre than o) and inv <= (1 + 5.1u)/|d|²: Et·|d| <= 22.41u·ρ;
    // 14.1u·M·λ + 85u²·M² <= 28.3u·(ρ/|d|)², so (sqrt(x²(1 + 2ε) + y) <= x(1 + ε) +
    // y/(2x), (1 + 22.9u)²(1 + 14.1u) <= 1 + 2·30u) (Rh - R)·|d| <= 30u·r + 14.2u·ρ²/r;
    // Et²|d|²/ρ <= 503u²·ρ; the absolute terms at most 2^-497·|d|. With ρ = r + δ and δ
    // <= r (ρ²/r <= r + 3δ) both cases hold when δ(1 - 65.1u) > 66.61u·r + 2^-497·|d| (the
    // u² terms inside the spare below), and δ >= gamma(105)·r gives δ(1 - 65.1u) >=
    // 104.99u·r: 38.3u·r to spare (the margin was derived for the kernel's earlier, looser
    // bound and is kept, so that conservative renders stay as they were), for the absolute
    // terms (r >= 2^-440·|d|: a sphere not 2^-440 times smaller than the way to the light,
    // 2^-497·|d| <= u·r/16) and for a direction turned towards the centre by
    // the normal's error θ (t* <= θρ/|d| adds θ²ρ to the second-order term) up to θ =
    // 2^-27 (θ²ρ about u·r/2). The tracer's rays reach the kernel's interval fallback
    // (|d|² outside [2^-400, 2^1000], r below 2^-300) only for a light within 2^-200 of
    // the point or a sphere of radius below 2^-300. A ray leaving from inside (δ inside)
    // needs nothing: the enclosure's lower end is at most the exact entry, behind o. An
    // origin farther out (δ > r, when the hit point's own error exceeds r) still holds up
    // to δ = 2^45·r: there ρ <= 2δ and 14.2u·ρ²/r <= 56.8u·δ²/r <= 0.23δ. The
    // other modes keep gamma(24)·r bit for bit (their goldens stay).
    static double sphere_margin(double r) {
        if constexpr (std::is_same_v<M, conservative_t>)
            return gamma_bound(105) * r;
        else
            return gamma_bound(24) * r;
    }

    // The face a box ray meets, its parameter and its hit record (entry face, or for a
    // ray inside the box the exit face = the entry face of the reversed ray).
    template <class Box> std::pair<Hitd, Rayd> box_face(const Box& b, const Rayd& ray, const Candidate& c) {
        if (!c.inside) return {c.hit, ray};
        const Rayd rev = reversed(ray);
        Hitd rh = query(rev, b);
        if (!rh || rh.face < 0) {  // inconsistent answers (possible in fast mode): nearest face plane
            rh = c.hit;
            rh.face = nearest_face(b, ray.origin + c.t * ray.direction);
            rh.t_enter = -c.t;
        }
        return {rh, rev};
    }

    // The distance from p to the plane of face f (axis f / 2, the hi side when f is odd).
    static double face_distance(const Aabb<double>& b, int f, const Vec3d& p) {
        return std::abs(p[f / 2] - ((f % 2) ? b.hi[f / 2] : b.lo[f / 2]));
    }
    static double face_distance(const Obb<double>& b, int f, const Vec3d& p) {
        const Vec3d a = b.axes.col(f / 2);
        const double h = (f % 2) ? b.half_extent[f / 2] : -b.half_extent[f / 2];
        return std::abs((p - b.center).dot(a) - h) / a.norm();
    }
    template <class Box> static int nearest_face(const Box& b, const Vec3d& p) {
        int best = 0;
        double dmin = inf;
        for (int f = 0; f < 6; ++f) {
            const double d = face_distance(b, f, p);
            if (d < dmin) dmin = d, best = f;
        }
        return best;
    }

    // The margin K of tracer.hpp for a box face at p: Aabb 0; Obb gamma(12)·Σ_j|(p - c)_j·a_j|
    // / |a|, a the face's column, gamma(25) in conservative mode.
    // Aabb, conservative: the face's exit value x = (hi - o)/d (or lo's) is widened to
    // fl(x + B), B = fl(fl(2·gamma(3)·|x|) + 2^-1022) (ray_aabb.hpp), which stays below 0
    // for |x| > 2^-1021: the origin is at least the underflow floor 2^-60·|d|_inf past
    // the face, so |x| >= 2^-60 and K = 0 still holds.
    // Obb, conservative: each slab value is widened to fl(t~ ± E), E = 2·B0 + 2^-1022
    // with B0 = eo·|inv| + |t~|·(ed·|inv| + 5u) and |t - t~| <= (1 + 2^-18)·B0 + 2^-1074
    // (ray_obb.hpp, obb_conservative_common), so the upper end is at most t + 3.01·B0 +
    // 3·2^-1022. For a ray leaving the face at distance δ, t = -δ|a|/|d'|, |t~| <= (1 +
    // 3u)|t|, ed·|inv| <= 2^-20 and eo <= 8u(1 + 10u)·Σ_j|a_j Δ_j| + 2^-1021: the end is
    // negative when δ|a|(1 - 3.01·2^-20 - 16u) > 24.1u·Σ + 2^-1019·(1 + |d'|), which
    // δ >= gamma(25)·Σ/|a| gives with 0.9u·Σ/|a| to spare for the absolute terms (for
    // Σ >= 2^-960·(1 + |d'|)).
    static double margin(const Aabb<double>&, int, const Vec3d&) { return 0; }
    static double margin(const Obb<double>& b, int face, const Vec3d& p) {
        const Vec3d a = b.axes.col(face / 2);
        const Vec3d pc = p - b.center;
        const double terms = std::abs(pc[0] * a[0]) + std::abs(pc[1] * a[1]) + std::abs(pc[2] * a[2]);
        return gamma_bound(std::is_same_v<M, conservative_t> ? 25 : 12) * terms / a.norm();
    }

    // A box's surface point: on the face box_face names, at its t_enter (the kernel brings
    // an Aabb's point onto the face exactly, E = 0, and bounds an Obb's a posteriori).
    template <class Box>
        requires std::is_same_v<Box, Aabb<double>> || std::is_same_v<Box, Obb<double>>
    SurfacePoint at(const Box& b, const Rayd& ray, const Candidate& c) {
        const auto [h, r] = box_face(b, ray, c);
        const rayproof::SurfacePoint<double> k = surface_point(r, b, h);
        SurfacePoint sp;
        sp.p = k.p;
        sp.n = k.n;
        sp.offset = spawn_offset(k) + margin(b, h.face, sp.p);
        return sp;
    }

    // A polyhedron's surface point: on the plane of its entry face, or for a ray inside it
    // of its exit face, the entry face of the reversed ray (as for boxes; where fast mode
    // answers inconsistently, the face plane nearest the point). The point and its bound
    // E are the kernel's for that plane (rayproof::surface_point of the Plane), the normal
    // the plane's outward unit normal, and the margin K of tracer.hpp, c·(|offset| +
    // Σ|n_i p_i|)/|n|: fast, c = gamma(12), the plane's (each plane's crossing is
    // evaluated as a plane's: num and den of a product and three sums); conservative, c =
    // detail::poly_leaving_margin = gamma(22), which ray_polyhedron.hpp derives for its
    // enclosure of the crossing (a ray leaving the face from that distance is answered
    // miss on it, however grazing).
    SurfacePoint at(const Polyhedron& poly, const Rayd& ray, const Candidate& c) {
        Hitd h = c.hit;
        Rayd r = ray;
        if (c.inside) {
            r = reversed(ray);
            ++st_.kernel_queries;
            h = kernel_hit(r, poly);
            if (h.verdict == Verdict::invalid) ++st_.invalid;
            if (!h || h.face < 0) h = Hitd{Verdict::hit, -c.t, -c.t, -1};
        } else {
            h.t_enter = c.t;
        }
        if (h.face < 0 || std::size_t(h.face) >= poly.planes.size()) {
            const Vec3d p = ray.origin + c.t * ray.direction;
            double dmin = inf;
            for (std::size_t k = 0; k < poly.planes.size(); ++k) {
                const Plane<double>& q = poly.planes[k];
                const double d = std::abs(q.normal.dot(p) - q.offset) / q.normal.norm();
                if (d < dmin) dmin = d, h.face = int(k);
            }
        }
        const Plane<double>& pl = poly.planes[std::size_t(h.face)];
        h.verdict = Verdict::hit;
        const rayproof::SurfacePoint<double> k = surface_point(r, pl, h);
        SurfacePoint sp;
        sp.p = k.p;
        sp.n = ::rayproof::detail::unit_vector<double>(pl.normal);
        const Vec3d& n = pl.normal;
        const double terms =
            std::abs(n[0] * sp.p[0]) + std::abs(n[1] * sp.p[1]) + std::abs(n[2] * sp.p[2]) + std::abs(pl.offset);
        const double margin = std::is_same_v<M, conservative_t> ? ::rayproof::detail::poly_leaving_margin : gamma_bound(12);
        sp.offset = spawn_offset(k) + margin * terms / n.norm();
        return sp;
    }

    // The plane's margin K (tracer.hpp) is gamma(12)·S/|n|, S = |offset| + Σ|n_i p_i|,
    // and gamma(13)·S/|n| in conservative mode: the kernel widens t~ = fl(N~·fl(1/D~))
    // to fl(t~ ± E), E = 2·B0 + 2^-1022 with B0 = e_N·|inv| + |t~|·(e_D·|inv| + 3u)
    // and |t - t~| <= (1 + 2^-18)·B0 (ray_plane.hpp, plane_conservative_common), so the
    // upper end is at most t + 3.01·B0 + 3·2^-1022. For a ray leaving the plane at
    // distance δ, t = -δ|n|/|D|, |t~| <= (1 + 3u)|t|, e_D·|inv| <= 2^-20 and e_N <=
    // 4u(1 + 10u)·S + 2^-1021: the end is negative when δ|n|(1 - 3.01·2^-20 - 14u) >
    // 12.05u·S + 2^-1019·(1 + |D|), which δ >= gamma(13)·S/|n| gives with 0.9u·S/|n| to
    // spare, for S at the new origin (above S at p by O(u²·S)) and the absolute terms
    // (for S >= 2^-960·(1 + |D|)).
    SurfacePoint at(const Plane<double>& pl, const Rayd& ray, const Candidate& c) {
        Hitd h = c.hit;
        h.t_enter = c.t;
        const rayproof::SurfacePoint<double> k = surface_point(ray, pl, h);
        SurfacePoint sp;
        sp.p = k.p;
        sp.n = k.n;
        const Vec3d& n = pl.normal;
        const double terms =
            std::abs(n[0] * sp.p[0]) + std::abs(n[1] * sp.p[1]) + std::abs(n[2] * sp.p[2]) + std::abs(pl.offset);
        sp.offset = spawn_offset(k) + gamma_bound(std::is_same_v<M, conservative_t> ? 13 : 12) * terms / n.norm();
        return sp;
    }

    // --- secondary rays ------------------------------------------------------------------

    // A ray leaving sp in direction dir on the side `side` (+1: the side the incoming ray
    // came from, -1: the other side).
    Rayd spawn(const SurfacePoint& sp, const Vec3d& dir, int side) const {
        if (opt_.offset == OffsetPolicy::naive) return Rayd{sp.p, dir, opt_.naive_t_min, inf};
        const double dist = std::max(sp.offset, underflow_floor(sp.p, dir));
        return Rayd{offset_origin(sp.p, side > 0 ? sp.n : Vec3d(-sp.n), dist), dir, 0, inf};
    }

    Rayd transmit(const Object& obj, const Material& mat, const SurfacePoint& sp, const Vec3d& u) const {
        if (is_plane(obj.shape)) return spawn(sp, u, -1);  // a thin sheet: straight through
        const double eta = sp.inside ? mat.ior : 1 / mat.ior;
        if (const auto t = refract(u, sp.n, eta)) return spawn(sp, t->normalized(), -1);
        return spawn(sp, reflect(u, sp.n), +1);  // total internal reflection
    }

    Color light(const Light& l, const Material& mat, const SurfacePoint& sp, const Vec3d& u) {
        const Vec3d to_light = l.position - sp.p;
        const double dist = to_light.norm();
        if (!(dist > 0)) return Color::Zero();
        const Vec3d L = to_light / dist;
        const double nl = sp.n.dot(L);
        const double att = std::min(1.0, 1.0 / (l.c1 + l.c2 * dist + l.c3 * dist * dist));
        if (!(nl > 0)) {  // the light is behind the surface: only a translucent one lets it through
            if (!(nl < 0) || !(mat.translucency > 0)) return Color::Zero();
            const Color back = att * l.color * mat.diffuse * (mat.translucency * -nl);
            if (!(back > 0).any()) return Color::Zero();
            return back * shadow(sp, l, -1);
        }
        Color term = mat.diffuse * nl;
        if ((mat.specular > 0).any()) {
            const Vec3d V = -u;
            double x;
            if (mat.highlight == Highlight::phong) {
                const Vec3d R = 2 * nl * sp.n - L;
                x = R.dot(V);
            } else {
                x = sp.n.dot((L + V).normalized());
            }
            if (x > 0) term += mat.specular * std::pow(x, mat.shininess);
        }
        const Color contribution = att * l.color * term;
        if (!(contribution > 0).any()) return Color::Zero();
        return contribution * shadow(sp, l, +1);
    }

    // The fraction of the light that reaches sp along the segment that leaves sp on the
    // side `side` (+1: the side the incoming ray came from): 0 behind an opaque object,
    // else K_t for each surface of a transparent object the segment crosses.
    Color shadow(const SurfacePoint& sp, const Light& l, int side) {
        ++st_.shadow;
        Rayd r;
        if (opt_.offset == OffsetPolicy::naive) {
            const Vec3d d = l.position - sp.p;
            const double dist = d.norm();
            r = Rayd{sp.p, d / dist, opt_.naive_t_min, dist};
        } else {
            // The segment from the offset origin to the light: t in [0, 1].
            const Vec3d o = offset_origin(sp.p, side > 0 ? sp.n : Vec3d(-sp.n),
                                          std::max(sp.offset, underflow_floor(sp.p, l.position - sp.p)));
            r = Rayd{o, l.position - o, 0, 1};
        }
        if (index_) return shadow_bvh(r);
        double pass = 1;
        for (const Object& obj : s_.objects) {
            const int n = crossings(r, obj);
            if (n == 0) continue;
            const double kt = s_.materials[std::size_t(obj.material)].transparency;
            pass *= n == 1 ? kt : kt * kt;
            if (pass <= 0) {
                ++st_.shadowed;
                return Color::Zero();
            }
        }
        return Color::Constant(pass);
    }

    // The same fraction from the objects the BVH offers (the lights' spheres cast no
    // shadow). Certified: every object the segment meets exactly is offered (its range is
    // never lowered), and crossings() asks each with the same query as the loop above.
    // The product of the transparencies does not commute in floating point, so the
    // crossings are collected and multiplied in object order, as the loop does: the same
    // factors in the same order, the same bits. An opaque object met (K_t = 0) makes it 0
    // whatever the order, and stops the search at once, as 0 is also where the loop ends
    // (a product of factors in [0, 1] is 0 exactly when some prefix of it is).
    Color shadow_bvh(const Rayd& r) {
        double limit = r.t_max;
        const PreparedRay<double> prepared(r);
        crossed_.clear();
        bool blocked = false;
        index_->bvh.for_each_candidate(prepared, M{}, limit, [&](std::size_t i) {
            if (i >= index_->objects) return true;
            const Object& obj = s_.objects[i];
            const int n = crossings(r, obj);
            if (n == 0) return true;
            if (!(s_.materials[std::size_t(obj.material)].transparency > 0)) {
                blocked = true;
                return false;
            }
            crossed_.push_back({i, n});
            return true;
        });
        if (blocked) {
            ++st_.shadowed;
            return Color::Zero();
        }
        std::sort(crossed_.begin(), crossed_.end());
        double pass = 1;
        for (const auto& [i, n] : crossed_) {
            const double kt = s_.materials[std::size_t(s_.objects[i].material)].transparency;
            pass *= n == 1 ? kt : kt * kt;
            if (pass <= 0) {
                ++st_.shadowed;
                return Color::Zero();
            }
        }
        return Color::Constant(pass);
    }

    struct Bulb {
        int light;  // index into Scene::lights
        Sphere<double> sphere;
    };

    const Scene& s_;
    const TraceOptions& opt_;
    Stats& st_;
    const SceneBvh* index_;                              // null: every object is asked
    std::vector<Bulb> bulbs_;                            // the visible lights
    std::vector<std::pair<std::size_t, int>> crossed_;  // shadow_bvh's (object, crossings)
};

template <class M> Color pixel(Tracer<M>& tr, const Scene& s, int x, int y, Stats& st) {
    const int n = s.settings.supersample;
    Color sum = Color::Zero();
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double px = x + (i + 0.5) / n, py = y + (j + 0.5) / n;
            ++st.primary;
            sum += tr.trace(camera_ray(s.camera, s.settings.width, s.settings.height, px, py), 1, 1.0);
        }
    return sum / double(n * n);
}

// Each of opt.threads threads (every hardware thread by default, never more than rows)
// renders the next row not yet taken until none is left. A pixel depends on the scene
// alone, so the image is the same for any number of threads; each thread counts into its
// own Stats, summed once all have finished.
template <class M> RenderResult render_in(const Scene& s, const RenderOptions& opt) {
    using clock = std::chrono::steady_clock;
    RenderResult res;
    const int w = s.settings.width, h = s.settings.height;
    res.image = Image(w, h);
    const int all = int(std::max(1u, std::thread::hardware_concurrency()));
    res.threads = std::max(0, std::min(opt.threads > 0 ? opt.threads : all, h));
    std::vector<Stats> stats(std::size_t(res.threads));
    std::atomic<int> next_row{0};
    // A bar on stderr once the render has lasted a second (progress.hpp): the caller's, or
    // one of its own when asked for.
    std::optional<Progress> own;
    Progress* progress = opt.reporter;
    if (!progress && opt.progress && h > 0) progress = &own.emplace(true);
    const auto t0 = clock::now();
    std::optional<SceneBvh> index;
    if (opt.trace.bvh) {
        if (progress) progress->phase("building the BVH of " + std::to_string(s.objects.size()) + " objects");
        index.emplace(build_bvh(s));
    }
    if (progress) progress->phase("rendering", std::uint64_t(std::max(h, 0)));
    std::vector<std::thread> pool;
    for (std::size_t k = 0; k < stats.size(); ++k)
        pool.emplace_back([&, k] {
            Stats st;
            Tracer<M> tr(s, opt.trace, st, index ? &*index : nullptr);
            for (int y; (y = next_row++) < h;) {
                for (int x = 0; x < w; ++x) {
                    const Color c = pixel(tr, s, x, y, st);
                    std::uint8_t* px = res.image.at(x, y);
                    for (int ch = 0; ch < 3; ++ch) px[ch] = to_byte(c[ch]);
                }
                if (progress) progress->add(1);
            }
            stats[k] = st;
        });
    for (std::thread& t : pool) t.join();
    if (progress) progress->finish();
    res.seconds = std::chrono::duration<double>(clock::now() - t0).count();
    for (const Stats& st : stats) res.stats += st;
    return res;
}

}  // namespace

Stats& Stats::operator+=(const Stats& o) {
    primary += o.primary;
    shadow += o.shadow;
    reflection += o.reflection;
    refraction += o.refraction;
    kernel_queries += o.kernel_queries;
    invalid += o.invalid;
    culled += o.culled;
    shadowed += o.shadowed;
    return *this;
}

Ray<double> camera_ray(const Camera& cam, int width, int height, double px, double py) {
    const Vec3d f = (cam.look_at - cam.position).normalized();
    const Vec3d r = f.cross(cam.up).normalized();
    const Vec3d u = r.cross(f);
    const double tan_half = std::tan(cam.fov * (3.14159265358979323846 / 360));
    const double sx = (2 * px / width - 1) * tan_half * (double(width) / height);
    const double sy = (1 - 2 * py / height) * tan_half;
    return Ray<double>{cam.position, f + sx * r + sy * u, 0, inf};
}

double underflow_floor(const Vec3d& p, const Vec3d& d) {
    return 0x1p-60 * std::max(p.cwiseAbs().maxCoeff(), d.cwiseAbs().maxCoeff());
}

Vec3d reflect(const Vec3d& u, const Vec3d& n) { return u - 2 * u.dot(n) * n; }

std::optional<Vec3d> refract(const Vec3d& u, const Vec3d& n, double eta) {
    const double cos_i = -u.dot(n);
    const double k = 1 - eta * eta * (1 - cos_i * cos_i);
    if (k < 0) return std::nullopt;
    return Vec3d(eta * u + (eta * cos_i - std::sqrt(k)) * n);
}

// The scene's mode as its tag, by the kernel's dispatch (a value outside the three
// renders as fast).
template <class F> decltype(auto) in_mode(Mode m, F&& f) {
    return with_mode(m, f, [&] { return f(fast); });
}

RenderResult render(const Scene& scene, const RenderOptions& options) {
    return in_mode(scene.settings.mode, [&](auto tag) { return render_in<decltype(tag)>(scene, options); });
}

Color radiance(const Scene& scene, double px, double py, const TraceOptions& options, Stats* stats) {
    return in_mode(scene.settings.mode, [&](auto tag) -> Color {
        Stats local;
        Stats& st = stats ? *stats : local;
        std::optional<SceneBvh> index;
        if (options.bvh) index.emplace(build_bvh(scene));
        Tracer<decltype(tag)> tr(scene, options, st, index ? &*index : nullptr);
        ++st.primary;
        return tr.trace(camera_ray(scene.camera, scene.settings.width, scene.settings.height, px, py), 1, 1.0);
    });
}

}  // namespace rayproof::render
