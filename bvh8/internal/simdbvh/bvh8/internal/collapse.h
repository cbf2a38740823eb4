#pragma once
// Internal: step 1 of the wide BVH build, the N-wide topology collapsed from a
// BVH2 (Ylitie, Karras, Laine 2017, section 4), before packing into NodeN/Tri8
// (pack.cpp). Plain structs so tests can check collapse and pack separately.
// Instantiated for N = 4, 8, 16.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/platform/large_alloc.h"

namespace simdbvh::bvh8 {

struct WideChild {
    Aabb box;
    std::uint32_t index = 0;  // inner: WideTopology::nodes index; leaf: its first position in the BVH2 leaf order
    std::uint32_t count = 0;  // 0 = inner; leaf: number of triangles
    bool is_leaf() const { return count != 0; }
};

template <int N>
struct WideNode {
    Aabb box;
    int child_count = 0;  // 1..N (1 only for a root over a single leaf)
    std::array<WideChild, N> children;
};

template <int N>
struct WideTopology {
    LargeVector<WideNode<N>> nodes;  // root at 0; a node's inner children are allocated together
    // Triangles in the leaves. A leaf's are the positions [index, index + count)
    // in the BVH2 leaf order (Bvh2::prim_ids()): a BVH2 subtree's leaves are
    // contiguous there, as every builder partitions its references in place.
    std::size_t prims = 0;
    int depth = 0;  // node levels (root = 1); leaves are not nodes
};

// Collapses the BVH2 into at most N children per node. Leaves hold at most
// opts.max_leaf_size triangles, except BVH2 leaves that are already larger
// (kept whole). Throws simdbvh::Error when the result is deeper than kMaxDepth.
template <int N>
WideTopology<N> collapse(const Bvh2& bvh2, const WideOptions& opts);
// The same over a BVH2's nodes and the number of triangles in its leaves.
template <int N>
WideTopology<N> collapse(std::span<const Node2> nodes, std::size_t prims, const WideOptions& opts);

// SAH cost of a wide topology with the WideOptions cost model: sum over nodes
// of node_cost * A(n)/A(root) + over leaves of block_cost * ceil(n/kBlockWidth) * A(leaf)/A(root).
template <int N>
double sah_cost(const WideTopology<N>& topo, const WideOptions& opts);

// Step 2: packs the topology into NodeN / Tri8 blocks and fills the stats
// (all but build_ms and sah_cost). Nodes are packed on `threads` threads
// (each node's blocks are placed first, so the result does not depend on it).
template <int N>
void pack(const Bvh2& bvh2, const WideTopology<N>& topo, NodesN<N>& nodes, Tri8Blocks& blocks, WideStats& stats,
          int threads = 1);
// The same from the mesh and the BVH2's leaf order (prim_ids), for a BVH2
// that never gathered its triangles (BvhN::build(mesh)).
// Whether pack(mesh) scatters the mesh's triangles to their lanes (in mesh
// order) rather than gathering them in leaf order: for leaf orders that jump
// across the mesh (pack.cpp).
bool scatter_pays(std::span<const std::uint32_t> prim_ids, std::size_t triangles);

template <int N>
void pack(const Mesh& mesh, std::span<const std::uint32_t> prim_ids, const WideTopology<N>& topo, NodesN<N>& nodes,
          Tri8Blocks& blocks, WideStats& stats, int threads = 1);

}  // namespace simdbvh::bvh8
