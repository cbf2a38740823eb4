// Binned SAH builder (Wald 2007, "On fast Construction of SAH-based Bounding
// Volume Hierarchies"), with SAH leaf-cost termination and a depth cap.
#include "build_common.h"

#include <algorithm>
#include <cmath>

namespace simdbvh::detail {

namespace {

struct Bin {
    Aabb box;
    std::uint32_t count = 0;
};

struct Split {
    int axis = -1;
    int bin = 0;  // primitives with bin index < bin go left
    float cost = 0;
};

}  // namespace

SplitResult split_binned_sah(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Aabb& node_box,
                             const Aabb& centroid_box, int /*depth*/) {
    const int nbins = std::clamp(ctx.opts.bins, 2, 256);
    const std::uint32_t n = end - begin;
    const float leaf_cost = ctx.opts.intersection_cost * float(n);
    const float parent_area = node_box.half_area();
    Split best;
    best.cost = std::numeric_limits<float>::infinity();
    Bin bins[256];
    float right_area[256];
    std::uint32_t right_count[256];
    for (int axis = 0; axis < 3; ++axis) {
        const float cmin = centroid_box.lo[axis], cmax = centroid_box.hi[axis];
        const float extent = cmax - cmin;
        if (!(extent > 0.0f)) continue;
        const float scale = float(nbins) / extent;
        if (!std::isfinite(scale)) continue;
        for (int b = 0; b < nbins; ++b) bins[b] = Bin{};
        for (std::uint32_t i = begin; i < end; ++i) {
            const std::uint32_t p = ctx.ids[i];
            const int b = std::min(nbins - 1, int((ctx.centroids[p][axis] - cmin) * scale));
            bins[b].box.grow(ctx.boxes[p]);
            bins[b].count++;
        }
        Aabb acc;
        std::uint32_t cnt = 0;
        for (int b = nbins - 1; b > 0; --b) {
            acc.grow(bins[b].box);
            cnt += bins[b].count;
            right_area[b] = acc.half_area();
            right_count[b] = cnt;
        }
        acc = Aabb{};
        cnt = 0;
        for (int b = 1; b < nbins; ++b) {
            acc.grow(bins[b - 1].box);
            cnt += bins[b - 1].count;
            if (cnt == 0 || right_count[b] == 0) continue;
            const float cost = ctx.opts.traversal_cost +
                               ctx.opts.intersection_cost *
                                   (acc.half_area() * float(cnt) + right_area[b] * float(right_count[b])) / parent_area;
            if (cost < best.cost) best = {axis, b, cost};
        }
    }
    SplitResult r;
    if (best.axis < 0) return r;  // no usable split: caller falls back
    r.make_leaf = best.cost >= leaf_cost && n <= std::uint32_t(ctx.opts.max_leaf_size);
    if (r.make_leaf) return r;
    const int axis = best.axis;
    const float cmin = centroid_box.lo[axis];
    const float scale = float(nbins) / (centroid_box.hi[axis] - cmin);
    std::uint32_t* first = ctx.ids.data() + begin;
    std::uint32_t* mid = std::partition(first, ctx.ids.data() + end, [&](std::uint32_t p) {
        return std::min(nbins - 1, int((ctx.centroids[p][axis] - cmin) * scale)) < best.bin;
    });
    r.mid = begin + std::uint32_t(mid - first);
    r.found = true;
    return r;
}

}  // namespace simdbvh::detail
