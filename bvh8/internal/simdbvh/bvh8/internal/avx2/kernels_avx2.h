#pragma once
// Internal: the AVX2 kernels behind traverse-inl.h's K interface (a distinct
// type per ISA). Include only from src/avx2 translation units (here and
// scene/src/avx2), compiled with the AVX2 flags.
#include "simdbvh/bvh8/internal/simd_kernels-inl.h"

namespace simdbvh::bvh8::avx2 {
struct Kernels : SimdKernels<kernels::simd::Avx2> {};
}  // namespace simdbvh::bvh8::avx2
