#pragma once
// Closest point on a triangle mesh: for a query point p, the point of the mesh
// nearest to p, its triangle, barycentrics and distance.
//
// Exact rule, the same on every path (BVH2 and brute force): each triangle's
// closest point and squared distance are computed in double from the float
// vertices (closest_point_on_triangle), the smallest squared distance wins and
// ties go to the lower triangle id. The returned point and distance are those
// doubles rounded once to float. Degenerate (zero-area) triangles are treated
// as their longest segment. A non-finite query point, an empty mesh or no
// triangle within max_distance give ClosestPoint{} (prim = kInvalidPrim,
// distance = +inf).
#include <cstdint>
#include <limits>
#include <span>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/vec.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh {

struct ClosestPoint {
    Vec3 point;                                               // on the triangle (rounded from double)
    float distance = std::numeric_limits<float>::infinity();  // |point - p| (rounded from double)
    std::uint32_t prim = kInvalidPrim;
    float u = 0.0f, v = 0.0f;                                    // barycentrics of v1 and v2 (Hit's convention)
    double distance2 = std::numeric_limits<double>::infinity();  // the squared distance that decided

    constexpr bool found() const { return prim != kInvalidPrim; }
};
static_assert(sizeof(ClosestPoint) == 40);

struct PointQueryStats {  // summed over a batch
    std::uint64_t points = 0, nodes_visited = 0, triangle_tests = 0, exact_tests = 0;
};

struct PointQueryOptions {
    // Only triangles within this distance (inclusive) are considered.
    float max_distance = std::numeric_limits<float>::infinity();
    int threads = 1;                   // batched calls: split the points over this many threads
    PointQueryStats* stats = nullptr;  // non-null: count (forces one thread)
};

// One triangle in double: the closest point of (v0, v1, v2) to p.
struct TrianglePoint {
    double x = 0, y = 0, z = 0;  // the closest point
    double u = 0, v = 0;         // its barycentrics of v1 and v2
    double distance2 = 0;        // squared distance to p
};
TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& v0, const Vec3& v1, const Vec3& v2);

ClosestPoint closest_point(const Bvh2& bvh, const Vec3& p, const PointQueryOptions& opts = {});
void closest_point(const Bvh2& bvh, std::span<const Vec3> points, std::span<ClosestPoint> out,
                   const PointQueryOptions& opts = {});

// O(points x triangles), the same rule.
ClosestPoint brute_force_closest_point(const Mesh& mesh, const Vec3& p, const PointQueryOptions& opts = {});

}  // namespace simdbvh
