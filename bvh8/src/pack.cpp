// Step 2 of the BVH8 build: the wide topology packed into SoA Node8s (child
// boxes in Box8, empty slots +inf/-inf at the end, Embree-style) and leaves
// gathered into Tri8 blocks (empty lanes: NaN vertices, kInvalidPrim).
#include "collapse.h"

namespace simdbvh::bvh8 {

void pack(const Bvh2& bvh2, const WideTopology& topo, std::vector<Node8>& nodes, std::vector<Tri8>& blocks,
          Bvh8Stats& stats) {
    const auto& tris = bvh2.triangles();
    const auto& ids = bvh2.prim_ids();
    nodes.assign(topo.nodes.size(), Node8{});
    blocks.clear();
    std::size_t blocks_needed = 0, used_slots = 0, leaves = 0;
    for (const WideNode& w : topo.nodes)
        for (int c = 0; c < w.child_count; ++c)
            if (w.children[c].is_leaf()) blocks_needed += (w.children[c].count + 7u) / 8u;
    blocks.reserve(blocks_needed);
    for (std::size_t i = 0; i < topo.nodes.size(); ++i) {
        const WideNode& w = topo.nodes[i];
        Node8& n = nodes[i];
        n.boxes.clear();
        for (int c = 0; c < 8; ++c) n.children[c] = Child8{0, kInvalidPrim};
        for (int c = 0; c < w.child_count; ++c) {
            const WideChild& wc = w.children[c];
            n.boxes.set(c, wc.box);
            ++used_slots;
            if (!wc.is_leaf()) {
                n.children[c] = Child8{wc.index, 0};
                continue;
            }
            ++leaves;
            const std::uint32_t first = std::uint32_t(blocks.size());
            const std::uint32_t count = (wc.count + 7u) / 8u;
            for (std::uint32_t b = 0; b < count; ++b) {
                Tri8& blk = blocks.emplace_back();
                blk.clear();
                for (std::uint32_t lane = 0; lane < 8 && b * 8 + lane < wc.count; ++lane) {
                    const std::uint32_t pos = topo.prims[wc.index + b * 8 + lane];
                    const TriangleVerts& tv = tris[pos];
                    blk.set(int(lane), tv.v0, tv.v1, tv.v2, ids[pos]);
                }
            }
            n.children[c] = Child8{first, count};
        }
    }
    stats.nodes = nodes.size();
    stats.leaves = leaves;
    stats.blocks = blocks.size();
    stats.triangles = topo.prims.size();
    stats.depth = topo.depth;
    stats.bytes_per_triangle =
        stats.triangles ? double(nodes.size() * sizeof(Node8) + blocks.size() * sizeof(Tri8)) / double(stats.triangles)
                        : 0.0;
    stats.fill_rate = nodes.empty() ? 0.0 : double(used_slots) / (8.0 * double(nodes.size()));
    stats.block_fill = blocks.empty() ? 0.0 : double(stats.triangles) / (8.0 * double(blocks.size()));
}

}  // namespace simdbvh::bvh8
