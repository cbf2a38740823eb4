#pragma once
// Internal: the per-ISA implementations behind kernels/batch.h. Each lives in
// its own translation unit (src/scalar, src/avx2, src/avx512) and namespace;
// batch.cpp holds the one switch. No intrinsics here.
#include <cstdint>
#include <span>

#include "simdbvh/kernels/batch.h"

namespace simdbvh::kernels {

namespace detail {
// Records which compiled implementation ran the last batched call on this thread.
void note_isa_used(Isa isa);
}  // namespace detail

namespace scalar {  // src/scalar/kernels_scalar.cpp
    Isa compiled_isa();
    void intersect_box8(std::span<const Ray> rays, const Box8& boxes, std::uint8_t* masks, float* entries);
    std::uint64_t count_box8_hits(std::span<const Ray> rays, std::span<const Box8> blocks);
    void intersect_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test, Hit* hits);
    void occluded_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test,
                       std::uint8_t* occluded, Hit* first_hits);  // first_hits may be null
}  // namespace scalar

namespace avx2 {  // src/avx2/kernels_avx2.cpp
    Isa compiled_isa();
    void intersect_box8(std::span<const Ray> rays, const Box8& boxes, std::uint8_t* masks, float* entries);
    std::uint64_t count_box8_hits(std::span<const Ray> rays, std::span<const Box8> blocks);
    void intersect_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test, Hit* hits);
    void occluded_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test,
                       std::uint8_t* occluded, Hit* first_hits);  // first_hits may be null
}  // namespace avx2

namespace avx512 {  // src/avx512/kernels_avx512.cpp
    Isa compiled_isa();
    void intersect_box8(std::span<const Ray> rays, const Box8& boxes, std::uint8_t* masks, float* entries);
    std::uint64_t count_box8_hits(std::span<const Ray> rays, std::span<const Box8> blocks);
    void intersect_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test, Hit* hits);
    void occluded_tri8(std::span<const Ray> rays, std::span<const Tri8> blocks, TriangleTest test,
                       std::uint8_t* occluded, Hit* first_hits);  // first_hits may be null
}  // namespace avx512

}  // namespace simdbvh::kernels
