#pragma once
// Seed 002's bounding-sphere hierarchy, kept as a bounding-volume-shape
// comparison beside the BVH2: the variance split rule (axis of greatest
// centroid variance, split at the mean), one sphere per node (centre = mean of
// the group's vertices, radius = the largest distance to them, rounded up), a
// stack traversal with a conservative ray/sphere test and the scalar triangle
// tests with the closer() tie rule, so results are bit-identical to
// brute_force_intersect.
#include <cstdint>
#include <span>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"

namespace simdbvh {

struct SphereNode {  // 24 bytes
    Vec3 center;
    float radius;         // bounds every vertex of the subtree (rounded toward +inf)
    std::uint32_t first;  // leaf: first index into prim_ids; inner: left child (right = first + 1)
    std::uint32_t count;  // 0 = inner node
    bool is_leaf() const { return count != 0; }
};
static_assert(sizeof(SphereNode) == 24);

struct SphereBuildStats {
    double build_ms = 0;
    std::size_t nodes = 0, leaves = 0, triangles = 0;
    int depth = 0;
    double sah_cost = 0;            // SAH of the same topology with its AABBs (comparable with the BVH2 rows)
    double sphere_sah_cost = 0;     // the same sum with sphere surface areas (4 pi r^2) in place of box areas
    double bytes_per_triangle = 0;  // nodes + prim ids + gathered triangles
};

class SphereBvh {
public:
    SphereBvh() = default;
    // Validates the mesh (throws simdbvh::Error) and builds. The split rule is
    // always Builder::variance; max_leaf_size, max_depth and threads are used.
    static SphereBvh build(const Mesh& mesh, const BuildOptions& opts = {});

    const std::vector<SphereNode>& nodes() const { return nodes_; }
    const std::vector<std::uint32_t>& prim_ids() const { return prim_ids_; }
    const std::vector<TriangleVerts>& triangles() const { return tris_; }  // tris_[i] is triangle prim_ids_[i]
    const SphereBuildStats& stats() const { return stats_; }

private:
    std::vector<SphereNode> nodes_;
    std::vector<std::uint32_t> prim_ids_;
    std::vector<TriangleVerts> tris_;
    SphereBuildStats stats_;
};

// Conservative ray/sphere test: false only when the ray's interval
// [tmin, tmax] certainly misses the sphere; *entry is a lower bound of the
// entry distance (may lie before tmin). Exposed for tests.
bool intersect_sphere(const PreparedRay& r, const SphereNode& s, float tmax, float* entry);

// Same contracts as the BVH2 queries (TraceStats::box_tests counts sphere tests).
Hit intersect(const SphereBvh& bvh, const Ray& ray, const TraceOptions& opts = {});
Hit occluded(const SphereBvh& bvh, const Ray& ray, const TraceOptions& opts = {});
void intersect(const SphereBvh& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts = {});
void occluded(const SphereBvh& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts = {});

}  // namespace simdbvh
