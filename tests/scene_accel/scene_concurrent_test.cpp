// Many threads tracing one scene at once, each batch split over threads of
// its own (run under the tsan preset by scripts/tsan.sh): the brute force's
// hits on every thread. Each calling thread keeps its own pool of chunk
// arrays (traverse.cpp), which its batch's workers share.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <thread>

#include "simdbvh/scene/scenes.h"
#include "simdbvh/scene_accel/scene.h"

namespace simdbvh {
namespace {

SceneDesc mixed_scene() {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    SceneDesc s;
    s.geometries.push_back(scene::icosphere(1));
    SphereSet spheres;
    for (int i = 0; i < 30; ++i) spheres.spheres.push_back({{u(rng), u(rng), u(rng)}, 0.1f + 0.1f * std::fabs(u(rng))});
    s.geometries.push_back(spheres);
    for (std::uint32_t i = 0; i < 20; ++i)
        s.instances.push_back({i % 2, Affine3::translation({4 * u(rng), 4 * u(rng), 4 * u(rng)}) *
                                          Affine3::rotation({u(rng), u(rng), 1.5f}, 3.0 * u(rng))});
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
    std::size_t hits = 0;
    for (const SceneHit& h : want) hits += h.hit();
    ASSERT_GT(hits, rays.size() / 4);
    constexpr int kThreads = 3;
    std::vector<std::vector<SceneHit>> got(kThreads, std::vector<SceneHit>(rays.size())), any = got;
    std::vector<std::thread> pool;
    for (int k = 0; k < kThreads; ++k)
        pool.emplace_back([&, k] {
            for (int round = 0; round < 2; ++round) {  // the second finds the thread's arrays made
                intersect(scene, std::span<const Ray>(rays), std::span<SceneHit>(got[k]), active_isa(), 2);
                occluded(scene, std::span<const Ray>(rays), std::span<SceneHit>(any[k]), active_isa(), 2);
            }
        });
    for (auto& t : pool) t.join();
    for (int k = 0; k < kThreads; ++k)
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_TRUE(got[k][i] == want[i]) << "thread " << k << " ray " << i << ": t " << got[k][i].t << " against "
                                              << want[i].t;
            ASSERT_EQ(any[k][i].hit(), want_any[i].hit()) << "thread " << k << " ray " << i;
        }
}

}  // namespace
}  // namespace simdbvh
