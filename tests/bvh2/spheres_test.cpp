// Seed 002's bounding-sphere hierarchy: bit-identical closest hits and any-hit
// agreement with brute force, conservative spheres, degenerate input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "simdbvh/bvh2/spheres.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"
#include "support/sanitizer.h"

namespace simdbvh {
namespace {

using workloads::RayKind;

constexpr float kInf = std::numeric_limits<float>::infinity();

struct Case {
    std::string scene;
    RayKind kind;
};

std::string case_name(const testing::TestParamInfo<Case>& info) {
    std::string s = info.param.scene + "_" + std::string(workloads::name(info.param.kind));
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

class SpheresVsBrute : public testing::TestWithParam<Case> {};

TEST_P(SpheresVsBrute, ClosestAndAnyHitMatchBruteForce) {
    const Case& c = GetParam();
    if (c.scene == "bunny" && !workloads::is_cached(c.scene))
        GTEST_SKIP() << "scene '" << c.scene << "' is not cached: run scripts/fetch_scenes.sh";
    const Mesh mesh = workloads::load_scene(c.scene);
    const SphereBvh bvh = SphereBvh::build(mesh);
    // (an eighth of the rays under a sanitizer: support/sanitizer.h)
    const std::size_t count =
        test::sampled(std::clamp<std::size_t>(100'000'000 / std::max<std::size_t>(mesh.size(), 1), 500, 20000), 200);
    const auto rays = workloads::generate_rays(mesh, c.kind, count, /*seed=*/11);
    std::vector<Hit> got(rays.size()), any(rays.size());
    intersect(bvh, rays, got);
    occluded(bvh, rays, any);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit want = brute_force_intersect(mesh, rays[i]);
        ASSERT_EQ(got[i], want) << "ray " << i << ": spheres prim " << got[i].prim << " t " << got[i].t
                                << ", brute prim " << want.prim << " t " << want.t;
        ASSERT_EQ(intersect(bvh, rays[i]), want) << "single-ray path, ray " << i;
        ASSERT_EQ(any[i].hit(), want.hit()) << "any-hit disagrees on ray " << i;
        if (any[i].hit()) {
            EXPECT_LE(rays[i].tmin, any[i].t);
            EXPECT_LE(any[i].t, rays[i].tmax);
            // The reported triangle really is hit at that t.
            const Hit self = brute_force_intersect(mesh, Ray{rays[i].org, any[i].t, rays[i].dir, any[i].t});
            EXPECT_TRUE(self.hit()) << "any-hit ray " << i;
        }
        hits += want.hit();
    }
    if (c.kind == RayKind::primary) {  // (diffuse bounces off a convex icosphere never hit)
        EXPECT_GT(hits, rays.size() / 10) << "too few hits to mean anything";
    }
    // Threads and the stats path give the same hits.
    std::vector<Hit> par(rays.size());
    TraceOptions o;
    o.threads = 2;
    intersect(bvh, rays, par, o);
    TraceStats st;
    o.stats = &st;
    std::vector<Hit> counted(rays.size());
    intersect(bvh, rays, counted, o);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(par[i], got[i]);
        ASSERT_EQ(counted[i], got[i]);
    }
    EXPECT_EQ(st.rays, rays.size());
    EXPECT_GT(st.nodes_visited, 0u);
}

INSTANTIATE_TEST_SUITE_P(Scenes, SpheresVsBrute,
                         testing::Values(Case{"icosphere-4", RayKind::primary},
                                         Case{"icosphere-4", RayKind::incoherent},
                                         Case{"icosphere-4", RayKind::diffuse}, Case{"soup-3000", RayKind::primary},
                                         Case{"soup-3000", RayKind::incoherent}, Case{"bunny", RayKind::primary},
                                         Case{"bunny", RayKind::incoherent}),
                         case_name);

// Every vertex lies inside its node's sphere and every subtree's vertices lie
// inside the ancestors' spheres (checked through the leaf ranges).
TEST(Spheres, EverySphereBoundsItsVertices) {
    const Mesh mesh = workloads::load_scene("soup-3000");
    const SphereBvh bvh = SphereBvh::build(mesh);
    const auto& nodes = bvh.nodes();
    ASSERT_FALSE(nodes.empty());
    std::vector<std::pair<std::uint32_t, std::vector<std::uint32_t>>> stack{{0u, {}}};
    std::size_t leaf_tris = 0;
    while (!stack.empty()) {
        auto [i, anc] = stack.back();
        stack.pop_back();
        anc.push_back(i);
        const SphereNode& n = nodes[i];
        if (n.is_leaf()) {
            leaf_tris += n.count;
            EXPECT_LE(n.count, 8u);
            for (std::uint32_t k = n.first; k < n.first + n.count; ++k)
                for (const Vec3& v : {bvh.triangles()[k].v0, bvh.triangles()[k].v1, bvh.triangles()[k].v2})
                    for (std::uint32_t a : anc) {
                        const SphereNode& s = nodes[a];
                        const double dx = double(v.x) - s.center.x, dy = double(v.y) - s.center.y,
                                     dz = double(v.z) - s.center.z;
                        ASSERT_LE(std::sqrt(dx * dx + dy * dy + dz * dz), double(s.radius));
                    }
        } else {
            ASSERT_GT(n.first, i);
            stack.push_back({n.first, anc});
            stack.push_back({n.first + 1, anc});
        }
    }
    EXPECT_EQ(leaf_tris, mesh.size());
    const SphereBuildStats& st = bvh.stats();
    EXPECT_EQ(st.nodes, nodes.size());
    EXPECT_EQ(st.triangles, mesh.size());
    EXPECT_GT(st.depth, 1);
    EXPECT_LE(st.depth, kMaxDepth);
    EXPECT_GT(st.bytes_per_triangle, 40.0);
    EXPECT_GT(st.sah_cost, 0.0);
    EXPECT_GT(st.sphere_sah_cost, 0.0);
    // Same tree for any thread count.
    BuildOptions o;
    o.threads = 2;
    const SphereBvh b2 = SphereBvh::build(mesh, o);
    ASSERT_EQ(b2.nodes().size(), nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        EXPECT_EQ(b2.nodes()[i].radius, nodes[i].radius);
        EXPECT_EQ(b2.nodes()[i].first, nodes[i].first);
    }
}

// The ray/sphere test never rejects a ray through a point inside the sphere,
// including far-away, tiny and grazing cases.
TEST(Spheres, RaySphereTestIsConservative) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 200000; ++i) {
        const float scale = std::ldexp(1.0f, int(rng() % 40) - 20);
        const float off = std::ldexp(1.0f, int(rng() % 30) - 10);
        SphereNode s{{u(rng) * off, u(rng) * off, u(rng) * off}, scale, 0, 1};
        // A point on (or just inside) the sphere's surface.
        Vec3 dir{u(rng), u(rng), u(rng)};
        const double len = std::sqrt(double(dir.x) * dir.x + double(dir.y) * dir.y + double(dir.z) * dir.z);
        if (len < 1e-3) continue;
        const double k = double(scale) * (1.0 - 1e-7) / len;
        const Vec3 p{float(s.center.x + dir.x * k), float(s.center.y + dir.y * k), float(s.center.z + dir.z * k)};
        const double dx = double(p.x) - s.center.x, dy = double(p.y) - s.center.y, dz = double(p.z) - s.center.z;
        if (std::sqrt(dx * dx + dy * dy + dz * dz) > double(s.radius)) continue;  // rounding pushed it out
        // A ray from far away through p.
        const Vec3 d{u(rng), u(rng), u(rng)};
        if (std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z) < 1e-3f) continue;
        const float back = std::ldexp(1.0f, int(rng() % 30) - 10);
        const Vec3 o{p.x - d.x * back, p.y - d.y * back, p.z - d.z * back};
        const PreparedRay r = prepare(Ray{o, 0.0f, d, kInf});
        float entry;
        ASSERT_TRUE(intersect_sphere(r, s, kInf, &entry)) << "case " << i;
    }
    // A clear miss is rejected.
    const SphereNode s{{0, 0, 0}, 1.0f, 0, 1};
    float entry;
    EXPECT_FALSE(intersect_sphere(prepare(Ray{{5, 5, 5}, 0, {1, 0, 0}, kInf}), s, kInf, &entry));
    EXPECT_FALSE(intersect_sphere(prepare(Ray{{-5, 0, 0}, 0, {1, 0, 0}, 1.0f}), s, 1.0f, &entry));  // before it
    EXPECT_FALSE(intersect_sphere(prepare(Ray{{5, 0, 0}, 0, {1, 0, 0}, kInf}), s, kInf, &entry));   // behind
    EXPECT_TRUE(intersect_sphere(prepare(Ray{{-5, 0, 0}, 0, {1, 0, 0}, kInf}), s, kInf, &entry));
    EXPECT_LE(entry, 4.0f);
}

