#pragma once
// Wide BVHs (N = 4, 8, 16 children per node; Bvh8 = BvhN<8>): the BVH2
// collapsed by SAH cost (Ylitie, Karras, Laine 2017), packed into SoA nodes
// whose N child boxes are tested in one SIMD operation, with triangles
// pre-gathered into SoA blocks of kBlockWidth (8), whatever N.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/node.h"
#include "simdbvh/bvh8/qnode.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/kernels/soa.h"

namespace simdbvh {

enum class Collapse : std::uint8_t {
    sah,     // Ylitie et al. 2017 section 4 dynamic program (default)
    greedy,  // adopt the child with the largest surface area until N children
};
std::string_view name(Collapse c);
std::optional<Collapse> parse_collapse(std::string_view s);

// The SAH intersection cost of the BVH2 topology a wide build from a mesh
// starts from (WideOptions::bvh2_intersection_cost). A Tri8 block tests up
// to 8 triangles in one SIMD operation, so a triangle costs far less than the
// BVH2's 1.0 per triangle (one box test); at 0.3 the BVH2 stops splitting
// small ranges that the collapse would put into one block anyway. On the
// dragon: 27% faster build, BVH8 SAH +0.16%, Mrays/s within the noise.
inline constexpr float kWideIntersectionCost = 0.3f;

// Collapse options, the same for every width.
struct WideOptions {
    Collapse collapse = Collapse::sah;
    int max_leaf_size = 8;  // triangles per leaf (one or more Tri8 blocks; small leaves share blocks)
    // Collapse cost model (Ylitie 2017 section 4 adapted to Tri8 blocks): a
    // node visit (one N-wide box test) costs node_cost, a leaf costs
    // block_cost per Tri8 block, i.e. block_cost * ceil(n / kBlockWidth) for n triangles.
    float node_cost = 1.0f;
    float block_cost = 1.0f;
    int threads = 1;  // collapse + pack threads (one below 32,768 triangles); the tree is identical for every count
    // BvhN::build(mesh, bvh2_opts, opts) builds its BVH2 topology with this
    // intersection cost in place of bvh2_opts.intersection_cost.
    float bvh2_intersection_cost = kWideIntersectionCost;
    // Also keep the nodes quantized (qnode.h: 8-bit child boxes, half the
    // bytes per node), which traversal then reads instead of the full nodes
    // (kept for refit, the point queries and the scenes). Same hits. N = 8, 16
    // only: a BVH4 with it is an Error (QNode4 would be as large as Node4, 128
    // bytes, so its traversal is not compiled).
    bool quantized_nodes = false;
};

struct WideStats {
    double build_ms = 0;  // collapse + pack (add the BVH2's build_ms for the total)
    std::size_t nodes = 0, leaves = 0, blocks = 0, triangles = 0;
    std::size_t shared_blocks = 0;  // blocks holding the triangles of more than one leaf
    int width = 0;                  // N: child slots per node
    int depth = 0;
    double sah_cost = 0;            // sum of cost * A(n)/A(root) (as the BVH2), node_cost / block_cost model
    double bytes_per_triangle = 0;  // nodes (and quantized nodes) + triangle blocks
    double fill_rate = 0;           // used child slots / (N * nodes)
    double block_fill = 0;          // used triangle lanes: triangles / (kBlockWidth * blocks)
};

// N-wide BVH (N = 4, 8, 16), all from the same BVH2 and the same collapse.
template <int N>
class BvhN {
    static_assert(kValidWidth<N>, "node widths: 4, 8, 16");

public:
    static constexpr int kWidth = N;
    using Node = NodeN<N>;
    using Child = ChildN<N>;
    using QNode = QNodeN<N>;

    BvhN() = default;
    static BvhN build(const Bvh2& bvh2, const WideOptions& opts = {});
    // From a mesh: the BVH2 topology (bvh2_opts, with
    // opts.bvh2_intersection_cost), collapsed and packed; the BVH2 itself is
    // not kept.
    static BvhN build(const Mesh& mesh, const BuildOptions& bvh2_opts = {}, const WideOptions& opts = {});

    // Refit for a moved mesh (the same triangles, new vertex positions): the
    // Tri8 blocks are re-gathered and every child box recomputed bottom-up,
    // in place, with the topology, the block packing and the ids kept (no
    // allocation). Leaves on `threads` threads, then one pass over the inner
    // nodes. stats().sah_cost is recomputed. Hits afterwards are bit-identical
    // to brute force on the moved mesh; a refit with the build's own mesh
    // reproduces the tree byte for byte. Another triangle count, an index out
    // of range or a non-finite vertex throws simdbvh::Error, tree unchanged.
    void refit(const Mesh& mesh, int threads = 1);

