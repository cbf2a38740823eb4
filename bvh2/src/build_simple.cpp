// The seed articles' split rules, kept as comparison rows.
#include <algorithm>

#include "build_common.h"

namespace simdbvh::detail {

namespace {

SplitResult leaf_result() {
    SplitResult r;
    r.make_leaf = true;
    return r;
}

SplitResult partition_at(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, int axis, float pos) {
    PrimRef* first = ctx.refs.data() + begin;
    PrimRef* mid = std::partition(first, ctx.refs.data() + end, [&](const PrimRef& p) { return p.c[axis] < pos; });
    SplitResult r;
    r.mid = begin + std::uint32_t(mid - first);
    r.found = r.mid > begin && r.mid < end;
    return r;
}

// Sorts ids[begin, end) by centroid along an axis, ties by id (deterministic).
void sort_axis(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, int axis) {
    std::sort(ctx.refs.begin() + begin, ctx.refs.begin() + end, [&](const PrimRef& a, const PrimRef& b) {
        const float ca = a.c[axis], cb = b.c[axis];
        return ca < cb || (ca == cb && a.id < b.id);
    });
}

}  // namespace

// Seed 000, first version: longest axis of the centroid bounds, split at its
// midpoint, leaf at <= 4 triangles (or the depth cap).
SplitResult split_midpoint(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Aabb&, const Aabb& cbox,
                           int) {
    if (end - begin <= 4) return leaf_result();
    const int axis = cbox.largest_axis();
    return partition_at(ctx, begin, end, axis, cbox.center()[axis]);
}

// Seed 004 (Shirley): sort by centroid along x, y, z in turn with depth and
// split the list in half; one primitive per leaf.
SplitResult split_median(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Aabb&, const Aabb&,
                         int depth) {
    if (end - begin <= 1) return leaf_result();
    sort_axis(ctx, begin, end, depth % 3);
    SplitResult r;
    r.found = true;
    r.mid = begin + (end - begin) / 2;
    return r;
}

// Seed 002: the axis of greatest centroid variance (Welford's method), split
// at the mean; leaf when at most max_leaf_size triangles remain.
SplitResult split_variance(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Aabb&, const Aabb&, int) {
    if (end - begin <= std::uint32_t(ctx.opts.max_leaf_size)) return leaf_result();
    double mean[3] = {0, 0, 0}, m2[3] = {0, 0, 0};
    double k = 0;
    for (std::uint32_t i = begin; i < end; ++i) {
        const Vec3 c = ctx.refs[i].c;
        k += 1;
        for (int a = 0; a < 3; ++a) {
            const double d = double(c[a]) - mean[a];
            mean[a] += d / k;
            m2[a] += d * (double(c[a]) - mean[a]);
        }
    }
    const int axis = m2[0] > m2[1] && m2[0] > m2[2] ? 0 : (m2[1] > m2[2] ? 1 : 2);
    return partition_at(ctx, begin, end, axis, float(mean[axis]));
}

}  // namespace simdbvh::detail
