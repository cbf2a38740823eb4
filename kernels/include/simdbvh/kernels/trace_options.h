#pragma once
// How a ray batch is traced, for every tree (BVH2, BVH4/8/16, the SIMD brute
// force, Accel): the options struct of the ray queries and its counters. Each
// field says which trees read it; a tree ignores the fields of the others.
#include <cstdint>
#include <optional>

#include "simdbvh/kernels/isa.h"
#include "simdbvh/kernels/triangle.h"

namespace simdbvh {

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

}  // namespace simdbvh
