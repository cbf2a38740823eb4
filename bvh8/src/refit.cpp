// BvhN<N>::refit (N = 4, 8, 16): new vertex positions, the same topology and
// block packing. Blocks are re-gathered and leaf slots re-bounded in
// parallel; inner slots are then bounded in reverse node order (the collapse
// allocates a node's inner children after it).
#include <atomic>
#include <cmath>
#include <string>

#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/platform/parallel.h"
#include "simdbvh/bvh8/internal/quantize.h"
#include "simdbvh/bvh8/internal/tri8_lanes-inl.h"

namespace simdbvh {

namespace {

template <int N>
Aabb union_of_slots(const NodeN<N>& n) {
    Aabb b;
    for (int c = 0; c < N; ++c) b.grow(n.boxes.get(c));  // empty slots are +inf/-inf: no effect
    return b;
}

void grow_lanes(Aabb& b, const Tri8& t, std::uint32_t lanes) {
    for (; lanes; lanes &= lanes - 1) {
        const int k = __builtin_ctz(lanes);
        b.grow(t.v0(k));
        b.grow(t.v1(k));
        b.grow(t.v2(k));
    }
}

template <int N>
Aabb leaf_box(const ChildN<N>& c, const Tri8Blocks& blocks) {
    Aabb b;
    if (c.own_lanes() != 0) {
        grow_lanes(b, blocks[c.index], c.own_lanes());
    } else {
        for (std::uint32_t k = 0; k < c.blocks(); ++k)
            grow_lanes(b, blocks[c.index + k], detail::used_lanes(blocks[c.index + k]));
    }
    return b;
}

// The collapse's cost (collapse.h sah_cost), summed in the same node order
// from the packed nodes, so an unchanged mesh gives the same number.
template <int N>
double wide_sah(const NodesN<N>& nodes, const Aabb& root_box, const WideOptions& opts) {
    if (nodes.empty()) return 0.0;
    const bool fa = std::isfinite(root_box.half_area_float());
    auto area = [&](const Aabb& b) { return fa ? double(b.half_area_float()) : b.half_area(); };
    double root = area(root_box);
    const bool flat = !(root > 0);
    if (flat) root = 1.0;
    double cost = 0;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const NodeN<N>& n = nodes[i];
        cost += double(opts.node_cost) * (flat ? 1.0 : area(i == 0 ? root_box : union_of_slots(n))) / root;
        for (int c = 0; c < N; ++c) {
            const ChildN<N>& ch = n.children[c];
            if (!ch.is_leaf()) continue;
            const double blocks = ch.own_lanes() != 0 ? 1.0 : double(ch.blocks());
            cost += double(opts.block_cost) * blocks * (flat ? 1.0 : area(n.boxes.get(c))) / root;
        }
    }
    return cost;
}

}  // namespace

template <int N>
void BvhN<N>::refit(const Mesh& mesh, int threads) {
    const std::string what = "BVH" + std::to_string(N) + " refit: ";
    if (mesh.size() != stats_.triangles)
        throw Error(what + "the mesh has " + std::to_string(mesh.size()) + " triangles, the tree " +
                    std::to_string(stats_.triangles));
    validate(mesh);
    // Every check before the first write: on error the tree is unchanged.
    const std::size_t n = nodes_.size();
    for (std::size_t i = 0; i < n; ++i) {
        for (int c = 0; c < N; ++c) {
            const Child& ch = nodes_[i].children[c];
            const bool ok = ch.is_empty() || (ch.is_inner() ? ch.index > i && ch.index < n
                                                            : std::size_t(ch.index) + ch.blocks() <= blocks_.size());
            if (!ok) throw Error(what + "node " + std::to_string(i) + " is not in collapse order");
        }
    }
    // Every id in the blocks is below stats_.triangles == mesh.size() (the build put them there): no check per lane.

    ParallelOptions po;
    po.pin = false;
    po.grain = 1024;
    parallel_for(
        blocks_.size(), threads,
        [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
                Tri8& t = blocks_[i];
                for (int k = 0; k < kBlockWidth; ++k)
                    if (t.prim[k] != kInvalidPrim)
                        t.set(k, mesh.vertex(t.prim[k], 0), mesh.vertex(t.prim[k], 1), mesh.vertex(t.prim[k], 2),
                              t.prim[k]);
            }
        },
        po);
    po.grain = 256;
    parallel_for(
        n, threads,
        [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i)
                for (int c = 0; c < N; ++c)
                    if (nodes_[i].children[c].is_leaf())
                        nodes_[i].boxes.set(c, leaf_box(nodes_[i].children[c], blocks_));
        },
        po);
    for (std::size_t i = n; i-- > 0;) {
        Node& nd = nodes_[i];
        for (int c = 0; c < N; ++c)
            if (nd.children[c].is_inner()) nd.boxes.set(c, union_of_slots(nodes_[nd.children[c].index]));
    }
    bounds_ = n ? union_of_slots(nodes_[0]) : Aabb{};
    stats_.sah_cost = wide_sah(nodes_, bounds_, opts_);
    if (!qnodes_.empty()) {  // requantized in place: the same node count, so no allocation
        std::atomic<bool> ok{true};
        parallel_for(
            n, threads,
            [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i)
                    if (!bvh8::quantize_box<N>(nodes_[i].boxes, nodes_[i].children, qnodes_[i].boxes)) ok.store(false);
            },
            po);
        if (!ok.load()) std::vector<QNode>().swap(qnodes_);  // an extent no grid spans: traversal reads the full nodes
    }
}

template void BvhN<4>::refit(const Mesh&, int);
template void BvhN<8>::refit(const Mesh&, int);
template void BvhN<16>::refit(const Mesh&, int);

}  // namespace simdbvh
