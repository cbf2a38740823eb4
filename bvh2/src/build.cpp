#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <string>

#include "build_common.h"
#include "tree_shape.h"
#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/platform/build_threads.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh {

std::string_view name(Builder b) {
    switch (b) {
    case Builder::sah_binned: return "sah-binned";
    case Builder::sah_sweep: return "sah-sweep";
    case Builder::midpoint: return "midpoint";
    case Builder::median: return "median";
    case Builder::variance: return "variance";
    }
    return "?";
}

std::optional<Builder> parse_builder(std::string_view s) {
    for (Builder b : {Builder::sah_binned, Builder::sah_sweep, Builder::midpoint, Builder::median, Builder::variance})
        if (s == name(b)) return b;
    if (s == "sah") return Builder::sah_binned;
    return std::nullopt;
}

namespace {

void check_options(const BuildOptions& opts) {
    if (opts.max_depth < 1 || opts.max_depth > kMaxDepth)
        throw Error("max_depth " + std::to_string(opts.max_depth) + " outside 1.." + std::to_string(kMaxDepth));
    if (opts.max_leaf_size < 1) throw Error("max_leaf_size must be at least 1");
}

// Builds over ctx.refs (filled by the caller) with the chosen split rule; the
// root's bounds when the caller has them.
Bvh2Topology build_refs(detail::BuildContext& ctx, const detail::Bounds* root = nullptr) {
    const BuildOptions& opts = ctx.opts;
    auto top_down = [&](detail::SplitFn split, std::uint32_t leaf_size) {
        return root ? detail::build_top_down(ctx, split, leaf_size, *root)
                    : detail::build_top_down(ctx, split, leaf_size);
    };
    switch (opts.builder) {
    case Builder::sah_binned: return top_down(detail::split_binned_sah, std::uint32_t(opts.max_leaf_size));
    case Builder::sah_sweep: return top_down(detail::split_sweep_sah, std::uint32_t(opts.max_leaf_size));
    case Builder::midpoint: return top_down(detail::split_midpoint, 4);
    case Builder::median: return top_down(detail::split_median, 1);
    case Builder::variance: return top_down(detail::split_variance, std::uint32_t(opts.max_leaf_size));
    }
    throw Error("unknown builder");
}

// Build passes over every primitive run on the build threads, never pinned
// (the host decides where its threads run).
ParallelOptions build_parallel() {
    ParallelOptions p;
    p.grain = 64 * 1024;
    p.pin = false;
    return p;
}

}  // namespace

Bvh2Topology build_topology(std::span<const Aabb> boxes, std::span<const Vec3> centroids, const BuildOptions& opts) {
    if (boxes.size() != centroids.size()) throw Error("build_topology: boxes and centroids differ in size");
    check_options(opts);
    detail::BuildContext ctx;
    ctx.opts = opts;
    ctx.opts.threads = build_threads(opts.threads, boxes.size());
    ctx.refs.reserve(boxes.size());
    for (std::size_t i = 0; i < boxes.size(); ++i)
        if (!boxes[i].is_empty())
            ctx.refs.push_back({boxes[i].lo, std::uint32_t(i), boxes[i].hi, 0.0f, centroids[i], 0.0f});
    return build_refs(ctx);
}

