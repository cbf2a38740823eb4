// Full-sweep SAH: every split position between centroid-sorted primitives on
// each axis (MacDonald and Booth 1990): the quality reference for binning.
#include <algorithm>
#include <limits>

#include "build_common.h"

namespace simdbvh::detail {

namespace {

// Costs in T: float or double (BuildContext::float_costs).
template <class T>
SplitResult split_sweep(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Aabb& node_box) {
    const std::uint32_t n = end - begin;
    const T parent_area = sah_area<T>(node_box);
    std::vector<PrimRef> sorted[3];
    std::vector<T> right_area(n);
    T best_cost = std::numeric_limits<T>::infinity();
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
            right_area[i] = sah_area<T>(acc);
        }
        acc = Aabb{};
        for (std::uint32_t i = 1; i < n; ++i) {
            acc.grow(sorted[axis][i - 1].box());
            const T cost = T(ctx.opts.traversal_cost) + T(ctx.opts.intersection_cost) *
                                                            (sah_area<T>(acc) * T(i) + right_area[i] * T(n - i)) /
                                                            parent_area;
            if (cost < best_cost) {
                best_cost = cost;
                best_axis = axis;
                best_i = i;
            }
        }
    }
    SplitResult r;
    if (best_axis < 0 || !(parent_area > 0)) return r;
    if (best_cost >= T(ctx.opts.intersection_cost) * T(n) && n <= std::uint32_t(ctx.opts.max_leaf_size)) {
        r.make_leaf = true;
        return r;
    }
    std::copy(sorted[best_axis].begin(), sorted[best_axis].end(), ctx.refs.begin() + begin);
    r.found = true;
    r.mid = begin + best_i;
    return r;
}

}  // namespace

SplitResult split_sweep_sah(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Aabb& node_box,
                            const Aabb&, int) {
    return ctx.float_costs ? split_sweep<float>(ctx, begin, end, node_box)
                           : split_sweep<double>(ctx, begin, end, node_box);
}

}  // namespace simdbvh::detail
