#pragma once
// Exact inside/outside on the wide trees (N = 4, 8, 16): the BVH2's test
// (simdbvh/query/inside.h), the same answer field for field: the +z ray from
// each point, every triangle it may meet decided by the same exact
// predicates. One wide node tests its N child boxes against the ray's column
// at once, and a Tri8 block its 8 triangles' columns; each triangle is counted
// through its own leaf only (a block shared by sibling leaves is read once per
// leaf, its own lanes), so every crossing is counted once.
#include <span>

#include "simdbvh/query/inside.h"
#include "simdbvh/bvh8/bvh8.h"

namespace simdbvh {

template <int N>
PointSide classify_point(const BvhN<N>& bvh, const Vec3& p, const InsideOptions& opts = {});
template <int N>
void classify_points(const BvhN<N>& bvh, std::span<const Vec3> points, std::span<PointSide> out,
                     const InsideOptions& opts = {});

}  // namespace simdbvh
