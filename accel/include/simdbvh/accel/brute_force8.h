#pragma once
// SIMD brute force: no tree, the mesh's triangles gathered once into Tri8
// blocks in index order, and every ray tested against every block with the
// 8-wide kernels of the chosen ISA (kernels/batch.h), split over threads by
// rays. For meshes and ray counts too small for a tree to pay back its build
// (Accel's automatic choice, accel.h). Closest hits are bit-identical to brute_force_intersect (bvh2.h)
// and to every tree: same watertight test, same tie rule (equal t: lower id).
// Any hit: the first hit in block and lane order (a genuine hit in [tmin, tmax]).
#include <span>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/node.h"
#include "simdbvh/kernels/isa.h"

namespace simdbvh {

class BruteForce8 {
public:
    BruteForce8() = default;
    // Validates the mesh (throws simdbvh::Error) and gathers its triangles.
    static BruteForce8 build(const Mesh& mesh);

    const Tri8Blocks& blocks() const { return blocks_; }
    std::size_t triangles() const { return triangles_; }
    double build_ms() const { return build_ms_; }

private:
    Tri8Blocks blocks_;
    std::size_t triangles_ = 0;
    double build_ms_ = 0;
};

// TraceOptions: test, threads and isa (unset: active_isa()) are used (box and stats do not apply).
void intersect(const BruteForce8& brute, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts = {});
void occluded(const BruteForce8& brute, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts = {});

}  // namespace simdbvh
