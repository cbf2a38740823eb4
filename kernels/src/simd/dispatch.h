#pragma once
// Internal: the per-ISA implementations behind kernels/batch.h. Each lives in
// its own translation unit (src/scalar, src/avx2, src/avx512) and namespace;
// batch.cpp holds the one switch. No intrinsics here.
#include <cstdint>
#include <span>

#include "simdbvh/kernels/batch.h"
#include "simdbvh/kernels/testing.h"
#include "box_tree_walk-inl.h"

namespace simdbvh::kernels {

namespace detail {
// Records which compiled implementation ran the last batched call on this thread.
void note_isa_used(Isa isa);
}  // namespace detail

namespace scalar {  // src/scalar/kernels_scalar.cpp
#include "simd/entry_points.inc"
}  // namespace scalar

#if defined(__x86_64__)
namespace avx2 {  // src/avx2/kernels_avx2.cpp
#include "simd/entry_points.inc"
}  // namespace avx2

namespace avx512 {  // src/avx512/kernels_avx512.cpp
#include "simd/entry_points.inc"
}  // namespace avx512
#else
// Not built for this processor (cmake/SimdbvhIsa.cmake): the names stand for
// the scalar set so the switches compile; require() refuses the ISA first.
namespace avx2 = scalar;
namespace avx512 = scalar;
#endif

}  // namespace simdbvh::kernels
