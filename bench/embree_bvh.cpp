// bench/embree_bvh.cpp — Embree 3 closest-hit scenes of balls (see embree_bvh.hpp).
#include "embree_bvh.hpp"

#include <embree3/rtcore.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <sys/types.h>

namespace rayproof::bench {

struct EmbreeBallScene::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::atomic<long long> bytes{0};
    double build_seconds = 0;
};

namespace {
bool count_bytes(void* user, ssize_t bytes, bool /*post*/) {
    static_cast<std::atomic<long long>*>(user)->fetch_add(static_cast<long long>(bytes));
    return true;
}
}  // namespace

EmbreeBallScene::EmbreeBallScene(std::span<const Sphere<float>> balls, bool robust) : impl_(std::make_unique<Impl>()) {
    impl_->device = rtcNewDevice("threads=1");
    if (!impl_->device) throw std::runtime_error("embree: rtcNewDevice failed");
    rtcSetDeviceMemoryMonitorFunction(impl_->device, count_bytes, &impl_->bytes);
    impl_->scene = rtcNewScene(impl_->device);
    if (robust) rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                          4 * sizeof(float), balls.size()));
    for (std::size_t i = 0; i < balls.size(); ++i) {
        v[4 * i + 0] = balls[i].center[0];
        v[4 * i + 1] = balls[i].center[1];
        v[4 * i + 2] = balls[i].center[2];
        v[4 * i + 3] = balls[i].radius;
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(impl_->scene, geom);
    rtcReleaseGeometry(geom);
    const auto t0 = std::chrono::steady_clock::now();
    rtcCommitScene(impl_->scene);
    impl_->build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE) throw std::runtime_error("embree: the scene did not build");
}

EmbreeBallScene::~EmbreeBallScene() {
    rtcReleaseScene(impl_->scene);
    rtcReleaseDevice(impl_->device);
}

double EmbreeBallScene::build_seconds() const { return impl_->build_seconds; }
std::size_t EmbreeBallScene::bytes() const { return static_cast<std::size_t>(impl_->bytes.load()); }

EmbreeBallScene::Answer EmbreeBallScene::closest(const Ray<float>& r) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = r.origin[0];
    rh.ray.org_y = r.origin[1];
    rh.ray.org_z = r.origin[2];
    rh.ray.dir_x = r.direction[0];
    rh.ray.dir_y = r.direction[1];
    rh.ray.dir_z = r.direction[2];
    rh.ray.tnear = r.t_min;
    rh.ray.tfar = r.t_max;
    rh.ray.time = 0;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &context, &rh);
    Answer a;
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
        a.hit = true;
        a.index = static_cast<std::int64_t>(rh.hit.primID);
        a.t = rh.ray.tfar;
    }
    return a;
}

}  // namespace rayproof::bench
