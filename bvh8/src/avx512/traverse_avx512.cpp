// Wide BVH traversal (N = 4, 8, 16), AVX-512 build of traverse-inl.h: Tri8
// kernels on 8 x float (VL, simd::Avx512), node tests of 4 (xmm), 8 (ymm) and
// 16 (one zmm) lanes.
// GCC 12 warns that _mm512_undefined_ps() (the pass-through of _mm512_max_ps,
// xsimd's max for zmm) may be used uninitialized: GCC PR 105593, a false positive.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include "simd_kernels-inl.h"
#include "traverse-inl.h"

namespace simdbvh::bvh8 {

namespace avx512 {
struct Kernels : SimdKernels<simd::Avx512> {};
}  // namespace avx512

template struct Traversal<avx512::Kernels, 4>;
template struct Traversal<avx512::Kernels, 8>;
template struct Traversal<avx512::Kernels, 16>;

}  // namespace simdbvh::bvh8
