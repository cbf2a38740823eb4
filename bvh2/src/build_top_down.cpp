#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "build_common.h"
#include "simdbvh/platform/large_alloc.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh::detail {

namespace {

// Subtrees this large may be built by another thread. The layout does not
// depend on it: a subtree built apart is spliced exactly where the
// sequential recursion would have put it, so any thread count gives the same
// tree bit for bit.
constexpr std::uint32_t kTaskMin = 32 * 1024;

struct Builder {
    BuildContext& ctx;
    SplitFn split;
    std::uint32_t leaf_size;

    // Builds the subtree of ids[begin, end) with its root at nodes[0] (already
    // allocated). Children of a node are allocated as a pair at the end of
    // `nodes`, after the parent's whole left subtree is complete.
    void build(Nodes2& nodes, std::uint32_t at, std::uint32_t begin, std::uint32_t end, int depth,
               const Bounds& bounds) {
        const Aabb& box = bounds.box;
        const Aabb& cbox = bounds.cbox;
        nodes[at].box = box;
        const std::uint32_t n = end - begin;
        auto make_leaf = [&] {
            nodes[at].first = begin;
            nodes[at].count = n;
        };
        if (n <= std::uint32_t(std::max(1, ctx.opts.min_leaf_size)) || depth + 1 >= ctx.opts.max_depth)
            return make_leaf();
        SplitResult r = split(ctx, begin, end, box, cbox, depth);
        if (r.make_leaf) return make_leaf();
        if (!r.found || r.mid <= begin || r.mid >= end) {
            if (n <= leaf_size) return make_leaf();
            r.mid = begin + n / 2;  // object median: keeps order, always progresses
            r.has_bounds = false;
        }
        if (!r.has_bounds) {
            r.left = range_bounds(ctx, begin, r.mid);
            r.right = range_bounds(ctx, r.mid, end);
        }
        const std::uint32_t left = std::uint32_t(nodes.size());
        nodes[at].first = left;
        nodes[at].count = 0;
        nodes.resize(nodes.size() + 2);
        const std::uint32_t mid = r.mid;
        if (n >= kTaskMin && ctx.spare_threads.fetch_sub(1) > 0) {
            // The right subtree as a task of its own (run_tasks: the host
            // executor's, or a thread of ours), into its own array, spliced
            // after both sides are done. The task returns its thread when it
            // ends (not when the parent joins it), so a thread that finished
            // a small side of an uneven split picks up work in the larger side.
            Nodes2 right_nodes;
            right_nodes.reserve(2 * std::size_t(end - mid));  // address space only: no copies while it grows
            right_nodes.resize(1);
            run_tasks(2, [&](std::size_t k) {
                if (k == 0) return build(nodes, left, begin, mid, depth + 1, r.left);
                struct Release {
                    std::atomic<int>& n;
                    ~Release() { n.fetch_add(1); }
                } release{ctx.spare_threads};
                build(right_nodes, 0, mid, end, depth + 1, r.right);
            });
            splice(nodes, left + 1, right_nodes);
            return;
        }
        if (n >= kTaskMin) ctx.spare_threads.fetch_add(1);
        build(nodes, left, begin, mid, depth + 1, r.left);
        build(nodes, left + 1, mid, end, depth + 1, r.right);
    }

    // Puts sub[0] at nodes[at] and sub[1..] at the end of nodes.
    static void splice(Nodes2& nodes, std::uint32_t at, const Nodes2& sub) {
        const std::uint32_t offset = std::uint32_t(nodes.size()) - 1;
        auto fix = [&](Node2 n) {
            if (!n.is_leaf()) n.first += offset;
            return n;
        };
        nodes[at] = fix(sub[0]);
        for (std::size_t i = 1; i < sub.size(); ++i) nodes.push_back(fix(sub[i]));
    }
};

}  // namespace

Bounds range_bounds(const BuildContext& ctx, std::uint32_t begin, std::uint32_t end) {
    Bounds b;
    for (std::uint32_t i = begin; i < end; ++i) {
        const PrimRef& r = ctx.refs[i];
        b.box.grow(r.box());
        b.cbox.grow(r.c);
    }
    return b;
}

bool costs_fit_float(const Aabb& root, std::size_t prims, const BuildOptions& opts) {
    const double area = double(root.half_area_float());  // NaN or +inf when an extent or a product overflows
    const double factor = 1.0 + std::fabs(double(opts.traversal_cost)) + std::fabs(double(opts.intersection_cost));
    return std::isfinite(area) && area * double(prims) * factor < 1e37;  // FLT_MAX ~ 3.4e38
}

Bvh2Topology build_top_down(BuildContext& ctx, SplitFn split, std::uint32_t leaf_size) {
    return build_top_down(ctx, split, leaf_size, range_bounds(ctx, 0, std::uint32_t(ctx.refs.size())));
}

Bvh2Topology build_top_down(BuildContext& ctx, SplitFn split, std::uint32_t leaf_size, const Bounds& root) {
    Bvh2Topology topo;
    if (ctx.refs.empty()) return topo;
    ctx.spare_threads = std::max(0, ctx.opts.threads - 1);
    topo.nodes.reserve(2 * ctx.refs.size());
    topo.nodes.resize(1);
    Builder b{ctx, split, std::max<std::uint32_t>(1, leaf_size)};
    const auto n = std::uint32_t(ctx.refs.size());
    ctx.float_costs = costs_fit_float(root.box, n, ctx.opts);
    b.build(topo.nodes, 0, 0, n, 0, root);
    topo.prim_ids.resize(ctx.refs.size());
    ParallelOptions po;
    po.grain = 64 * 1024;
    po.pin = false;
    parallel_for(
        ctx.refs.size(), ctx.opts.threads,
        [&](std::size_t b0, std::size_t e0) {
            for (std::size_t i = b0; i < e0; ++i) topo.prim_ids[i] = ctx.refs[i].id;
        },
        po);
    return topo;
}

}  // namespace simdbvh::detail
