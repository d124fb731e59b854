// bench/embree_sphere.cpp — Embree 3 one-sphere scenes (see embree_sphere.hpp).
#include "embree_sphere.hpp"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace rayproof::bench {

struct EmbreeSpheres::Impl {
    RTCDevice device = nullptr;
    std::vector<RTCScene> scenes;
};

namespace {
// The device is shared by every set of scenes (one worker thread: the builds are trivial).
RTCDevice shared_device() {
    static RTCDevice device = [] {
        RTCDevice d = rtcNewDevice("threads=1");
        if (!d) throw std::runtime_error("embree: rtcNewDevice failed");
        return d;
    }();
    return device;
}

// The first crossing along o + t·d for t in [tnear, tfar] (tnear >= 0); NaN if none.
float first_crossing(RTCScene scene, const Ray<float>& r, float sign, float tnear, float tfar) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = r.origin[0];
    rh.ray.org_y = r.origin[1];
    rh.ray.org_z = r.origin[2];
    rh.ray.dir_x = sign * r.direction[0];
    rh.ray.dir_y = sign * r.direction[1];
    rh.ray.dir_z = sign * r.direction[2];
    rh.ray.tnear = tnear;
    rh.ray.tfar = tfar;
    rh.ray.time = 0;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &rh);
    return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? std::numeric_limits<float>::quiet_NaN() : rh.ray.tfar;
}
}  // namespace

EmbreeSpheres::EmbreeSpheres(std::span<const Sphere<float>> spheres, bool robust) : impl_(std::make_unique<Impl>()) {
    impl_->device = shared_device();
    impl_->scenes.reserve(spheres.size());
    for (const Sphere<float>& s : spheres) {
        RTCScene scene = rtcNewScene(impl_->device);
        if (robust) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
        RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* v = static_cast<float*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
        v[0] = s.center[0];
        v[1] = s.center[1];
        v[2] = s.center[2];
        v[3] = s.radius;
        rtcCommitGeometry(geom);
        rtcAttachGeometry(scene, geom);
        rtcReleaseGeometry(geom);
        rtcCommitScene(scene);
        impl_->scenes.push_back(scene);
    }
}

EmbreeSpheres::~EmbreeSpheres() {
    for (RTCScene s : impl_->scenes) rtcReleaseScene(s);
}

std::size_t EmbreeSpheres::size() const { return impl_->scenes.size(); }

// Embree's precondition on a ray (RayK::valid, asserted by Debian's build): every origin
// and direction component at most FLT_LARGE = 1.844e18 in magnitude.
bool EmbreeSpheres::accepts(const Ray<float>& r) {
    constexpr float large = 1.844E18f;
    for (int i = 0; i < 3; ++i)
        if (!(std::abs(r.origin[i]) <= large && std::abs(r.direction[i]) <= large)) return false;
    return true;
}

Hit<float> EmbreeSpheres::intersect(std::size_t i, const Ray<float>& r) const {
    if (!accepts(r)) {
        Hit<float> refused;
        refused.verdict = Verdict::invalid;
        return refused;
    }
    RTCScene scene = impl_->scenes[i];
    float t;
    if (r.t_min >= 0) {
        t = first_crossing(scene, r, 1.0f, r.t_min, r.t_max);
    } else if (r.t_max >= 0) {
        t = first_crossing(scene, r, 1.0f, 0.0f, r.t_max);
        if (std::isnan(t)) t = -first_crossing(scene, r, -1.0f, 0.0f, -r.t_min);
    } else {
        t = -first_crossing(scene, r, -1.0f, -r.t_max, -r.t_min);
    }
    Hit<float> h;
    if (!std::isnan(t)) {
        h.verdict = Verdict::hit;
        h.t_enter = h.t_exit = t;
    }
    return h;
}

}  // namespace rayproof::bench
