#pragma once
// Embree 3 single-level instancing of a scene description, for speed
// comparisons: one RTCScene per mesh geometry, one RTC_GEOMETRY_TYPE_INSTANCE
// per instance (the 3x4 transform as RTC_FORMAT_FLOAT3X4_ROW_MAJOR) in the top
// scene. Meshes only (sphere and box sets and planes throw simdbvh::Error).
#include <memory>
#include <span>

#include "simdbvh/scene_accel/scene.h"

namespace simdbvh::compare {

class EmbreeInstanceScene {
public:
    explicit EmbreeInstanceScene(const SceneDesc& scene);  // RTC_BUILD_QUALITY_MEDIUM, default device
    ~EmbreeInstanceScene();
    EmbreeInstanceScene(const EmbreeInstanceScene&) = delete;
    EmbreeInstanceScene& operator=(const EmbreeInstanceScene&) = delete;

    double build_ms() const;
    // rtcIntersect1 per ray: t, u, v, prim, geom (the instance's geometry), inst.
    // Rays Embree must not see (check_embree_ray) miss.
    void intersect(std::span<const Ray> rays, std::span<SceneHit> hits) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace simdbvh::compare