    const NodesN<N>& nodes() const { return nodes_; }
    const Tri8Blocks& blocks() const { return blocks_; }
    // The quantized nodes (WideOptions::quantized_nodes; else empty), one per node.
    const std::vector<QNode>& qnodes() const { return qnodes_; }
    const WideOptions& options() const { return opts_; }
    const WideStats& stats() const { return stats_; }
    Aabb bounds() const { return bounds_; }

private:
    friend struct WideAccess;
    friend struct StoreAccess;
    void quantize();   // qnodes_ from nodes_ when opts_.quantized_nodes (build.cpp)
    NodesN<N> nodes_;  // root at 0 (when the mesh is not empty)
    Tri8Blocks blocks_;
    std::vector<QNode> qnodes_;
    WideStats stats_;
    Aabb bounds_;
    WideOptions opts_;
};
extern template class BvhN<4>;
extern template class BvhN<8>;
extern template class BvhN<16>;
using Bvh4 = BvhN<4>;
using Bvh8 = BvhN<8>;
using Bvh16 = BvhN<16>;
// Any one of the wide trees, or none.
using AnyWideBvh = std::variant<std::monostate, Bvh4, Bvh8, Bvh16>;

// The one width ladder: f(std::integral_constant<int, N>{}) for N = width, one of 4, 8, 16 (tree_width in
// cost_model.h); throws simdbvh::Error for any other width.
template <class F>
decltype(auto) with_width(int width, F&& f) {
    switch (width) {
    case 4: return f(std::integral_constant<int, 4>{});
    case 8: return f(std::integral_constant<int, 8>{});
    case 16: return f(std::integral_constant<int, 16>{});
    default: throw Error("no wide tree of width " + std::to_string(width) + " (4, 8 or 16)");
    }
}

// Closest hit and any hit, bit-identical to the BVH2 (same kernels, same tie
// rule) on every ISA. TraceOptions::stats: nodes_visited counts wide nodes;
// box_tests and triangle_tests count lanes (N per node test, kBlockWidth per
// Tri8 block). Defined for N = 4, 8, 16.
//
// With TraceOptions::isa set: that ISA's code runs (one kernel set per batch;
// an unsupported isa throws simdbvh::Error). Unset, it is chosen by speed: the forced
// one when SIMDBVH_ISA or set_active_isa() sets it (forced_isa()); otherwise,
// once per process and per (width, query), the first batch of at least
// kIsaCalibrationRays rays times every SIMD ISA the CPU has on its own rays:
// small groups spread over the batch, each traced with the widest ISA (its
// hits: the results are those of any path), then again with every ISA,
// timed, the tree's nodes for those rays in the cache (where the ISAs
// differ); at most 1/64 of the batch is traced again (320 rays below 36,864).
// It keeps the widest ISA unless another one's median time ratio to it is
// below 0.97 and that one is faster in all but an eighth of the comparisons;
// before that, the best detected ISA. traversal_isa_choice() reports it.
template <int N>
void intersect(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts = {});
template <int N>
void occluded(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts = {});
template <int N>
Hit intersect(const BvhN<N>& bvh, const Ray& ray, const TraceOptions& opts = {});
template <int N>
Hit occluded(const BvhN<N>& bvh, const Ray& ray, const TraceOptions& opts = {});

// Batches smaller than this never calibrate (they use the current choice).
inline constexpr std::size_t kIsaCalibrationRays = 8192;

// The ISA a trace without TraceOptions::isa uses now for this width (4, 8, 16) and
// query, and why. ns_per_ray[int(isa)]: the calibration's median time per
// ray and ISA, on rays whose nodes are in the cache (less than a batch's own
// time per ray; 0 for an ISA not measured).
struct TraversalIsaChoice {
    Isa isa = Isa::scalar;
    bool forced = false;      // SIMDBVH_ISA or set_active_isa()
    bool calibrated = false;  // chosen by the calibration (else: the best detected, not yet calibrated)
    double ns_per_ray[3] = {0, 0, 0};
    std::size_t rays_timed = 0;  // rays timed per ISA
};
TraversalIsaChoice traversal_isa_choice(int width, bool any_hit);

}  // namespace simdbvh
