#pragma once
// Internal: the per-ISA BVH8 traversals. Each lives in its own translation
// unit (src/scalar, src/avx2, src/avx512) and namespace; traverse.cpp holds the
// one switch on the ISA.
#include <span>

#include "simdbvh/bvh8/bvh8.h"

namespace simdbvh::bvh8 {

#define SIMDBVH_BVH8_ISA_DECLS                                                                              \
    void intersect(const Bvh8& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o); \
    void occluded(const Bvh8& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o);

namespace scalar { SIMDBVH_BVH8_ISA_DECLS }  // src/scalar/traverse_scalar.cpp
namespace avx2 { SIMDBVH_BVH8_ISA_DECLS }    // src/avx2/traverse_avx2.cpp
namespace avx512 { SIMDBVH_BVH8_ISA_DECLS }  // src/avx512/traverse_avx512.cpp

#undef SIMDBVH_BVH8_ISA_DECLS

}  // namespace simdbvh::bvh8