// The same references as boxes and centroids from the mesh would give (box of
// the three vertices, centroid = box centre), written directly: no
// intermediate arrays, one pass, on the build threads. The pass also bounds
// fixed blocks of references, merged in block order: the root's bounds, bit
// for bit those of one pass over all of them, for any thread count.
Bvh2Topology build_topology(const Mesh& mesh, const BuildOptions& opts) {
    check_options(opts);
    const std::size_t n = mesh.triangles.size();
    constexpr std::size_t kBlock = 64 * 1024;
    const std::size_t nblocks = (n + kBlock - 1) / kBlock;
    detail::BuildContext ctx;
    ctx.opts = opts;
    ctx.opts.threads = build_threads(opts.threads, n);
    ctx.refs.resize(n);
    std::vector<detail::Bounds> block_bounds(nblocks);
    std::atomic<bool> any_empty{false};
    ParallelOptions po = build_parallel();
    po.grain = 1;
    parallel_for(
        nblocks, ctx.opts.threads,
        [&](std::size_t b0, std::size_t e0) {
            bool empty = false;
            for (std::size_t blk = b0; blk < e0; ++blk) {
                detail::Bounds bb;
                for (std::size_t i = blk * kBlock, e = std::min(n, i + kBlock); i < e; ++i) {
                    Aabb box;
                    for (int k = 0; k < 3; ++k) box.grow(mesh.vertex(i, k));
                    empty |= box.is_empty();
                    const Vec3 c = box.center();
                    ctx.refs[i] = {box.lo, std::uint32_t(i), box.hi, 0.0f, c, 0.0f};
                    bb.box.grow(box);
                    bb.cbox.grow(c);
                }
                block_bounds[blk] = bb;
            }
            if (empty) any_empty = true;
        },
        po);
    if (any_empty) {  // primitives with an empty box are left out (they can never be hit)
        std::erase_if(ctx.refs, [](const detail::PrimRef& r) { return r.box().is_empty(); });
        return build_refs(ctx);
    }
    detail::Bounds root;
    for (const detail::Bounds& bb : block_bounds) detail::grow(root, bb);
    return build_refs(ctx, &root);
}

double sah_cost(std::span<const Node2> nodes, std::size_t prims, float ct, float ci) {
    if (nodes.empty()) return 0.0;
    // The areas the builders use: float while the root's float area is
    // finite (the same numbers as ever), else double (finite for any finite mesh).
    const bool fa = std::isfinite(nodes[0].box.half_area_float());
    auto area = [&](const Aabb& b) { return fa ? double(b.half_area_float()) : b.half_area(); };
    const double root = area(nodes[0].box);
    if (!(root > 0)) return ci * double(prims);
    double cost = 0;
    for (const Node2& n : nodes) cost += (n.is_leaf() ? ci * double(n.count) : ct) * area(n.box) / root;
    return cost;
}

double sah_cost(const Bvh2Topology& topo, float ct, float ci) {
    return sah_cost(topo.nodes, topo.prim_ids.size(), ct, ci);
}

Bvh2 Bvh2::build(const Mesh& mesh, const BuildOptions& opts) {
    const auto t0 = std::chrono::steady_clock::now();
    validate(mesh);
    const std::size_t n = mesh.triangles.size();
    Bvh2Topology topo = build_topology(mesh, opts);
    Bvh2 bvh;
    bvh.opts_ = opts;
    bvh.tris_.resize(topo.prim_ids.size());
    const int threads = build_threads(opts.threads, topo.prim_ids.size());
    parallel_for(
        topo.prim_ids.size(), threads,
        [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) {
                const std::uint32_t p = topo.prim_ids[i];
                bvh.tris_[i] = {mesh.vertex(p, 0), mesh.vertex(p, 1), mesh.vertex(p, 2)};
            }
        },
        build_parallel());
    const auto t1 = std::chrono::steady_clock::now();
    BuildStats& s = bvh.stats_;
    s.build_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    s.nodes = topo.nodes.size();
    s.triangles = n;
    s.sah_cost = sah_cost(topo, opts.traversal_cost, opts.intersection_cost);
    const detail::TreeShape shape = detail::tree_shape(topo.nodes);
    s.depth = shape.depth;
    s.leaves = shape.leaves;
    s.bytes_per_triangle = n ? double(topo.nodes.size() * sizeof(Node2) +
                                      topo.prim_ids.size() * (sizeof(std::uint32_t) + sizeof(TriangleVerts))) /
                                   double(n)
                             : 0.0;
    bvh.nodes_ = std::move(topo.nodes);
    bvh.prim_ids_ = std::move(topo.prim_ids);
    return bvh;
}

}  // namespace simdbvh
