#pragma once
// The shared top-down driver: every builder supplies only a split rule.
#include <atomic>
#include <cstdint>
#include <span>
#include <vector>

#include "simdbvh/bvh2/build.h"

namespace simdbvh::detail {

struct BuildContext {
    std::span<const Aabb> boxes;
    std::span<const Vec3> centroids;
    std::vector<std::uint32_t> ids;  // the permutation being partitioned
    BuildOptions opts;
    std::atomic<int> spare_threads{0};
};

struct SplitResult {
    bool found = false;      // split found: ids[begin, mid) left, [mid, end) right
    bool make_leaf = false;  // the rule prefers a leaf (e.g. SAH leaf cost wins)
    std::uint32_t mid = 0;
};

// A split rule partitions ctx.ids[begin, end) in place.
using SplitFn = SplitResult (*)(BuildContext& ctx, std::uint32_t begin, std::uint32_t end, const Aabb& node_box,
                                const Aabb& centroid_box, int depth);

SplitResult split_binned_sah(BuildContext&, std::uint32_t, std::uint32_t, const Aabb&, const Aabb&, int);
SplitResult split_sweep_sah(BuildContext&, std::uint32_t, std::uint32_t, const Aabb&, const Aabb&, int);
SplitResult split_midpoint(BuildContext&, std::uint32_t, std::uint32_t, const Aabb&, const Aabb&, int);
SplitResult split_median(BuildContext&, std::uint32_t, std::uint32_t, const Aabb&, const Aabb&, int);
SplitResult split_variance(BuildContext&, std::uint32_t, std::uint32_t, const Aabb&, const Aabb&, int);

// Builds the tree with the given split rule. Leaves: a range of at most
// `leaf_size` primitives (the rule may stop earlier), or whatever is left at
// the depth cap. When the rule finds no split, ranges larger than `leaf_size`
// are split at the object median (all centroids equal never recurses forever).
Bvh2Topology build_top_down(BuildContext& ctx, SplitFn split, std::uint32_t leaf_size);

}  // namespace simdbvh::detail
