// BvhN<N>::build: collapse (collapse.cpp) then pack (pack.cpp), N = 4, 8, 16.
#include <chrono>

#include "simdbvh/bvh8/internal/collapse.h"
#include "simdbvh/bvh8/internal/quantize.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/platform/build_threads.h"

namespace simdbvh {

std::string_view name(Collapse c) {
    switch (c) {
    case Collapse::sah: return "sah";
    case Collapse::greedy: return "greedy";
    }
    return "?";
}

std::optional<Collapse> parse_collapse(std::string_view s) {
    for (Collapse c : {Collapse::sah, Collapse::greedy})
        if (s == name(c)) return c;
    return std::nullopt;
}

template <int N>
void check_quantized(const WideOptions& opts) {
    if (N == 4 && opts.quantized_nodes)
        throw Error("BVH4 has no quantized nodes (a QNode4 would take the 128 bytes of a Node4): use BVH8 or BVH16");
}

namespace {
// The options a build of `prims` triangles runs with: the threads worth
// starting for that size (build_threads.h); b.opts_ keeps the caller's.
WideOptions sized_for(const WideOptions& opts, std::size_t prims) {
    WideOptions run = opts;
    run.threads = build_threads(opts.threads, prims);
    return run;
}
}  // namespace

struct WideAccess {
    template <int N>
    static BvhN<N> build(const Bvh2& bvh2, const WideOptions& opts) {
        check_quantized<N>(opts);
        const auto t0 = std::chrono::steady_clock::now();
        const LargeAllocReuse reuse;  // the collapse's tables become the blocks' pages (large_alloc.h)
        const WideOptions run = sized_for(opts, bvh2.prim_ids().size());
        const bvh8::WideTopology<N> topo = bvh8::collapse<N>(bvh2, run);
        BvhN<N> b;
        {
            const LargeAllocTake take;  // pack writes every array it allocates
            bvh8::pack<N>(bvh2, topo, b.nodes_, b.blocks_, b.stats_, run.threads);
        }
        b.stats_.sah_cost = bvh8::sah_cost(topo, opts);
        b.bounds_ = bvh2.bounds();
        b.opts_ = opts;
        b.quantize();
        b.stats_.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        return b;
    }

    // The same tree as from Bvh2::build(mesh), without the BVH2's gathered
    // triangles and statistics: the topology is collapsed and packed from the mesh.
    template <int N>
    static BvhN<N> build(const Mesh& mesh, const BuildOptions& bvh2_opts, const WideOptions& opts) {
        validate(mesh);
        check_quantized<N>(opts);
        BuildOptions b2 = bvh2_opts;
        b2.intersection_cost = opts.bvh2_intersection_cost;
        // The BVH2's references and nodes and the collapse's tables, freed
        // on the way, become the wide nodes' and Tri8 blocks' pages
        // (large_alloc.h): the kernel clears no fresh page for them.
        const LargeAllocReuse reuse;
        Bvh2Topology topo2 = build_topology(mesh, b2);
        const auto t0 = std::chrono::steady_clock::now();  // build_ms: collapse + pack, as from a Bvh2
        const WideOptions run = sized_for(opts, topo2.prim_ids.size());
        const bvh8::WideTopology<N> topo = bvh8::collapse<N>(topo2.nodes, topo2.prim_ids.size(), run);
        BvhN<N> b;
        b.bounds_ = topo2.nodes.empty() ? Aabb{} : topo2.nodes[0].box;
        Nodes2().swap(topo2.nodes);  // not needed by pack: kept for its arrays
        {
            const LargeAllocTake take;  // pack writes every array it allocates
            bvh8::pack<N>(mesh, topo2.prim_ids, topo, b.nodes_, b.blocks_, b.stats_, run.threads);
        }
        b.stats_.sah_cost = bvh8::sah_cost(topo, opts);
        b.opts_ = opts;
        b.quantize();
        b.stats_.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        return b;
    }
};

template <int N>
void BvhN<N>::quantize() {
    std::vector<QNode>().swap(qnodes_);
    if (!opts_.quantized_nodes) return;
    qnodes_ = bvh8::quantize<N>(nodes_, opts_.threads);
    if (stats_.triangles)
        stats_.bytes_per_triangle += double(qnodes_.size() * sizeof(QNode)) / double(stats_.triangles);
}

template <int N>
BvhN<N> BvhN<N>::build(const Bvh2& bvh2, const WideOptions& opts) {
    return WideAccess::build<N>(bvh2, opts);
}

template <int N>
BvhN<N> BvhN<N>::build(const Mesh& mesh, const BuildOptions& bvh2_opts, const WideOptions& opts) {
    return WideAccess::build<N>(mesh, bvh2_opts, opts);
}

template class BvhN<4>;
template class BvhN<8>;
template class BvhN<16>;

}  // namespace simdbvh
