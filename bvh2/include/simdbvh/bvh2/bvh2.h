#pragma once
// Binary BVH over a triangle mesh: flat 32-byte nodes, triangles gathered in
// leaf order, stack traversal for closest hit and any hit.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "simdbvh/kernels/error.h"  // simdbvh::Error, thrown by everything declared here
#include "simdbvh/bvh2/build.h"
#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/kernels/ray.h"
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

struct TraceStats {  // per-ray counters, summed over a batch
    std::uint64_t rays = 0, nodes_visited = 0, box_tests = 0, triangle_tests = 0;
};

// Ray/box test of the BVH2 traversal. conservative: Ize 2013 (far distance
// widened by kFarWiden and the far slack, culling by cull_bound), the validated default. plain:
// (b - o) * rdir with no widening, a comparison variant for the accuracy
// charts. The BVH8 always uses the conservative test (it ignores this field).
enum class BoxTest : std::uint8_t { conservative, plain };

enum class Packets : std::uint8_t { automatic, off, on };
enum class Reorder : std::uint8_t { automatic, off, on };

struct TraceOptions {
    TriangleTest test = TriangleTest::watertight;
    BoxTest box = BoxTest::conservative;  // BVH2 only
    TraceStats* stats = nullptr;          // non-null: count (slower path; forces one thread)
    int threads = 1;                      // batched calls: split the rays over this many threads
    // Wide trees (BVH4/8/16, batched calls): rays interleaved per traversal
    // loop. 0: by the tree's size, 1 for trees of at most 4 MiB (nodes and
    // triangle blocks: they stay in cache, interleaving only costs state
    // switches), else 8 (hides the node and block misses of larger trees);
    // 1 or 8 force it. Anything else is an error. Hits do not depend on it.
    int in_flight = 0;
    // Wide trees (batched calls, AVX2 and AVX-512, not with stats or quantized
    // nodes): packets of 8 consecutive rays sharing one walk of the tree for
    // closest hits, streams of 32 for any hits (occluded). automatic: where they pay, measured as the batch is traced (coherent
    // rays: a camera's in image order); off: never; on: always. Closest hits
    // do not depend on it; an any hit may be another real hit.
    Packets packets = Packets::automatic;
    // Wide trees (batched calls): trace the batch sorted by where its rays
    // start and the octant they go to (bvh8/internal/simdbvh/bvh8/internal/ray_order.h), the hits
    // written back in the caller's order. automatic: rays scattered from
    // surfaces (diffuse bounces in pixel order: neighbours that do not share
    // a start and octant, origins inside the tree's bounds on surfaces, at
    // least 16,384 rays and 300 per 8^3 cell of the bounds they start in),
    // else the caller's order (a camera's rays, rays from outside); off: the
    // caller's order; on: always. Hits do not depend on it (any hits with
    // packets: the stream's choice, as without it).
    Reorder reorder = Reorder::automatic;
    // The one way to choose the ISA of a trace (wide trees, the SIMD brute
    // force, Accel): that ISA's code runs (an unsupported one throws
    // simdbvh::Error). Unset: by speed (bvh8.h: the forced ISA, else the
    // calibrated choice; the brute force and Accel: active_isa() and the
    // Accel's own). The BVH2's walk has one path and ignores it.
    std::optional<Isa> isa;
};
// `o` with TraceOptions::isa set: intersect(bvh8, rays, hits, with_isa({}, Isa::avx2)).
inline TraceOptions with_isa(TraceOptions o, Isa isa) {
    o.isa = isa;
    return o;
}

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
