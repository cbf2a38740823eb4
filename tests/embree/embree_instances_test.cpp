// Embree's single-level instancing of a scene description against ours: the
// same instance and primitive on nearly every ray (Embree's float transforms
// and test differ from ours in the last bits, so a few grazing rays may not).
#include <gtest/gtest.h>

#include <cmath>

#include "simdbvh/compare/embree_instances.h"
#include "simdbvh/scene/rays.h"
#include "simdbvh/scene/scene_desc.h"
#include "simdbvh/scene/scenes.h"

namespace simdbvh {
namespace {

TEST(EmbreeInstances, AgreeWithTheSceneOnNearlyEveryRay) {
    const SceneDesc d = scene::instances_scene(scene::icosphere(3), 12);
    const SceneBvhN<8> ours = SceneBvhN<8>::build(d);
    const compare::EmbreeInstanceScene embree(d);
    Mesh proxy;
    const Aabb b = world_bounds(d);
    proxy.positions = {b.lo, b.hi};
    proxy.triangles = {{0, 1, 1}};
    const auto rays = scene::generate_rays(proxy, scene::RayKind::primary, 20000, 1);
    std::vector<SceneHit> a(rays.size()), e(rays.size());
    intersect(ours, std::span<const Ray>(rays), std::span<SceneHit>(a), Isa::scalar);
    embree.intersect(rays, e);
    std::size_t hits = 0, same = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits += a[i].hit();
        if (a[i].hit() != e[i].hit()) continue;
        if (!a[i].hit()) { ++same; continue; }
        if (a[i].inst == e[i].inst && a[i].prim == e[i].prim && a[i].geom == e[i].geom) {
            ++same;
            EXPECT_NEAR(a[i].t, e[i].t, 1e-4f * a[i].t) << "ray " << i;
        }
    }
    EXPECT_GT(hits, rays.size() / 40);
    EXPECT_GE(double(same), 0.995 * double(rays.size()));
}

TEST(EmbreeInstances, RejectsAnalyticGeometry) {
    SceneDesc d;
    d.geometries.push_back(SphereSet{{Sphere{{0, 0, 0}, 1}}});
    d.instances.push_back({0, Affine3{}});
    EXPECT_THROW(compare::EmbreeInstanceScene{d}, Error);
}

}  // namespace
}  // namespace simdbvh