Ray down_at(float x, float y) { return Ray{{x, y, 5.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, kInf}; }

TEST(SpheresDegenerate, EmptyMeshMissesEverything) {
    const SphereBvh bvh = SphereBvh::build(Mesh{});
    EXPECT_TRUE(bvh.nodes().empty());
    EXPECT_FALSE(intersect(bvh, down_at(0, 0)).hit());
    EXPECT_FALSE(occluded(bvh, down_at(0, 0)).hit());
    EXPECT_EQ(bvh.stats().nodes, 0u);
}

TEST(SpheresDegenerate, IdenticalTrianglesTerminateAndTieToLowestId) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.triangles.assign(1000, Triangle{0, 1, 2});
    const SphereBvh bvh = SphereBvh::build(m);
    EXPECT_LE(bvh.stats().depth, kMaxDepth);
    for (float x : {0.1f, 0.3f, 0.45f}) {
        const Hit h = intersect(bvh, down_at(x, 0.2f));
        EXPECT_EQ(h.prim, 0u);
        EXPECT_EQ(h, brute_force_intersect(m, down_at(x, 0.2f)));
        EXPECT_TRUE(occluded(bvh, down_at(x, 0.2f)).hit());
    }
    EXPECT_FALSE(intersect(bvh, down_at(0.75f, 0.5f)).hit());
}

TEST(SpheresDegenerate, OneTriangleAndZeroArea) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
    m.triangles = {{0, 1, 2}, {0, 1, 3}, {3, 3, 3}};
    const SphereBvh bvh = SphereBvh::build(m);
    const Hit h = intersect(bvh, down_at(0.25f, 0.5f));
    EXPECT_EQ(h, brute_force_intersect(m, down_at(0.25f, 0.5f)));
    EXPECT_EQ(h.prim, 0u);
    for (float x : {0.0f, 0.5f, 1.0f, 1.5f, 2.0f})
        for (float y : {0.0f, 0.25f, 1.0f}) {
            EXPECT_EQ(intersect(bvh, down_at(x, y)), brute_force_intersect(m, down_at(x, y)));
            EXPECT_EQ(occluded(bvh, down_at(x, y)).hit(), brute_force_occluded(m, down_at(x, y)).hit());
        }
}

}  // namespace
}  // namespace simdbvh
