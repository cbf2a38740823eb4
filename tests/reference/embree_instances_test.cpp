// Embree's single-level instancing of a scene description against ours: the
// same instance and primitive on nearly every ray (Embree's float transforms
// and test differ from ours in the last bits, so a few grazing rays may not).
// Meshes, analytic spheres, boxes and planes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "simdbvh/reference/embree_instances.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scene_desc.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh {
namespace {

TEST(EmbreeInstances, AgreeWithTheSceneOnNearlyEveryRay) {
    const SceneDesc d = workloads::instances_scene(workloads::icosphere(3), 12);
    const SceneBvhN<8> ours = SceneBvhN<8>::build(d);
    const reference::EmbreeInstanceScene embree(d);
    Mesh proxy;
    const Aabb b = world_bounds(d);
    proxy.positions = {b.lo, b.hi};
    proxy.triangles = {{0, 1, 1}};
    const auto rays = workloads::generate_rays(proxy, workloads::RayKind::primary, 20000, 1);
    std::vector<SceneHit> a(rays.size()), e(rays.size());
    intersect(ours, std::span<const Ray>(rays), std::span<SceneHit>(a), {.isa = Isa::scalar});
    embree.intersect(rays, e);
    std::size_t hits = 0, same = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits += a[i].hit();
        if (a[i].hit() != e[i].hit()) continue;
        if (!a[i].hit()) {
            ++same;
            continue;
        }
        if (a[i].inst == e[i].inst && a[i].prim == e[i].prim && a[i].geom == e[i].geom) {
            ++same;
            EXPECT_NEAR(a[i].t, e[i].t, 1e-4f * a[i].t) << "ray " << i;
        }
    }
    EXPECT_GT(hits, rays.size() / 40);
    EXPECT_GE(double(same), 0.995 * double(rays.size()));
}

// Spheres (Embree's SPHERE_POINT), boxes (six quads each) and planes (our per-ray loop after Embree's answer)
// under rotated, scaled instances: the same object on nearly every ray, closest and any hit.
TEST(EmbreeInstances, AnalyticGeometryAndPlanesAgree) {
    SceneDesc d;
    d.geometries.push_back(workloads::icosphere(2));
    SphereSet spheres;
    BoxSet boxes;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-4.0f, 4.0f);
    for (int i = 0; i < 30; ++i) spheres.spheres.push_back({{u(rng), u(rng), u(rng)}, 0.2f + 0.1f * std::fabs(u(rng))});
    for (int i = 0; i < 30; ++i) {
        const Vec3 lo{u(rng), u(rng), u(rng)};
        boxes.boxes.push_back({lo, lo + Vec3{0.3f, 0.5f, 0.2f}});
    }
    d.geometries.push_back(spheres);
    d.geometries.push_back(boxes);
    for (std::uint32_t g = 0; g < 3; ++g)
        for (int k = 0; k < 3; ++k) {
            Affine3 a;  // a rotation about z by 0.3k rad, scale 1 + 0.25k, a shift along x
            const float c = std::cos(0.3f * float(k)), s = std::sin(0.3f * float(k)), sc = 1.0f + 0.25f * float(k);
            a.m[0][0] = c * sc;
            a.m[0][1] = -s * sc;
            a.m[1][0] = s * sc;
            a.m[1][1] = c * sc;
            a.m[2][2] = sc;
            a.m[0][3] = 3.0f * float(k) - 3.0f;
            d.instances.push_back({g, a});
        }
    d.planes.push_back({{0, -6, 0}, {0, 1, 0}});
    d.planes.push_back({{0, 0, -7}, {0, 0, 1}});
    const SceneBvhN<8> ours = SceneBvhN<8>::build(d);
    const reference::EmbreeInstanceScene embree(d);
    EXPECT_GT(embree.bytes(), 0u);
    Mesh proxy;
    const Aabb b = world_bounds(d);
    proxy.positions = {b.lo, b.hi};
    proxy.triangles = {{0, 1, 1}};
    const auto rays = workloads::generate_rays(proxy, workloads::RayKind::incoherent, 20000, 3);
    std::vector<SceneHit> a(rays.size()), e(rays.size()), ao(rays.size()), eo(rays.size());
    intersect(ours, std::span<const Ray>(rays), std::span<SceneHit>(a), {.isa = Isa::scalar});
    occluded(ours, std::span<const Ray>(rays), std::span<SceneHit>(ao), {.isa = Isa::scalar});
    embree.intersect(rays, e);
    embree.occluded(rays, eo);
    std::size_t same = 0, same_any = 0, kinds[4] = {0, 0, 0, 0};
    for (std::size_t i = 0; i < rays.size(); ++i) {
        same_any += ao[i].hit() == eo[i].hit();
        if (a[i].hit()) ++kinds[a[i].geom == kNoGeometry ? 3 : a[i].geom];
        if (a[i].hit() != e[i].hit()) continue;
        if (!a[i].hit()) {
            ++same;
            continue;
        }
        if (a[i].inst == e[i].inst && a[i].prim == e[i].prim && a[i].geom == e[i].geom) {
            ++same;
            EXPECT_NEAR(a[i].t, e[i].t, 1e-4f * a[i].t) << "ray " << i;
        }
    }
    for (int k = 0; k < 4; ++k) EXPECT_GT(kinds[k], rays.size() / 200) << "kind " << k;  // mesh, spheres, boxes, planes
    EXPECT_GE(double(same), 0.995 * double(rays.size()));
    EXPECT_GE(double(same_any), 0.995 * double(rays.size()));
}

}  // namespace
}  // namespace simdbvh
