#pragma once
// Binary BVH over a triangle mesh: flat 32-byte nodes, triangles gathered in
// leaf order, stack traversal for closest hit and any hit.
#include <cstdint>
#include <span>
#include <vector>

#include "simdbvh/kernels/error.h"  // simdbvh::Error, thrown by everything declared here
#include "simdbvh/bvh2/build.h"
#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/trace_options.h"
#include "simdbvh/kernels/triangle.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh {

struct TriangleVerts {  // a triangle's vertices, gathered in leaf order (36 bytes)
    Vec3 v0, v1, v2;
};

struct BuildStats {
    double build_ms = 0;
    std::size_t nodes = 0, leaves = 0, triangles = 0;
    int depth = 0;
    double sah_cost = 0;
    double bytes_per_triangle = 0;  // nodes + prim ids + gathered triangles
};

class Bvh2 {
public:
    Bvh2() = default;
    // Validates the mesh (throws simdbvh::Error), builds, gathers triangles.
    static Bvh2 build(const Mesh& mesh, const BuildOptions& opts = {});

    // Refit for a moved mesh: the same triangles (same count and ids), new
    // vertex positions. Re-gathers the triangles and recomputes every box
    // bottom-up (leaves on `threads` threads, then one pass over the inner
    // nodes), in place: no allocation, the topology kept. stats().sah_cost is
    // recomputed; the rest of the stats are the build's. Hits afterwards are
    // bit-identical to brute force on the moved mesh (the boxes are exact
    // unions, as after a build). A mesh with another triangle count, an index
    // out of range or a non-finite vertex throws simdbvh::Error and leaves the
    // tree unchanged. A refit with the build's own mesh reproduces the tree
    // byte for byte.
    void refit(const Mesh& mesh, int threads = 1);

    const Nodes2& nodes() const { return nodes_; }
    const std::vector<std::uint32_t>& prim_ids() const { return prim_ids_; }
    const std::vector<TriangleVerts>& triangles() const { return tris_; }  // tris_[i] is triangle prim_ids_[i]
    const BuildStats& stats() const { return stats_; }
    const BuildOptions& options() const { return opts_; }
    Aabb bounds() const { return nodes_.empty() ? Aabb{} : nodes_[0].box; }

private:
    friend struct StoreAccess;  // store/: loads a saved tree
    Nodes2 nodes_;
    std::vector<std::uint32_t> prim_ids_;
    std::vector<TriangleVerts> tris_;
    BuildStats stats_;
    BuildOptions opts_;
};

// Closest hit: smallest t in [tmin, tmax], ties to the lower triangle id. Misses
// return Hit{} (t = +inf, prim = kInvalidPrim). Invalid rays miss without traversal.
Hit intersect(const Bvh2& bvh, const Ray& ray, const TraceOptions& opts = {});
// Any hit: some triangle hit in [tmin, tmax] (t, u, v of that hit), or Hit{}.
Hit occluded(const Bvh2& bvh, const Ray& ray, const TraceOptions& opts = {});

void intersect(const Bvh2& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts = {});
void occluded(const Bvh2& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts = {});

// The O(rays x triangles) reference with the same triangle test and tie rule.
Hit brute_force_intersect(const Mesh& mesh, const Ray& ray, TriangleTest test = TriangleTest::watertight);
Hit brute_force_occluded(const Mesh& mesh, const Ray& ray, TriangleTest test = TriangleTest::watertight);
void brute_force_intersect(const Mesh& mesh, std::span<const Ray> rays, std::span<Hit> hits,
                           TriangleTest test = TriangleTest::watertight);

}  // namespace simdbvh
