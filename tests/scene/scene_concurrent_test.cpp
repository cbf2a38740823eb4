// Many threads tracing one scene at once, each batch split over threads of
// its own (run under the tsan preset by scripts/tsan.sh): the brute force's
// hits on every thread. Each calling thread keeps its own pool of chunk
// arrays (traverse.cpp), which its batch's workers share.
#include <gtest/gtest.h>

#include <random>
#include <thread>

#include "simdbvh/workloads/scene_desc.h"
#include "simdbvh/workloads/scenes.h"
#include "simdbvh/scene/scene.h"

namespace simdbvh {
namespace {

// The built-ins' parts: 20 rotated icospheres (instances_scene), a set of 30
// spheres placed three times, and a floor plane.
SceneDesc mixed_scene() {
    SceneDesc s = workloads::instances_scene(workloads::icosphere(1), 20);
    s.geometries.push_back(workloads::spheres_scene(30).geometries[0]);
    for (float x : {-2.0f, 0.0f, 2.0f})
        s.instances.push_back({1, Affine3::translation({x, 0, 0}) * Affine3::scaling(2)});
    s.planes.push_back({{0, -6, 0}, {0, 1, 0}});
    return s;
}

TEST(Concurrent, ManyThreadsTraceOneScene) {
    const SceneDesc desc = mixed_scene();
    const SceneBvhN<8> scene = SceneBvhN<8>::build(desc);
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Ray> rays;
    for (int i = 0; i < 5000; ++i) {
        const Vec3 o{8 * u(rng), 8 * u(rng), 8 * u(rng)}, at{4 * u(rng), 4 * u(rng), 4 * u(rng)};
        rays.push_back(Ray{o, 0.0f, at - o, INFINITY});
    }
    std::vector<SceneHit> want(rays.size()), want_any(rays.size());
    brute_force_intersect(desc, rays, want);
    brute_force_occluded(desc, rays, want_any);
    std::size_t hits = 0, sphere_hits = 0;
    for (const SceneHit& h : want) {
        hits += h.hit();
        sphere_hits += h.hit() && h.geom == 1;
    }
    ASSERT_GT(hits, rays.size() / 4);
    ASSERT_GT(sphere_hits, 50u);  // the sphere set's bottom level is traced too
    constexpr int kThreads = 3;
    std::vector<std::vector<SceneHit>> got(kThreads, std::vector<SceneHit>(rays.size())), any = got;
    std::vector<std::thread> pool;
    for (int k = 0; k < kThreads; ++k)
        pool.emplace_back([&, k] {
            for (int round = 0; round < 2; ++round) {  // the second finds the thread's arrays made
                intersect(scene, std::span<const Ray>(rays), std::span<SceneHit>(got[k]),
                          {.isa = active_isa(), .threads = 2});
                occluded(scene, std::span<const Ray>(rays), std::span<SceneHit>(any[k]),
                         {.isa = active_isa(), .threads = 2});
            }
        });
    for (auto& t : pool) t.join();
    for (int k = 0; k < kThreads; ++k)
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_TRUE(got[k][i] == want[i])
                << "thread " << k << " ray " << i << ": t " << got[k][i].t << " against " << want[i].t;
            ASSERT_EQ(any[k][i].hit(), want_any[i].hit()) << "thread " << k << " ray " << i;
        }
}

}  // namespace
}  // namespace simdbvh
