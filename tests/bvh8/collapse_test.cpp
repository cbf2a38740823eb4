// Structure of the two build steps, checked separately: collapse (the wide
// topology, collapse.h) and pack (Node8 / Tri8 blocks). Triangle conservation,
// child boxes bounding their subtrees, <= 8 children, leaf sizes, empty slots
// last and never hit, and the SAH collapse never costing more than greedy.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "collapse.h"
#include "simdbvh/kernels/box.h"
#include "simdbvh/scene/rays.h"
#include "simdbvh/scene/scenes.h"

namespace simdbvh {
namespace {

Aabb tri_box(const Mesh& mesh, std::uint32_t prim) {
    Aabb b;
    for (int k = 0; k < 3; ++k) b.grow(mesh.vertex(prim, k));
    return b;
}

void check_topology(const Mesh& mesh, const Bvh2& bvh2, const bvh8::WideTopology& topo, const Bvh8Options& o,
                    const std::string& what) {
    SCOPED_TRACE(what);
    const auto& ids = bvh2.prim_ids();
    ASSERT_FALSE(topo.nodes.empty());
    EXPECT_EQ(topo.nodes[0].box.lo, bvh2.bounds().lo);
    EXPECT_EQ(topo.nodes[0].box.hi, bvh2.bounds().hi);
    // The largest BVH2 leaf (a leaf that is already larger than max_leaf_size is kept whole).
    std::uint32_t biggest_bvh2_leaf = 0;
    for (const Node2& n : bvh2.nodes())
        if (n.is_leaf()) biggest_bvh2_leaf = std::max(biggest_bvh2_leaf, n.count);
    std::vector<int> prim_seen(ids.size(), 0), node_refs(topo.nodes.size(), 0);
    std::vector<std::pair<std::uint32_t, int>> stack{{0u, 1}};
    int depth = 0;
    while (!stack.empty()) {
        auto [i, d] = stack.back();
        stack.pop_back();
        ASSERT_LT(i, topo.nodes.size());
        node_refs[i]++;
        depth = std::max(depth, d);
        const bvh8::WideNode& n = topo.nodes[i];
        ASSERT_GE(n.child_count, 1);
        ASSERT_LE(n.child_count, 8);
        if (i != 0 || !n.children[0].is_leaf()) {
            EXPECT_GE(n.child_count, 2) << "node " << i;
        }
        for (int c = 0; c < n.child_count; ++c) {
            const bvh8::WideChild& ch = n.children[c];
            EXPECT_TRUE(n.box.contains(ch.box)) << "node " << i << " child " << c;
            if (ch.is_leaf()) {
                ASSERT_LE(std::size_t(ch.index) + ch.count, topo.prims.size());
                EXPECT_TRUE(ch.count <= std::uint32_t(o.max_leaf_size) || ch.count <= biggest_bvh2_leaf)
                    << "leaf of " << ch.count << " triangles";
                for (std::uint32_t k = ch.index; k < ch.index + ch.count; ++k) {
                    const std::uint32_t pos = topo.prims[k];
                    ASSERT_LT(pos, ids.size());
                    prim_seen[pos]++;
                    EXPECT_TRUE(ch.box.contains(tri_box(mesh, ids[pos]))) << "leaf box misses triangle " << ids[pos];
                }
            } else {
                ASSERT_LT(ch.index, topo.nodes.size());
                EXPECT_EQ(topo.nodes[ch.index].box.lo, ch.box.lo);
                EXPECT_EQ(topo.nodes[ch.index].box.hi, ch.box.hi);
                stack.push_back({ch.index, d + 1});
            }
        }
    }
    for (std::size_t k = 0; k < node_refs.size(); ++k) ASSERT_EQ(node_refs[k], 1) << "node " << k;
    for (std::size_t k = 0; k < prim_seen.size(); ++k) ASSERT_EQ(prim_seen[k], 1) << "triangle position " << k;
    EXPECT_EQ(topo.prims.size(), ids.size());
    EXPECT_EQ(depth, topo.depth);
    EXPECT_LE(depth, kMaxDepth);
}

void check_packed(const Mesh& mesh, const Bvh2& bvh2, const bvh8::WideTopology& topo, const Bvh8& b,
                  const Bvh8Options& o, const std::string& what) {
    SCOPED_TRACE(what);
    const auto& nodes = b.nodes();
    const auto& blocks = b.blocks();
    ASSERT_EQ(nodes.size(), topo.nodes.size());
    std::vector<int> seen(mesh.size(), 0);
    std::vector<int> block_refs(blocks.size(), 0);
    std::size_t used = 0, leaves = 0;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const Node8& n = nodes[i];
        const bvh8::WideNode& w = topo.nodes[i];
        for (int c = 0; c < 8; ++c) {
            const Aabb box = n.boxes.get(c);
            if (c >= w.child_count) {  // empty slots: at the end, +inf/-inf, marked
                EXPECT_EQ(n.children[c].count, kInvalidPrim);
                EXPECT_TRUE(std::isinf(box.lo.x) && box.lo.x > 0 && std::isinf(box.hi.x) && box.hi.x < 0);
                EXPECT_TRUE(std::isinf(box.lo.y) && box.lo.y > 0 && std::isinf(box.hi.y) && box.hi.y < 0);
                EXPECT_TRUE(std::isinf(box.lo.z) && box.lo.z > 0 && std::isinf(box.hi.z) && box.hi.z < 0);
                continue;
            }
            ++used;
            const bvh8::WideChild& wc = w.children[c];
            EXPECT_EQ(box.lo, wc.box.lo);
            EXPECT_EQ(box.hi, wc.box.hi);
            const Child8 ch = n.children[c];
            ASSERT_NE(ch.count, kInvalidPrim);
            if (ch.count == 0) {
                EXPECT_EQ(ch.index, wc.index);
                continue;
            }
            ++leaves;
            ASSERT_LE(std::size_t(ch.index) + ch.count, blocks.size());
            EXPECT_EQ(ch.count, (wc.count + 7) / 8);
            std::uint32_t tris = 0;
            for (std::uint32_t k = ch.index; k < ch.index + ch.count; ++k) {
                block_refs[k]++;
                const Tri8& blk = blocks[k];
                bool ended = false;
                for (int lane = 0; lane < 8; ++lane) {
                    if (blk.prim[lane] == kInvalidPrim) {  // empty lanes: NaN, only at the end of the leaf's last block
                        ended = true;
                        EXPECT_EQ(k, ch.index + ch.count - 1);
                        EXPECT_TRUE(std::isnan(blk.v0x[lane]) && std::isnan(blk.v1y[lane]) && std::isnan(blk.v2z[lane]));
                        continue;
                    }
                    EXPECT_FALSE(ended) << "filled lane after an empty one";
                    const std::uint32_t p = blk.prim[lane];
                    ASSERT_LT(p, mesh.size());
                    seen[p]++;
                    ++tris;
                    EXPECT_EQ(blk.v0(lane), mesh.vertex(p, 0));
                    EXPECT_EQ(blk.v1(lane), mesh.vertex(p, 1));
                    EXPECT_EQ(blk.v2(lane), mesh.vertex(p, 2));
                    EXPECT_TRUE(box.contains(tri_box(mesh, p)));
                }
            }
            EXPECT_EQ(tris, wc.count);
        }
    }
    // Every triangle of the BVH2 exactly once (degenerate triangles left out of the BVH2 stay out).
    std::vector<int> in_bvh2(mesh.size(), 0);
    for (std::uint32_t p : bvh2.prim_ids()) in_bvh2[p] = 1;
    for (std::size_t p = 0; p < mesh.size(); ++p) ASSERT_EQ(seen[p], in_bvh2[p]) << "triangle " << p;
    for (std::size_t k = 0; k < block_refs.size(); ++k) ASSERT_EQ(block_refs[k], 1) << "block " << k;
    const Bvh8Stats& s = b.stats();
    EXPECT_EQ(s.nodes, nodes.size());
    EXPECT_EQ(s.leaves, leaves);
    EXPECT_EQ(s.blocks, blocks.size());
    EXPECT_EQ(s.triangles, bvh2.prim_ids().size());
    EXPECT_EQ(s.depth, topo.depth);
    EXPECT_DOUBLE_EQ(s.fill_rate, double(used) / (8.0 * double(nodes.size())));
    EXPECT_DOUBLE_EQ(s.sah_cost, bvh8::sah_cost(topo, o));
    EXPECT_GT(s.bytes_per_triangle, 0);
}

struct Scene {
    std::string name;
    Mesh mesh;
};

std::vector<Scene> scenes() {
    std::vector<Scene> out;
    for (std::string n : {"icosphere-3", "soup-2000", "bunny", "dragon-res4"}) {
        const bool npm = n == "bunny" || n.rfind("dragon", 0) == 0;
        if (npm && !scene::is_cached(n)) continue;
        out.push_back({n, scene::load_scene(n)});
    }
    return out;
}

TEST(Bvh8Collapse, TopologyAndPackingAreSound) {
    for (const Scene& sc : scenes()) {
        for (int bvh2_leaf : {1, 4, 8}) {
            BuildOptions bo;
            bo.max_leaf_size = bvh2_leaf;
            const Bvh2 bvh2 = Bvh2::build(sc.mesh, bo);
            for (Collapse c : {Collapse::sah, Collapse::greedy}) {
                for (int leaf : {1, 4, 8, 16}) {
                    Bvh8Options o;
                    o.collapse = c;
                    o.max_leaf_size = leaf;
                    const std::string what = sc.name + " bvh2 leaf " + std::to_string(bvh2_leaf) + " " +
                                             std::string(name(c)) + " leaf " + std::to_string(leaf);
                    const bvh8::WideTopology topo = bvh8::collapse(bvh2, o);
                    check_topology(sc.mesh, bvh2, topo, o, what);
                    check_packed(sc.mesh, bvh2, topo, Bvh8::build(bvh2, o), o, what);
                }
            }
        }
    }
}

TEST(Bvh8Collapse, SahCostNeverAboveGreedy) {
    for (const Scene& sc : scenes()) {
        const Bvh2 bvh2 = Bvh2::build(sc.mesh);
        for (int leaf : {4, 8, 16}) {
            for (float node_cost : {0.5f, 1.0f, 2.0f}) {
                Bvh8Options o;
                o.max_leaf_size = leaf;
                o.node_cost = node_cost;
                o.collapse = Collapse::sah;
                const double sah = Bvh8::build(bvh2, o).stats().sah_cost;
                o.collapse = Collapse::greedy;
                const double greedy = Bvh8::build(bvh2, o).stats().sah_cost;
                EXPECT_LE(sah, greedy * (1 + 1e-9)) << sc.name << " leaf " << leaf << " node cost " << node_cost;
                EXPECT_GT(sah, 0);
            }
        }
    }
}

// Empty slots (+inf/-inf) never hit, whatever the ray: axis-aligned with
// +-0 components, origins on planes, random.
TEST(Bvh8Collapse, EmptySlotsNeverHit) {
    std::size_t empty_slots = 0;
    for (std::size_t tris : {3u, 20u, 37u, 90u}) {  // partly filled nodes
        const Mesh mesh = scene::random_soup(tris, 3);
        const Bvh8 b = Bvh8::build(mesh);
        std::vector<Ray> rays = scene::incoherent_rays(mesh.bounds(), 300, 9);
        for (float sx : {0.0f, -0.0f, 1.0f, -1.0f})
            for (float sy : {0.0f, -0.0f, 1.0f, -1.0f})
                for (float sz : {0.0f, -0.0f, 1.0f, -1.0f}) rays.push_back({{0, 0, 0}, 0, {sx, sy, sz}});
        for (const Ray& ray : rays) {
            const PreparedRay r = prepare(ray);
            for (const Node8& n : b.nodes())
                for (int c = 0; c < 8; ++c) {
                    if (n.children[c].count != kInvalidPrim) continue;
                    ++empty_slots;
                    float e;
                    ASSERT_FALSE(intersect_box(r, n.boxes.get(c), std::numeric_limits<float>::infinity(), &e));
                }
        }
    }
    EXPECT_GT(empty_slots, 0u);
}

TEST(Bvh8Collapse, EmptyMesh) {
    const Bvh2 bvh2 = Bvh2::build(Mesh{});
    const bvh8::WideTopology topo = bvh8::collapse(bvh2, {});
    EXPECT_TRUE(topo.nodes.empty());
    const Bvh8 b = Bvh8::build(bvh2);
    EXPECT_TRUE(b.nodes().empty());
    EXPECT_EQ(b.stats().triangles, 0u);
    EXPECT_EQ(b.stats().sah_cost, 0.0);
}

}  // namespace
}  // namespace simdbvh
