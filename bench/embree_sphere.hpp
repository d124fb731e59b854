// bench/embree_sphere.hpp — Embree 3 as a sphere baseline: each case's sphere is its own
// one-sphere scene (RTC_GEOMETRY_TYPE_SPHERE_POINT, one float4 vertex x, y, z, r), and a
// query is rtcIntersect1 on it. Embree computes in float, so only Sphere<float> is
// answered. The header includes no Embree.
//
// Embree reports the first surface crossing in [tnear, tfar] and needs tnear >= 0:
//   t_min >= 0            one query on [t_min, t_max]; a hit answers t_enter = t_exit = tfar
//   t_min < 0 <= t_max    one query forwards on [0, t_max], one backwards (-d) on
//                         [0, -t_min]; hit if either hits (t_enter, t_exit: the crossing
//                         found, negated when found backwards)
//   t_max < 0             one query backwards on [-t_max, -t_min]
// A ray that starts and ends inside the ball crosses no surface: Embree answers miss
// where the ball semantics of the contract say hit. Only the verdict is comparable in
// general; t_enter is comparable when the ray starts outside the ball (t_min >= 0 and the
// exact entry after t_min).
//
// Embree requires every origin and direction component to be at most 1.844e18 in
// magnitude (FLT_LARGE; Debian's build asserts it and aborts): such rays are refused,
// answered Verdict::invalid, and counted apart from the wrong verdicts.
#pragma once

#include <rayproof/types.hpp>

#include <cstddef>
#include <memory>
#include <span>

namespace rayproof::bench {

class EmbreeSpheres {
public:
    // One scene per sphere; `robust` sets RTC_SCENE_FLAG_ROBUST.
    EmbreeSpheres(std::span<const Sphere<float>> spheres, bool robust);
    ~EmbreeSpheres();
    EmbreeSpheres(const EmbreeSpheres&) = delete;
    EmbreeSpheres& operator=(const EmbreeSpheres&) = delete;

    // The ray against sphere i (Verdict::invalid when Embree does not accept the ray).
    Hit<float> intersect(std::size_t i, const Ray<float>& ray) const;
    // Whether Embree accepts the ray (see above).
    static bool accepts(const Ray<float>& ray);
    std::size_t size() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace rayproof::bench
