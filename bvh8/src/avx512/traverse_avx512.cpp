// Wide BVH traversal (N = 4, 8, 16), AVX-512 build of traverse-inl.h: Tri8
// kernels on 8 x float (VL, simd::Avx512), node tests of 4 (xmm), 8 (ymm) and
// 16 (one zmm) lanes.
#include "simdbvh/bvh8/internal/avx512/kernels_avx512.h"
#include "simdbvh/bvh8/internal/traverse-inl.h"

namespace simdbvh::bvh8 {

template struct Traversal<avx512::Kernels, 4>;
template struct Traversal<avx512::Kernels, 8>;
template struct Traversal<avx512::Kernels, 16>;

}  // namespace simdbvh::bvh8
