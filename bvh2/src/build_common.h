#pragma once
// The shared top-down driver: every builder supplies only a split rule.
// Primitives are PrimRefs (box, centroid, id) kept contiguous and partitioned
// in place, so every pass over a node's range streams through memory.
#include <atomic>
#include <cstdint>
#include <span>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "simdbvh/bvh2/build.h"
#include "simdbvh/platform/large_alloc.h"

namespace simdbvh::detail {

struct alignas(16) PrimRef {  // 48 bytes; lo and hi load as 16-byte vectors
    Vec3 lo;
    std::uint32_t id;
    Vec3 hi;
    float pad0;
    Vec3 c;  // centroid, as given by the caller
    float pad1;
    Aabb box() const { return {lo, hi}; }
};
static_assert(sizeof(PrimRef) == 48);

// A LargeVector's resize() leaves new PrimRefs unwritten (no zero fill): every
// writer sets each reference it allocates, on the build threads, so the pages
// are first touched there rather than by a serial memset.
static_assert(std::is_trivially_copyable_v<PrimRef> && std::is_trivially_destructible_v<PrimRef>);

struct BuildContext {
    LargeVector<PrimRef> refs;  // partitioned in place
    BuildOptions opts;
    std::atomic<int> spare_threads{0};
    bool float_costs = true;  // SAH costs in float (see sah_area); set by build_top_down
};

// SAH costs of a whole tree are computed in float when they cannot overflow
// (the root's float area times the primitive count and the cost factors stays
// far below FLT_MAX): the trees are then bit-identical to the float builders'.
// Otherwise in double, finite for any finite input (Aabb::half_area).
bool costs_fit_float(const Aabb& root, std::size_t prims, const BuildOptions& opts);

template <class T>
T sah_area(const Aabb& b) {
    if constexpr (std::is_same_v<T, float>) return b.half_area_float();
    else return b.half_area();
}

struct Bounds {  // a range's box and centroid box
    Aabb box, cbox;
};
Bounds range_bounds(const BuildContext& ctx, std::uint32_t begin, std::uint32_t end);
// Grows `into` by `b` exactly as range_bounds grows by each reference in
// turn: merging the bounds of consecutive ranges in order gives the bounds of
// their union bit for bit (on ties between -0 and +0 the earlier one stays).
inline void grow(Bounds& into, const Bounds& b) {
    into.box.grow(b.box);
    into.cbox.grow(b.cbox);
}

struct SplitResult {
    bool found = false;      // split found: refs[begin, mid) left, [mid, end) right
    bool make_leaf = false;  // the rule prefers a leaf (e.g. SAH leaf cost wins)
    std::uint32_t mid = 0;
    bool has_bounds = false;  // the rule computed the children's bounds while partitioning
    Bounds left, right;
};

// A split rule partitions ctx.refs[begin, end) in place.
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
// The same, with the root's bounds (range_bounds over every reference)
// already known.
Bvh2Topology build_top_down(BuildContext& ctx, SplitFn split, std::uint32_t leaf_size, const Bounds& root);

}  // namespace simdbvh::detail
