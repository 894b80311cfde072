#include <embree3/rtcore.h>
#include <superloc/sim/raycaster.h>

#include <cstring>
#include <stdexcept>
#include <string>

namespace superloc::sim {

struct RayCaster::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    Mesh mesh;  // kept for the normals of hit triangles
};

RayCaster::RayCaster(const Mesh& mesh) : impl_(std::make_unique<Impl>()) {
    if (mesh.triangles.empty()) throw std::runtime_error("RayCaster: the world mesh is empty");
    impl_->mesh = mesh;
    // One thread: generation is measured on one core, and results must not depend on scheduling.
    impl_->device = rtcNewDevice("threads=1");
    if (!impl_->device)
        throw std::runtime_error("RayCaster: rtcNewDevice failed (error " +
                                 std::to_string(rtcGetDeviceError(nullptr)) + ")");
    impl_->scene = rtcNewScene(impl_->device);
    rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                          mesh.vertices.size()));
    for (size_t i = 0; i < mesh.vertices.size(); ++i)
        std::memcpy(v + 3 * i, mesh.vertices[i].data(), 3 * sizeof(float));
    auto* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), mesh.triangles.size()));
    for (size_t i = 0; i < mesh.triangles.size(); ++i)
        for (int k = 0; k < 3; ++k) idx[3 * i + k] = static_cast<unsigned>(mesh.triangles[i][k]);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(impl_->scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(impl_->scene);
    if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE)
        throw std::runtime_error("RayCaster: Embree failed to build the scene");
}

RayCaster::~RayCaster() {
    if (impl_->scene) rtcReleaseScene(impl_->scene);
    if (impl_->device) rtcReleaseDevice(impl_->device);
}

RayHit RayCaster::cast(const Vec3d& o, const Vec3d& d, double t_min, double t_max) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = static_cast<float>(o.x());
    rh.ray.org_y = static_cast<float>(o.y());
    rh.ray.org_z = static_cast<float>(o.z());
    rh.ray.dir_x = static_cast<float>(d.x());
    rh.ray.dir_y = static_cast<float>(d.y());
    rh.ray.dir_z = static_cast<float>(d.z());
    rh.ray.tnear = static_cast<float>(t_min);
    rh.ray.tfar = static_cast<float>(t_max);
    rh.ray.time = 0;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &ctx, &rh);
    RayHit out;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return out;
    out.hit = true;
    out.range = rh.ray.tfar;
    out.triangle = rh.hit.primID;
    out.normal = impl_->mesh.normal(rh.hit.primID);
    return out;
}

void RayCaster::castFan(const Vec3d& o, const std::vector<Vec3d>& dirs, double t_min, double t_max,
                        std::vector<RayHit>& out) const {
    out.assign(dirs.size(), RayHit{});
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    for (size_t first = 0; first < dirs.size(); first += 16) {
        alignas(64) RTCRayHit16 rh;
        alignas(64) int valid[16];
        for (int k = 0; k < 16; ++k) {
            const size_t i = first + k;
            valid[k] = i < dirs.size() ? -1 : 0;
            const Vec3d& d = i < dirs.size() ? dirs[i] : dirs[first];
            rh.ray.org_x[k] = static_cast<float>(o.x());
            rh.ray.org_y[k] = static_cast<float>(o.y());
            rh.ray.org_z[k] = static_cast<float>(o.z());
            rh.ray.dir_x[k] = static_cast<float>(d.x());
            rh.ray.dir_y[k] = static_cast<float>(d.y());
            rh.ray.dir_z[k] = static_cast<float>(d.z());
            rh.ray.tnear[k] = static_cast<float>(t_min);
            rh.ray.tfar[k] = static_cast<float>(t_max);
            rh.ray.time[k] = 0;
            rh.ray.mask[k] = 0xFFFFFFFFu;
            rh.ray.id[k] = static_cast<unsigned>(k);
            rh.ray.flags[k] = 0;
            rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect16(valid, impl_->scene, &ctx, &rh);
        for (int k = 0; k < 16 && first + k < dirs.size(); ++k) {
            if (rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID) continue;
            RayHit& h = out[first + k];
            h.hit = true;
            h.range = rh.ray.tfar[k];
            h.triangle = rh.hit.primID[k];
            h.normal = impl_->mesh.normal(rh.hit.primID[k]);
        }
    }
}

}  // namespace superloc::sim
