// bench/embree_bvh.hpp — Embree 3 as the closest-hit baseline of the BVH benchmark: one
// scene holding every ball of a set as Embree's own sphere primitive
// (RTC_GEOMETRY_TYPE_SPHERE_POINT, one float4 vertex x, y, z, r per ball, one geometry),
// queried with rtcIntersect1. The header includes no Embree.
//
// Why the sphere primitive, not a user geometry: rtcIntersect1 on SPHERE_POINT answers the
// first surface crossing at t >= tnear, over all balls. For a ray whose origin lies
// outside every ball (the ray sets of bvh_scenes.hpp are built so: origins at distance
// >= 110 from the cube that holds the balls) with tnear = t_min = 0, the first crossing
// of a ball is its entry t_enter, and the first crossing over all balls is the smallest
// t_enter over the balls met: exactly the question rayproof's closest_hit answers for
// closed balls, and answered by Embree's own intersector. A user geometry would time an
// intersection routine of our writing inside Embree's dispatch, not a method of Embree's.
// Embree computes in float: the set is Sphere<float>.
//
// Each scene has its own device (one build thread, so that the build time compares with
// a single-threaded build), whose memory monitor counts the bytes Embree holds: the
// vertex buffer and the BVH.
#pragma once

#include <rayproof/types.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

namespace rayproof::bench {

class EmbreeBallScene {
public:
    // `robust` sets RTC_SCENE_FLAG_ROBUST; the build quality is RTC_BUILD_QUALITY_HIGH.
    EmbreeBallScene(std::span<const Sphere<float>> balls, bool robust);
    ~EmbreeBallScene();
    EmbreeBallScene(const EmbreeBallScene&) = delete;
    EmbreeBallScene& operator=(const EmbreeBallScene&) = delete;

    struct Answer {
        bool hit = false;
        std::int64_t index = -1;  // the ball hit (its index in the set)
        float t = 0;              // Embree's t of the crossing
    };
    // The first crossing on [ray.t_min, ray.t_max]; the caller keeps t_min >= 0 and every
    // origin and direction component within Embree's 1.844e18.
    Answer closest(const Ray<float>& ray) const;
    double build_seconds() const;  // rtcCommitScene, wall time
    std::size_t bytes() const;     // what the device holds after the build

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace rayproof::bench
