// Wide BVH traversal (N = 4, 8, 16), AVX2 + FMA build of traverse-inl.h:
// xsimd::avx2 Tri8 kernels, node tests of 4 (xmm), 8 (ymm) and 16 (two ymm) lanes.
#include "simdbvh/bvh8/internal/avx2/kernels_avx2.h"
#include "simdbvh/bvh8/internal/traverse-inl.h"

namespace simdbvh::bvh8 {

template struct Traversal<avx2::Kernels, 4>;
template struct Traversal<avx2::Kernels, 8>;
template struct Traversal<avx2::Kernels, 16>;

}  // namespace simdbvh::bvh8
