#pragma once
// Internal: the AVX512 kernels behind traverse-inl.h's K interface (a distinct
// type per ISA). Include only from src/avx512 translation units (here and
// scene/src/avx512), compiled with the AVX512 flags.
// GCC 12 warns that _mm512_undefined_ps() (the pass-through of _mm512_max_ps,
// xsimd's max for zmm) may be used uninitialized: GCC PR 105593, a false positive.
#if defined(__GNUC__) && !defined(__clang__)  // Clang has no such warning
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "simdbvh/bvh8/internal/simd_kernels-inl.h"

namespace simdbvh::bvh8::avx512 {
struct Kernels : SimdKernels<kernels::simd::Avx512> {};
}  // namespace simdbvh::bvh8::avx512
