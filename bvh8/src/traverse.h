#pragma once
// Internal: the per-ISA wide BVH traversals. Traversal<K, N> is defined once
// (traverse-inl.h) and instantiated per ISA and width in its own translation
// unit (src/scalar, src/avx2, src/avx512), each with the kernels of its ISA
// (K = <isa>::Kernels, a distinct type per ISA); traverse.cpp holds the one
// switch on the ISA.
#include <span>

#include "simdbvh/bvh8/bvh8.h"

namespace simdbvh::bvh8 {

namespace scalar { struct Kernels; }  // src/scalar/traverse_scalar.cpp
namespace avx2 { struct Kernels; }    // src/avx2/traverse_avx2.cpp
namespace avx512 { struct Kernels; }  // src/avx512/traverse_avx512.cpp

// Flattened (on the declaration: GCC drops it from an out-of-class template
// member definition), so the whole loop, its kernels and lambdas are one function.
template <class K, int N>
struct Traversal {
    [[gnu::flatten]] static void intersect(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits,
                                           const TraceOptions& o);
    [[gnu::flatten]] static void occluded(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits,
                                          const TraceOptions& o);
};

#define SIMDBVH_WIDE_ISA(isa)                               \
    extern template struct Traversal<isa::Kernels, 4>;     \
    extern template struct Traversal<isa::Kernels, 8>;     \
    extern template struct Traversal<isa::Kernels, 16>;
SIMDBVH_WIDE_ISA(scalar)
SIMDBVH_WIDE_ISA(avx2)
SIMDBVH_WIDE_ISA(avx512)
#undef SIMDBVH_WIDE_ISA

}  // namespace simdbvh::bvh8
