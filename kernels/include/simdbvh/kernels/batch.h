#pragma once
// Batched kernel entry points: a span of rays against boxes or triangles.
// Each call chooses its implementation once, at the top (one switch on `isa`);
// the ISA defaults to the detected/forced one and can be set explicitly so
// tests and benchmarks can run every path. Unsupported ISA -> simdbvh::Error.
//
// Every implementation (scalar, avx2, avx512) returns bit-identical results:
// the scalar one loops the reference functions of box.h / triangle.h.
// Rays that prepare() marks invalid (zero/NaN/Inf direction, NaN/Inf origin,
// NaN or empty interval) are misses: mask 0 with entries +inf, Hit{}.
// No intrinsics and no xsimd in this header.
#include <cstdint>
#include <span>

#include "simdbvh/kernels/aabb.h"
#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/soa.h"
#include "simdbvh/kernels/triangle.h"

namespace simdbvh::kernels {

// One triangle with its id (the single-triangle form, benchmark baseline).
struct Tri1 {
    Vec3 v0, v1, v2;
    std::uint32_t prim = kInvalidPrim;
};
static_assert(sizeof(Tri1) == 40);

// --- Single-primitive forms (scalar only: the reference, one test per ray) ---
// Ray i against boxes[i]: hits[i] = 0/1, entries[i] = entry distance (+inf on a miss).
void intersect_box1(std::span<const Ray> rays, std::span<const Aabb> boxes, std::span<std::uint8_t> hits,
                    std::span<float> entries);
// Ray i against tris[i]: hits[i] = the hit in [tmin, tmax] or Hit{}.
void intersect_tri1(std::span<const Ray> rays, std::span<const Tri1> tris, TriangleTest test,
                    std::span<Hit> hits);

// --- 8-wide forms (SoA blocks; one implementation per ISA) ---
// Every ray against one Box8, interval [tmin, tmax] of the ray: masks[i] bit j =
// ray i hits box j; entries[8*i + j] = its entry distance (lanes that miss:
// whatever the slab test computed; invalid rays: +inf).
void intersect_box8(std::span<const Ray> rays, const Box8& boxes, std::span<std::uint8_t> masks,
                    std::span<float> entries, Isa isa = active_isa());
// Every ray against every block: the total number of (ray, box) hits. Streams
// `blocks` once per ray (the benchmark's memory-bound form).
std::uint64_t count_box8_hits(std::span<const Ray> rays, std::span<const Box8> blocks, Isa isa = active_isa());
// Closest hit of each ray over all blocks (ties: lower prim id); Hit{} on a miss.
void intersect_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test,
                    std::span<Hit> hits, Isa isa = active_isa());
// Any hit of each ray over the blocks in [tmin, tmax]: occluded[i] = 0/1.
// When first_hits is not empty it receives the first hit found (blocks in
// order, lanes in order), Hit{} when none.
void occluded_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test,
                   std::span<std::uint8_t> occluded, std::span<Hit> first_hits = {}, Isa isa = active_isa());

// The ISA whose compiled code ran the last 8-wide batched call on this thread
// (set by the per-ISA translation unit itself), or nullopt before any call.
std::optional<Isa> last_isa_used();
// The ISA a per-ISA translation unit was compiled for (asks that unit).
Isa compiled_isa(Isa isa);

}  // namespace simdbvh::kernels
