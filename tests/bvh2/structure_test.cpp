// Structural invariants of every builder: children inside parents, every
// triangle in exactly one leaf, leaf boxes bound their triangles, depth cap.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh {
namespace {

void check_structure(const Mesh& mesh, const Bvh2& bvh, int max_depth) {
    const auto& nodes = bvh.nodes();
    const auto& ids = bvh.prim_ids();
    ASSERT_EQ(ids.size(), mesh.size());
    std::vector<int> seen(mesh.size(), 0);
    std::vector<std::pair<std::uint32_t, int>> stack{{0u, 1}};
    std::size_t reached = 0;
    int depth = 0;
    while (!stack.empty()) {
        auto [i, d] = stack.back();
        stack.pop_back();
        ASSERT_LT(i, nodes.size());
        ++reached;
        depth = std::max(depth, d);
        const Node2& n = nodes[i];
        if (n.is_leaf()) {
            ASSERT_LE(std::size_t(n.first) + n.count, ids.size());
            for (std::uint32_t k = n.first; k < n.first + n.count; ++k) {
                seen[ids[k]]++;
                Aabb tb;
                for (int v = 0; v < 3; ++v) tb.grow(mesh.vertex(ids[k], v));
                EXPECT_TRUE(n.box.contains(tb)) << "leaf " << i << " does not bound triangle " << ids[k];
                const TriangleVerts& tv = bvh.triangles()[k];
                EXPECT_EQ(tv.v0, mesh.vertex(ids[k], 0));
                EXPECT_EQ(tv.v2, mesh.vertex(ids[k], 2));
            }
        } else {
            ASSERT_LT(n.first + 1, nodes.size());
            EXPECT_TRUE(n.box.contains(nodes[n.first].box)) << "node " << i;
            EXPECT_TRUE(n.box.contains(nodes[n.first + 1].box)) << "node " << i;
            stack.push_back({n.first, d + 1});
            stack.push_back({n.first + 1, d + 1});
        }
    }
    EXPECT_EQ(reached, nodes.size()) << "unreachable nodes";
    for (std::size_t t = 0; t < seen.size(); ++t) ASSERT_EQ(seen[t], 1) << "triangle " << t;
    EXPECT_LE(depth, max_depth);
    EXPECT_EQ(depth, bvh.stats().depth);
}

class Structure : public testing::TestWithParam<Builder> {};

TEST_P(Structure, InvariantsHoldOnSoupAndSphere) {
    BuildOptions opts;
    opts.builder = GetParam();
    for (const Mesh& m : {workloads::random_soup(5000, 3), workloads::icosphere(4)}) {
        const Bvh2 bvh = Bvh2::build(m, opts);
        check_structure(m, bvh, opts.max_depth);
        EXPECT_GT(bvh.stats().leaves, 1u);
    }
}

TEST_P(Structure, DepthCapHoldsOnDegenerateInput) {
    // 1,000 identical triangles, and all centroids equal: must terminate under the cap.
    Mesh same;
    same.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    same.triangles.assign(1000, Triangle{0, 1, 2});
    for (int cap : {8, 64}) {
        BuildOptions opts;
        opts.builder = GetParam();
        opts.max_depth = cap;
        const Bvh2 bvh = Bvh2::build(same, opts);
        check_structure(same, bvh, cap);
    }
}

TEST_P(Structure, SameTreeForAnyThreadCount) {
    const Mesh m = workloads::random_soup(200'000, 11);
    BuildOptions one, many;
    one.builder = many.builder = GetParam();
    many.threads = 4;
    const Bvh2 a = Bvh2::build(m, one), b = Bvh2::build(m, many);
    ASSERT_EQ(a.nodes().size(), b.nodes().size());
    ASSERT_EQ(0, std::memcmp(a.nodes().data(), b.nodes().data(), a.nodes().size() * sizeof(Node2)));
    ASSERT_EQ(a.prim_ids(), b.prim_ids());
}

INSTANTIATE_TEST_SUITE_P(Builders, Structure,
                         testing::Values(Builder::sah_binned, Builder::sah_sweep, Builder::midpoint, Builder::median,
                                         Builder::variance),
                         [](const auto& info) {
                             std::string s(name(info.param));
                             for (char& c : s)
                                 if (c == '-') c = '_';
                             return s;
                         });

TEST(Structure, BinnedSahBeatsMidpointOnSahCost) {
    const Mesh m = workloads::random_soup(20000, 5);
    BuildOptions sah, mid;
    mid.builder = Builder::midpoint;
    EXPECT_LT(Bvh2::build(m, sah).stats().sah_cost, Bvh2::build(m, mid).stats().sah_cost);
}

TEST(Structure, LeavesRespectMaxLeafSize) {
    const Mesh m = workloads::random_soup(20000, 9);
    for (int leaf : {1, 4, 8}) {
        BuildOptions o;
        o.max_leaf_size = leaf;
        const Bvh2 bvh = Bvh2::build(m, o);
        for (const Node2& n : bvh.nodes())
            if (n.is_leaf()) ASSERT_LE(n.count, std::uint32_t(leaf));
    }
}

// The root's box comes from per-block bounds merged in block order: the same
// bits as one pass over every vertex (Mesh::bounds), -0 against +0 included,
// for any thread count, over several 64K-reference blocks.
TEST(Structure, RootBoxIsTheMeshBoundsBitForBit) {
    Mesh m;
    const std::uint32_t n = 200000;
    std::uint32_t seed = 12345;
    auto next = [&] {
        seed = seed * 1664525u + 1013904223u;
        return float(seed >> 8) / float(1 << 24);
    };
    for (std::uint32_t i = 0; i < n; ++i) {
        const Vec3 c{next(), next(), next()};
        const std::uint32_t v = std::uint32_t(m.positions.size());
        m.positions.push_back(c);
        m.positions.push_back({c.x + 0.01f, c.y, c.z});
        m.positions.push_back({c.x, c.y + 0.01f, c.z + 0.01f});
        m.triangles.push_back({v, v + 1, v + 2});
    }
    // Extremes shared by +0 and -0, first met as +0 in one block and as -0
    // in another (x, y: lower bounds; z: +0 first, then -0 at the upper end
    // after scaling every z below 0).
    for (Vec3& p : m.positions) p.z -= 2.0f;
    m.positions[3 * 70000].x = 0.0f;
    m.positions[3 * 150000 + 1].x = -0.0f;
    m.positions[3 * 5].y = -0.0f;
    m.positions[3 * 190000].y = 0.0f;
    m.positions[3 * 100000 + 2].z = 0.0f;
    m.positions[3 * 130000].z = -0.0f;
    const Aabb want = m.bounds();
    ASSERT_EQ(std::signbit(want.lo.x), false);
    ASSERT_EQ(std::signbit(want.lo.y), true);
    for (int threads : {1, 2, 3}) {
        BuildOptions o;
        o.threads = threads;
        const Aabb got = Bvh2::build(m, o).bounds();
        EXPECT_EQ(std::memcmp(&got, &want, sizeof(Aabb)), 0) << "threads " << threads;
    }
}

}  // namespace
}  // namespace simdbvh
