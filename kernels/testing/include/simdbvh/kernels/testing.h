#pragma once
// Test and benchmark support for the kernels, not part of the installed API
// (target simdbvh_kernels_testing, build tree only): the single-triangle and
// single-box reference forms the kernel benchmarks use as a baseline, the
// memory-bound box counter, and which compiled ISA ran a call (so tests can
// check that dispatch reached the path they asked for). Implemented in the
// kernels library's per-ISA translation units beside batch.h's entry points.
#include <cstdint>
#include <optional>
#include <span>

#include "simdbvh/kernels/batch.h"

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
void intersect_tri1(std::span<const Ray> rays, std::span<const Tri1> tris, TriangleTest test, std::span<Hit> hits);

// Every ray against every block: the total number of (ray, box) hits. Streams
// `blocks` once per ray (the benchmark's memory-bound form).
std::uint64_t count_box8_hits(std::span<const Ray> rays, std::span<const Box8> blocks, Isa isa = active_isa());

// The ISA whose compiled code ran the last 8-wide batched call on this thread
// (set by the per-ISA translation unit itself), or nullopt before any call.
std::optional<Isa> last_isa_used();
// The ISA a per-ISA translation unit was compiled for (asks that unit).
Isa compiled_isa(Isa isa);

}  // namespace simdbvh::kernels
