// Step 2 of the wide BVH build: the N-wide topology packed into SoA NodeNs
// (child boxes in BoxN, empty slots +inf/-inf at the end, Embree-style) and
// leaves gathered into Tri8 blocks (empty lanes: NaN vertices, kInvalidPrim).
//
// Per node, the leaves of at most kBlockWidth triangles are bin-packed into
// shared blocks, first fit by decreasing size, a leaf never split across blocks
// (see ChildN in node.h for why testing the siblings' triangles too is harmless).
// Larger leaves own their blocks. A node's blocks are contiguous, in slot
// order of their first leaf.
#include <algorithm>
#include <string>

#include "collapse.h"
#include "simdbvh/kernels/error.h"

namespace simdbvh::bvh8 {

namespace {

constexpr std::uint32_t kLanes = kBlockWidth;

// First fit decreasing of a node's small leaves (<= kBlockWidth triangles) into
// bins of kBlockWidth lanes; bins numbered by their lowest slot.
template <int N>
struct NodePacking {
    int bins = 0;
    int bin_of[N], lane_of[N];       // per slot (small leaves only)
    std::uint32_t bin_slots[N] = {}; // slots per bin
};

bool is_small(const WideChild& c) { return c.is_leaf() && c.count <= kLanes; }

template <int N>
NodePacking<N> pack_node(const WideNode<N>& w) {
    NodePacking<N> p;
    int order[N], small = 0;
    for (int c = 0; c < w.child_count; ++c)
        if (is_small(w.children[c])) order[small++] = c;
    std::stable_sort(order, order + small, [&](int a, int b) { return w.children[a].count > w.children[b].count; });
    int used[N], bin_of[N];
    std::uint32_t slots[N] = {};
    int bins = 0;
    for (int k = 0; k < small; ++k) {
        const int c = order[k];
        const int sz = int(w.children[c].count);
        int b = 0;
        while (b < bins && used[b] + sz > int(kLanes)) ++b;
        if (b == bins) used[bins++] = 0;
        bin_of[c] = b;
        p.lane_of[c] = used[b];
        used[b] += sz;
        slots[b] |= 1u << c;
    }
    int rank[N] = {};
    for (int c = 0; c < w.child_count; ++c)
        if (is_small(w.children[c]) && int(__builtin_ctz(slots[bin_of[c]])) == c) rank[bin_of[c]] = p.bins++;
    for (int c = 0; c < w.child_count; ++c)
        if (is_small(w.children[c])) p.bin_of[c] = rank[bin_of[c]];
    for (int b = 0; b < bins; ++b) p.bin_slots[rank[b]] = slots[b];
    return p;
}

}  // namespace

template <int N>
void pack(const Bvh2& bvh2, const WideTopology<N>& topo, std::vector<NodeN<N>>& nodes, Tri8Blocks& blocks,
          WideStats& stats) {
    using Child = ChildN<N>;
    const auto& tris = bvh2.triangles();
    const auto& ids = bvh2.prim_ids();
    nodes.assign(topo.nodes.size(), NodeN<N>{});
    blocks.clear();
    std::size_t blocks_needed = 0, used_slots = 0, leaves = 0, shared = 0;
    for (const WideNode<N>& w : topo.nodes) {
        blocks_needed += std::size_t(pack_node(w).bins);
        for (int c = 0; c < w.child_count; ++c)
            if (w.children[c].is_leaf() && !is_small(w.children[c]))
                blocks_needed += (w.children[c].count + kLanes - 1u) / kLanes;
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
        const WideNode<N>& w = topo.nodes[i];
        NodeN<N>& n = nodes[i];
        n.boxes.clear();
        for (int c = 0; c < N; ++c) n.children[c] = Child::empty();
        const NodePacking<N> p = pack_node(w);
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
                n.children[c] = Child::inner(wc.index);
                continue;
            }
            ++leaves;
            if (is_small(wc)) {
                const int b = p.bin_of[c];
                fill(blocks[base + std::uint32_t(b)], p.lane_of[c], wc, 0, wc.count);
                const std::uint32_t lanes = ((1u << wc.count) - 1u) << p.lane_of[c];
                const std::uint32_t sharing = __builtin_popcount(p.bin_slots[b]) > 1 ? p.bin_slots[b] : 0u;
                n.children[c] = Child::small_leaf(base + std::uint32_t(b), lanes, sharing);
                continue;
            }
            const std::uint32_t first = std::uint32_t(blocks.size());
            const std::uint32_t count = (wc.count + kLanes - 1u) / kLanes;
            if (count > Child::kMaxBlocks)
                throw Error("BVH" + std::to_string(N) + " leaf of " + std::to_string(wc.count) + " triangles exceeds " +
                            std::to_string(Child::kMaxBlocks) + " Tri8 blocks");
            for (std::uint32_t b = 0; b < count; ++b) {
                Tri8& blk = blocks.emplace_back();
                blk.clear();
                fill(blk, 0, wc, b * kLanes, std::min(kLanes, wc.count - b * kLanes));
            }
            n.children[c] = Child::leaf(first, count);
        }
    }
    stats.nodes = nodes.size();
    stats.leaves = leaves;
    stats.blocks = blocks.size();
    stats.shared_blocks = shared;
    stats.triangles = topo.prims.size();
    stats.width = N;
    stats.depth = topo.depth;
    stats.bytes_per_triangle =
        stats.triangles
            ? double(nodes.size() * sizeof(NodeN<N>) + blocks.size() * sizeof(Tri8)) / double(stats.triangles)
            : 0.0;
    stats.fill_rate = nodes.empty() ? 0.0 : double(used_slots) / (double(N) * double(nodes.size()));
    stats.block_fill = blocks.empty() ? 0.0 : double(stats.triangles) / (double(kLanes) * double(blocks.size()));
}

template void pack<4>(const Bvh2&, const WideTopology<4>&, std::vector<Node4>&, Tri8Blocks&, WideStats&);
template void pack<8>(const Bvh2&, const WideTopology<8>&, std::vector<Node8>&, Tri8Blocks&, WideStats&);
template void pack<16>(const Bvh2&, const WideTopology<16>&, std::vector<Node16>&, Tri8Blocks&, WideStats&);

}  // namespace simdbvh::bvh8
