// Embree single-level instancing of a scene description (embree_instances.h).
#include "simdbvh/compare/embree_instances.h"
#include "embree_ray.h"

#include <embree3/rtcore.h>

#include <chrono>
#include <string>
#include <vector>

#include "simdbvh/compare/embree.h"
#include "simdbvh/kernels/error.h"

namespace simdbvh::compare {

struct EmbreeInstanceScene::Impl {
    RTCDevice device = nullptr;
    RTCScene top = nullptr;
    std::vector<RTCScene> children;
    std::vector<std::uint32_t> geometry_of;  // per instance
    double build_ms = 0;
    void check(const char* what) const {
        const RTCError e = rtcGetDeviceError(device);
        if (e != RTC_ERROR_NONE) throw Error(std::string("Embree: ") + what + " failed (error " + std::to_string(int(e)) + ")");
    }
    ~Impl() {
        if (top) rtcReleaseScene(top);
        for (RTCScene s : children)
            if (s) rtcReleaseScene(s);
        if (device) rtcReleaseDevice(device);
    }
};

EmbreeInstanceScene::EmbreeInstanceScene(const SceneDesc& scene) : impl_(std::make_unique<Impl>()) {
    validate(scene);
    if (!scene.planes.empty()) throw Error("Embree instancing comparison: meshes only (no planes)");
    Impl& s = *impl_;
    s.device = rtcNewDevice("");
    if (!s.device) throw Error("Embree: rtcNewDevice failed");
    const auto t0 = std::chrono::steady_clock::now();
    for (const Geometry& g : scene.geometries) {
        const Mesh* m = std::get_if<Mesh>(&g);
        if (!m) throw Error("Embree instancing comparison: meshes only (no sphere or box sets)");
        RTCScene child = rtcNewScene(s.device);
        s.children.push_back(child);
        RTCGeometry geom = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), m->positions.size()));
        auto* idx = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), m->triangles.size()));
        s.check("rtcSetNewGeometryBuffer");
        for (std::size_t i = 0; i < m->positions.size(); ++i)
            for (int k = 0; k < 3; ++k) v[3 * i + k] = m->positions[i][k];
        for (std::size_t i = 0; i < m->triangles.size(); ++i)
            for (int k = 0; k < 3; ++k) idx[3 * i + k] = m->triangles[i][k];
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(child, geom, 0);
        rtcReleaseGeometry(geom);
        rtcCommitScene(child);
        s.check("rtcCommitScene (mesh)");
    }
    s.top = rtcNewScene(s.device);
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& in = scene.instances[i];
        RTCGeometry inst = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(inst, s.children[in.geometry]);
        float m[12];
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) m[4 * r + c] = in.transform.m[r][c];
        rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, m);
        rtcCommitGeometry(inst);
        rtcAttachGeometryByID(s.top, inst, unsigned(i));
        rtcReleaseGeometry(inst);
        s.geometry_of.push_back(in.geometry);
    }
    rtcCommitScene(s.top);
    s.check("rtcCommitScene (instances)");
    s.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

EmbreeInstanceScene::~EmbreeInstanceScene() = default;

double EmbreeInstanceScene::build_ms() const { return impl_->build_ms; }

void EmbreeInstanceScene::intersect(std::span<const Ray> rays, std::span<SceneHit> hits) const {
    if (hits.size() < rays.size()) throw Error("hits span is smaller than rays span");
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Ray& r = rays[i];
        hits[i] = SceneHit{};
        if (check_embree_ray(r) != EmbreeRayCheck::ok) continue;
        alignas(16) RTCRayHit rh = embree_ray_hit(r);
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        rtcIntersect1(impl_->top, &ctx, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        const std::uint32_t inst = rh.hit.instID[0];
        hits[i] = SceneHit{rh.ray.tfar, rh.hit.u, rh.hit.v, rh.hit.primID, impl_->geometry_of[inst], inst};
    }
}

}  // namespace simdbvh::compare
