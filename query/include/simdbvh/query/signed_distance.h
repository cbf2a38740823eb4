#pragma once
// Signed distance to a closed mesh: the closest point's distance, negative for
// points inside (exact inside test, simdbvh/query/inside.h), 0 on the surface.
// For a mesh that is not closed the sign is the crossing rule's answer and may
// be wrong near the holes: check mesh_closure() first.
#include <span>

#include "simdbvh/query/closest_point.h"
#include "simdbvh/query/inside.h"

namespace simdbvh {

struct SignedDistance {
    ClosestPoint nearest;  // unsigned distance, triangle, point
    PointSide side;
    float signed_distance() const {
        return side.side == Side::surface ? 0.0f : (side.side == Side::inside ? -nearest.distance : nearest.distance);
    }
};

void signed_distance(const Bvh2& bvh, std::span<const Vec3> points, std::span<SignedDistance> out,
                     const PointQueryOptions& opts = {}, const InsideOptions& inside = {});

}  // namespace simdbvh
