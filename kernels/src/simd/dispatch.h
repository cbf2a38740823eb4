#pragma once
// Internal: the per-ISA implementations behind kernels/batch.h. Each lives in
// its own translation unit (src/scalar, src/avx2, src/avx512), the static
// members of that ISA's Kernels; with_kernels picks one. No intrinsics here.
#include <cstdint>
#include <span>
#include <utility>

#include "simdbvh/kernels/batch.h"
#include "simdbvh/kernels/testing.h"
#include "box_tree_walk-inl.h"
#include "simdbvh/kernels/internal/by_isa.h"

namespace simdbvh::kernels {

namespace detail {
// Records which compiled implementation ran the last batched call on this thread.
void note_isa_used(Isa isa);
}  // namespace detail

namespace scalar {  // src/scalar/kernels_scalar.cpp
struct Kernels {
#include "simd/entry_points.inc"
};
}  // namespace scalar

namespace avx2 {  // src/avx2/kernels_avx2.cpp (x86 only: by_isa never picks it elsewhere)
struct Kernels {
#include "simd/entry_points.inc"
};
}  // namespace avx2

namespace avx512 {  // src/avx512/kernels_avx512.cpp (x86 only)
struct Kernels {
#include "simd/entry_points.inc"
};
}  // namespace avx512

// The kernel set of an ISA: f.template operator()<Set>() with Set one of the
// Kernels structs above, after require(isa) (by_isa.h holds the one switch).
template <class F>
decltype(auto) with_kernels(Isa isa, F&& f) {
    return detail::by_isa<scalar::Kernels, avx2::Kernels, avx512::Kernels>(isa, std::forward<F>(f));
}

}  // namespace simdbvh::kernels
