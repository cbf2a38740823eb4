// avx512 kernels: simd/*-inl.h instantiated for simd::Avx512, the same 8-wide (ymm) code as avx2
// compiled with AVX-512F/VL/DQ/BW/CD: EVEX encodings, 32 vector registers, opmask compares.
#if !defined(__AVX512F__) || !defined(__AVX512VL__) || !defined(__AVX512DQ__) || !defined(__AVX512BW__) || \
    !defined(__AVX512CD__)
#error "src/avx512/ must be compiled with the AVX-512 flags"
#endif
#include "simd/batch-inl.h"

namespace simdbvh::kernels::avx512 {

using Loops = simd::BatchLoops<simd::Avx512>;
constexpr Isa kThisIsa = Isa::avx512;

#include "simd/entry_defs.inc"

}  // namespace simdbvh::kernels::avx512
