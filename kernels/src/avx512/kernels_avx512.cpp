// avx512 kernels: simd/*-inl.h instantiated for simd::Avx512, the same 8-wide (ymm) code as avx2
// compiled with AVX-512F/VL/DQ/BW/CD: EVEX encodings, 32 vector registers, opmask compares.
#if !defined(__AVX512F__) || !defined(__AVX512VL__) || !defined(__AVX512DQ__) || !defined(__AVX512BW__) || !defined(__AVX512CD__)
#error "src/avx512/ must be compiled with the AVX-512 flags"
#endif
#include "simd/batch-inl.h"

namespace simdbvh::kernels::avx512 {

using Loops = simd::BatchLoops<simd::Avx512>;

Isa compiled_isa() { return Isa::avx512; }

SIMDBVH_FLATTEN void intersect_box8(std::span<const Ray> rays, const Box8& boxes, std::uint8_t* masks, float* entries) {
    detail::note_isa_used(Isa::avx512);
    Loops::box8(rays, boxes, masks, entries);
}

SIMDBVH_FLATTEN void intersect_box8_groups(std::span<const Ray> rays, std::span<const Box8> supers,
                                           std::span<const Box8> groups, std::uint8_t* masks, float* entries) {
    detail::note_isa_used(Isa::avx512);
    Loops::box8_groups(rays, supers, groups, masks, entries);
}

SIMDBVH_FLATTEN detail::TreeWalk collect_box8_tree(std::span<const Ray> rays, std::span<const std::uint8_t> live,
                                                   std::span<const Box8> nodes,
                                                   std::span<const std::uint32_t> children, std::size_t leaf_lanes,
                                                   std::uint32_t* stack, std::pair<float, std::uint32_t>* out,
                                                   std::size_t used, std::size_t cap, std::uint32_t* first) {
    detail::note_isa_used(Isa::avx512);
    return Loops::box8_tree(rays, live, nodes, children, leaf_lanes, stack, out, used, cap, first);
}

SIMDBVH_FLATTEN std::uint64_t count_box8_hits(std::span<const Ray> rays, std::span<const Box8> blocks) {
    detail::note_isa_used(Isa::avx512);
    return Loops::count_box8(rays, blocks);
}

SIMDBVH_FLATTEN void intersect_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test,
                                    Hit* hits) {
    detail::note_isa_used(Isa::avx512);
    if (test == TriangleTest::watertight) Loops::closest<TriangleTest::watertight>(rays, blocks, hits);
    else Loops::closest<TriangleTest::moller>(rays, blocks, hits);
}

SIMDBVH_FLATTEN void occluded_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test,
                                   std::uint8_t* occluded, Hit* first_hits) {
    detail::note_isa_used(Isa::avx512);
    if (test == TriangleTest::watertight) Loops::any<TriangleTest::watertight>(rays, blocks, occluded, first_hits);
    else Loops::any<TriangleTest::moller>(rays, blocks, occluded, first_hits);
}

}  // namespace simdbvh::kernels::avx512
