// Step 2 of the BVH8 build: the wide topology packed into SoA Node8s (child
// boxes in Box8, empty slots +inf/-inf at the end, Embree-style) and leaves
// gathered into Tri8 blocks (empty lanes: NaN vertices, kInvalidPrim).
//
// Per Node8, the leaves of at most 8 triangles are bin-packed into shared
// blocks, first fit by decreasing size, a leaf never split across blocks (see
// Child8 in bvh8.h for why testing the siblings' triangles too is harmless).
// Larger leaves own their blocks. A node's blocks are contiguous, in slot
// order of their first leaf.
#include <algorithm>
#include <string>

#include "collapse.h"
#include "simdbvh/kernels/error.h"

namespace simdbvh::bvh8 {

namespace {

// First fit decreasing of a node's small leaves (<= 8 triangles) into bins of
// 8 lanes; bins numbered by their lowest slot.
struct NodePacking {
    int bins = 0;
    int bin_of[8], lane_of[8];       // per slot (small leaves only)
    std::uint32_t bin_slots[8] = {}; // slots per bin
};

bool is_small(const WideChild& c) { return c.is_leaf() && c.count <= 8; }

NodePacking pack_node(const WideNode& w) {
    NodePacking p;
    int order[8], small = 0;
    for (int c = 0; c < w.child_count; ++c)
        if (is_small(w.children[c])) order[small++] = c;
    std::stable_sort(order, order + small, [&](int a, int b) { return w.children[a].count > w.children[b].count; });
    int used[8], bin_of[8];
    std::uint32_t slots[8] = {};
    int bins = 0;
    for (int k = 0; k < small; ++k) {
        const int c = order[k];
        const int sz = int(w.children[c].count);
        int b = 0;
        while (b < bins && used[b] + sz > 8) ++b;
        if (b == bins) used[bins++] = 0;
        bin_of[c] = b;
        p.lane_of[c] = used[b];
        used[b] += sz;
        slots[b] |= 1u << c;
    }
    int rank[8];
    for (int c = 0; c < w.child_count; ++c)
        if (is_small(w.children[c]) && int(__builtin_ctz(slots[bin_of[c]])) == c) rank[bin_of[c]] = p.bins++;
    for (int c = 0; c < w.child_count; ++c)
        if (is_small(w.children[c])) p.bin_of[c] = rank[bin_of[c]];
    for (int b = 0; b < bins; ++b) p.bin_slots[rank[b]] = slots[b];
    return p;
}

}  // namespace

void pack(const Bvh2& bvh2, const WideTopology& topo, std::vector<Node8>& nodes, Tri8Blocks& blocks,
          Bvh8Stats& stats) {
    const auto& tris = bvh2.triangles();
    const auto& ids = bvh2.prim_ids();
    nodes.assign(topo.nodes.size(), Node8{});
    blocks.clear();
    std::size_t blocks_needed = 0, used_slots = 0, leaves = 0, shared = 0;
    for (const WideNode& w : topo.nodes) {
        blocks_needed += std::size_t(pack_node(w).bins);
        for (int c = 0; c < w.child_count; ++c)
            if (w.children[c].is_leaf() && !is_small(w.children[c])) blocks_needed += (w.children[c].count + 7u) / 8u;
    }
    blocks.reserve(blocks_needed);
    auto fill = [&](Tri8& blk, int lane0, const WideChild& wc, std::uint32_t from, std::uint32_t n) {
        for (std::uint32_t k = 0; k < n; ++k) {
            const std::uint32_t pos = topo.prims[wc.index + from + k];
            const TriangleVerts& tv = tris[pos];
            blk.set(lane0 + int(k), tv.v0, tv.v1, tv.v2, ids[pos]);
        }
    };
    for (std::size_t i = 0; i < topo.nodes.size(); ++i) {
        const WideNode& w = topo.nodes[i];
        Node8& n = nodes[i];
        n.boxes.clear();
        for (int c = 0; c < 8; ++c) n.children[c] = Child8{0, kInvalidPrim};
        const NodePacking p = pack_node(w);
        const std::uint32_t base = std::uint32_t(blocks.size());
        for (int b = 0; b < p.bins; ++b) {
            blocks.emplace_back().clear();
            if (__builtin_popcount(p.bin_slots[b]) > 1) ++shared;
        }
        for (int c = 0; c < w.child_count; ++c) {
            const WideChild& wc = w.children[c];
            n.boxes.set(c, wc.box);
            ++used_slots;
            if (!wc.is_leaf()) {
                n.children[c] = Child8{wc.index, 0};
                continue;
            }
            ++leaves;
            if (is_small(wc)) {
                const int b = p.bin_of[c];
                fill(blocks[base + std::uint32_t(b)], p.lane_of[c], wc, 0, wc.count);
                const std::uint32_t lanes = ((1u << wc.count) - 1u) << p.lane_of[c];
                const std::uint32_t sharing = __builtin_popcount(p.bin_slots[b]) > 1 ? p.bin_slots[b] : 0u;
                n.children[c] = Child8{base + std::uint32_t(b), 1u | (lanes << 16) | (sharing << 24)};
                continue;
            }
            const std::uint32_t first = std::uint32_t(blocks.size());
            const std::uint32_t count = (wc.count + 7u) / 8u;
            if (count > Child8::kMaxBlocks)
                throw Error("BVH8 leaf of " + std::to_string(wc.count) + " triangles exceeds " +
                            std::to_string(Child8::kMaxBlocks) + " Tri8 blocks");
            for (std::uint32_t b = 0; b < count; ++b) {
                Tri8& blk = blocks.emplace_back();
                blk.clear();
                fill(blk, 0, wc, b * 8, std::min(8u, wc.count - b * 8));
            }
            n.children[c] = Child8{first, count};
        }
    }
    stats.nodes = nodes.size();
    stats.leaves = leaves;
    stats.blocks = blocks.size();
    stats.shared_blocks = shared;
    stats.triangles = topo.prims.size();
    stats.depth = topo.depth;
    stats.bytes_per_triangle =
        stats.triangles ? double(nodes.size() * sizeof(Node8) + blocks.size() * sizeof(Tri8)) / double(stats.triangles)
                        : 0.0;
    stats.fill_rate = nodes.empty() ? 0.0 : double(used_slots) / (8.0 * double(nodes.size()));
    stats.block_fill = blocks.empty() ? 0.0 : double(stats.triangles) / (8.0 * double(blocks.size()));
}

}  // namespace simdbvh::bvh8
