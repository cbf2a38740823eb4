#pragma once
// Embree 3 single-level instancing of a scene description, for speed
// comparisons: one RTCScene per mesh geometry, one RTC_GEOMETRY_TYPE_INSTANCE
// per instance (the 3x4 transform as RTC_FORMAT_FLOAT3X4_ROW_MAJOR) in the top
// scene. Sphere sets are RTC_GEOMETRY_TYPE_SPHERE_POINT (Embree's analytic
// sphere), box sets RTC_GEOMETRY_TYPE_QUAD (six quads per box, prim = quad / 6).
// Embree has no plane primitive: planes go through the same per-ray loop as
// ours (nearest_plane, shapes.h) after Embree's answer, with the same tie rule
// (an instance's hit wins a tie with a plane; planes follow instances). u, v
// are Embree's (its sphere and quad parameterisations, not scene_hit.h's).
#include <memory>
#include <span>

#include "simdbvh/scene/scene.h"

namespace simdbvh::reference {

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
    // rtcOccluded1 per ray after the planes: an occluded ray gets a SceneHit with t = 0 and prim = 0 (Embree does
    // not say which primitive), a plane's hit gets that plane's ids; else SceneHit{}.
    void occluded(std::span<const Ray> rays, std::span<SceneHit> hits) const;
    // Device memory after the build (Embree's memory monitor): its geometry buffers and its BVHs.
    std::size_t bytes() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace simdbvh::reference
