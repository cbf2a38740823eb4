// Full-sweep SAH: every split position between centroid-sorted primitives on
// each axis (MacDonald and Booth 1990): the quality reference for binning.
#include <algorithm>
#include <limits>

#include "build_common.h"

namespace simdbvh::detail {

SplitResult split_sweep_sah(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Aabb& node_box,
                            const Aabb&, int) {
    const std::uint32_t n = end - begin;
    const float parent_area = node_box.half_area();
    std::vector<PrimRef> sorted[3];
    std::vector<float> right_area(n);
    float best_cost = std::numeric_limits<float>::infinity();
    int best_axis = -1;
    std::uint32_t best_i = 0;
    for (int axis = 0; axis < 3; ++axis) {
        sorted[axis].assign(ctx.refs.begin() + begin, ctx.refs.begin() + end);
        std::sort(sorted[axis].begin(), sorted[axis].end(), [&](const PrimRef& a, const PrimRef& b) {
            const float ca = a.c[axis], cb = b.c[axis];
            return ca < cb || (ca == cb && a.id < b.id);
        });
        Aabb acc;
        for (std::uint32_t i = n; i-- > 1;) {
            acc.grow(sorted[axis][i].box());
            right_area[i] = acc.half_area();
        }
        acc = Aabb{};
        for (std::uint32_t i = 1; i < n; ++i) {
            acc.grow(sorted[axis][i - 1].box());
            const float cost = ctx.opts.traversal_cost +
                               ctx.opts.intersection_cost *
                                   (acc.half_area() * float(i) + right_area[i] * float(n - i)) / parent_area;
            if (cost < best_cost) {
                best_cost = cost;
                best_axis = axis;
                best_i = i;
            }
        }
    }
    SplitResult r;
    if (best_axis < 0 || !(parent_area > 0)) return r;
    if (best_cost >= ctx.opts.intersection_cost * float(n) && n <= std::uint32_t(ctx.opts.max_leaf_size)) {
        r.make_leaf = true;
        return r;
    }
    std::copy(sorted[best_axis].begin(), sorted[best_axis].end(), ctx.refs.begin() + begin);
    r.found = true;
    r.mid = begin + best_i;
    return r;
}

}  // namespace simdbvh::detail
