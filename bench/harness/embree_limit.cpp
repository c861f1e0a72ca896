#include "harness/embree_limit.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cstring>
#include <string>

#include "accel/embree_rays.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/core/hit_batch.hpp"

namespace beamtrace {

std::string_view to_string(EmbreeCall call) {
    switch (call) {
        case EmbreeCall::single:
            return "rtcIntersect1";
        case EmbreeCall::packet16:
            return "rtcIntersect16";
        case EmbreeCall::packet16_coherent:
            return "rtcIntersect16 coherent";
    }
    return "?";
}

struct EmbreeLimit::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
};

EmbreeLimit::EmbreeLimit(const TriangleMesh& mesh, unsigned threads)
    : impl_(std::make_unique<Impl>()) {
    const std::string config = "threads=" + std::to_string(threads) + ",set_affinity=0";
    impl_->device = rtcNewDevice(config.c_str());
    if (impl_->device == nullptr) {
        throw ConfigError("Embree: rtcNewDevice failed");
    }
    impl_->scene = rtcNewScene(impl_->device);
    rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
    if (!mesh.faces.empty()) {
        RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(Vec3f), mesh.vertices.size()));
        if (v != nullptr) {
            std::memcpy(v, mesh.vertices.data(), mesh.vertices.size() * sizeof(Vec3f));
        }
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.faces.data(),
                                   0, sizeof(Face), mesh.faces.size());
        rtcCommitGeometry(g);
        rtcAttachGeometry(impl_->scene, g);
        rtcReleaseGeometry(g);
    }
    rtcCommitScene(impl_->scene);
    if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE) {
        rtcReleaseScene(impl_->scene);
        rtcReleaseDevice(impl_->device);
        throw ConfigError("Embree: building the limit scene failed");
    }
}

EmbreeLimit::~EmbreeLimit() {
    rtcReleaseScene(impl_->scene);
    rtcReleaseDevice(impl_->device);
}

void EmbreeLimit::trace(const RayBatch& rays, EmbreeCall call, std::vector<std::uint32_t>& face,
                        ThreadPool& pool) const {
    face.resize(rays.size());
    RTCScene scene = impl_->scene;
    pool.parallel_for(rays.size(), 1024, [&](std::size_t b, std::size_t e) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        if (call == EmbreeCall::single) {
            for (std::size_t i = b; i < e; ++i) {
                RTCRayHit rh;
                detail::set_embree_ray(rh.ray, rays, i);
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(scene, &ctx, &rh);
                face[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? kNoFace : rh.hit.primID;
            }
            return;
        }
        ctx.flags = call == EmbreeCall::packet16_coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT
                                                          : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
        alignas(64) RTCRayHit16 rh;
        detail::init_embree_packet(rh);
        alignas(64) int valid[16];
        for (std::size_t p = b; p < e; p += 16) {
            const std::size_t n = std::min<std::size_t>(16, e - p);
            detail::set_embree_packet(rh, valid, rays, p, n);
            rtcIntersect16(valid, scene, &ctx, &rh);
            for (std::size_t k = 0; k < n; ++k) {
                face[p + k] =
                    rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID ? kNoFace : rh.hit.primID[k];
            }
        }
    });
}

}  // namespace beamtrace
