// Bvh2::refit: a refit with the build's own mesh reproduces the tree byte for
// byte; after a twist every box bounds its subtree's triangles (checked from
// the mesh, not from the tree) and hits are bit-identical to brute force on
// the moved mesh; 1 and 2 threads give the same bytes; bad meshes throw and
// leave the tree as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/workloads/deform.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh {
namespace {

bool same_nodes(const Bvh2& a, const Bvh2& b) {
    return a.nodes().size() == b.nodes().size() &&
           std::memcmp(a.nodes().data(), b.nodes().data(), a.nodes().size() * sizeof(Node2)) == 0 &&
           std::memcmp(a.triangles().data(), b.triangles().data(), a.triangles().size() * sizeof(TriangleVerts)) == 0 &&
           a.prim_ids() == b.prim_ids();
}

// Every vertex of every triangle under node i lies in the box of i and of each ancestor.
void expect_bounds(const Bvh2& bvh, const Mesh& mesh, std::uint32_t i, const Aabb& parent) {
    const Node2& n = bvh.nodes()[i];
    ASSERT_TRUE(parent.contains(n.box)) << "node " << i;
    if (!n.is_leaf()) {
        expect_bounds(bvh, mesh, n.first, n.box);
        expect_bounds(bvh, mesh, n.first + 1, n.box);
        return;
    }
    for (std::uint32_t k = n.first; k < n.first + n.count; ++k)
        for (int v = 0; v < 3; ++v) {
            const Vec3 p = mesh.vertex(bvh.prim_ids()[k], v);
            ASSERT_TRUE(n.box.contains(Aabb{p, p})) << "node " << i << " triangle " << bvh.prim_ids()[k];
        }
}

TEST(Bvh2Refit, SameMeshReproducesTheBuild) {
    const Mesh mesh = workloads::icosphere(4);
    const Bvh2 built = Bvh2::build(mesh);
    Bvh2 b = built;
    b.refit(mesh);
    EXPECT_TRUE(same_nodes(b, built));
    EXPECT_EQ(b.stats().sah_cost, built.stats().sah_cost);
    // Twisted and back: the build again, bit for bit.
    b.refit(workloads::twist(mesh, 2.0));
    EXPECT_FALSE(same_nodes(b, built));
    b.refit(mesh, 2);
    EXPECT_TRUE(same_nodes(b, built));
}

TEST(Bvh2Refit, TwistedHitsEqualBruteForce) {
    const Mesh mesh = workloads::random_soup(5000, 3);
    Bvh2 b = Bvh2::build(mesh);
    Bvh2 b2 = b;
    for (double angle : {0.4, 1.5, 3.0}) {
        const Mesh moved = workloads::twist(mesh, angle);
        b.refit(moved, 1);
        b2.refit(moved, 2);
        ASSERT_TRUE(same_nodes(b, b2)) << angle;
        expect_bounds(b, moved, 0, Aabb{{-INFINITY, -INFINITY, -INFINITY}, {INFINITY, INFINITY, INFINITY}});
        const Bvh2 rebuilt = Bvh2::build(moved);
        EXPECT_GT(b.stats().sah_cost, rebuilt.stats().sah_cost)
            << "a twisted soup's refit tree is worse than a rebuild";
        const auto rays = workloads::generate_rays(moved, workloads::RayKind::incoherent, 3000, 5);
        std::size_t hits = 0;
        for (const Ray& r : rays) {
            const Hit want = brute_force_intersect(moved, r);
            const Hit got = intersect(b, r);
            ASSERT_TRUE(got == want) << angle << " prim " << got.prim << " vs " << want.prim;
            ASSERT_EQ(occluded(b, r).hit(), want.hit());
            hits += want.hit();
        }
        EXPECT_GT(hits, rays.size() / 4);
    }
}

TEST(Bvh2Refit, BadMeshThrowsAndLeavesTheTree) {
    const Mesh mesh = workloads::icosphere(2);
    const Bvh2 built = Bvh2::build(mesh);
    Bvh2 b = built;
    Mesh fewer = mesh;
    fewer.triangles.pop_back();
    EXPECT_THROW(b.refit(fewer), Error);
    Mesh nan = workloads::twist(mesh, 1.0);
    nan.positions[nan.triangles.back()[1]].y = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(b.refit(nan), Error);
    Mesh index = workloads::twist(mesh, 1.0);
    index.triangles.back()[2] = std::uint32_t(index.positions.size());
    EXPECT_THROW(b.refit(index), Error);
    EXPECT_TRUE(same_nodes(b, built));
}

}  // namespace
}  // namespace simdbvh
