// avx2 kernels: simd/*-inl.h instantiated for simd::Avx2. AVX2 + FMA, 8 x float in ymm.
#if !defined(__AVX2__) || !defined(__FMA__) || defined(__AVX512F__)
#error "src/avx2/ must be compiled with the AVX2 flags (and without AVX-512)"
#endif
#include "simd/batch-inl.h"

namespace simdbvh::kernels::avx2 {

using Loops = simd::BatchLoops<simd::Avx2>;
constexpr Isa kThisIsa = Isa::avx2;

#include "simd/entry_defs.inc"

}  // namespace simdbvh::kernels::avx2
