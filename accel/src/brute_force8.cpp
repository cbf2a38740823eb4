// SIMD brute force: Tri8 blocks in triangle order, the kernels' batched
// entry points (one switch on the ISA there), rays split over threads.
#include "simdbvh/accel/brute_force8.h"

#include <chrono>
#include <vector>

#include "simdbvh/kernels/batch.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh {

BruteForce8 BruteForce8::build(const Mesh& mesh) {
    const auto t0 = std::chrono::steady_clock::now();
    validate(mesh);
    BruteForce8 b;
    b.triangles_ = mesh.size();
    b.blocks_.resize((mesh.size() + kBlockWidth - 1) / kBlockWidth);
    for (std::size_t k = 0; k < b.blocks_.size(); ++k) {
        Tri8& blk = b.blocks_[k];
        blk.clear();
        for (int i = 0; i < kBlockWidth; ++i) {
            const std::size_t t = k * kBlockWidth + std::size_t(i);
            if (t < mesh.size()) blk.set(i, mesh.vertex(t, 0), mesh.vertex(t, 1), mesh.vertex(t, 2), std::uint32_t(t));
        }
    }
    b.build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return b;
}

void intersect(const BruteForce8& brute, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    simdbvh::detail::check_size(hits.size(), rays.size(), "hits");
    const Isa isa = o.isa.value_or(active_isa());
    require(isa);
    parallel_for(
        rays.size(), o.threads,
        [&](std::size_t b, std::size_t e) {
            kernels::intersect_tri8(rays.subspan(b, e - b), brute.blocks(), o.test, hits.subspan(b, e - b), isa);
        },
        options_for_cost(brute.triangles(), kernels::kBruteRayTile));
}

void occluded(const BruteForce8& brute, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    simdbvh::detail::check_size(hits.size(), rays.size(), "hits");
    const Isa isa = o.isa.value_or(active_isa());
    require(isa);
    parallel_for(
        rays.size(), o.threads,
        [&](std::size_t b, std::size_t e) {
            std::vector<std::uint8_t> flags(e - b);
            kernels::occluded_tri8(rays.subspan(b, e - b), brute.blocks(), o.test, flags, hits.subspan(b, e - b), isa);
        },
        options_for_cost(brute.triangles(), kernels::kBruteRayTile));
}

}  // namespace simdbvh
