#pragma once
// Closest point on the wide trees (N = 4, 8, 16): the BVH2's rule
// (simdbvh/query/closest_point.h), the same answer bit for bit: each
// triangle's closest point in double, the smallest squared distance, ties to
// the lower triangle id. Depth first, nearer child first by box distance,
// pruned by the best distance so far (conservatively: pruning never changes
// the answer); one wide node tests its N child boxes at once.
#include <span>

#include "simdbvh/query/closest_point.h"
#include "simdbvh/bvh8/bvh8.h"

namespace simdbvh {

template <int N>
ClosestPoint closest_point(const BvhN<N>& bvh, const Vec3& p, const PointQueryOptions& opts = {});
// PointQueryStats::nodes_visited counts wide nodes.
template <int N>
void closest_point(const BvhN<N>& bvh, std::span<const Vec3> points, std::span<ClosestPoint> out,
                   const PointQueryOptions& opts = {});

}  // namespace simdbvh
