#pragma once
// Internal: the per-ISA wide BVH traversals. Each lives in its own translation
// unit (src/scalar, src/avx2, src/avx512) and namespace, and instantiates the
// widths it runs; traverse.cpp holds the one switch on the ISA.
#include <span>

#include "simdbvh/bvh8/bvh8.h"

namespace simdbvh::bvh8 {

#define SIMDBVH_WIDE_ISA_DECLS                                                                                     \
    template <int N>                                                                                               \
    void intersect(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o);     \
    template <int N>                                                                                               \
    void occluded(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o);

namespace scalar { SIMDBVH_WIDE_ISA_DECLS }  // src/scalar/traverse_scalar.cpp
namespace avx2 { SIMDBVH_WIDE_ISA_DECLS }    // src/avx2/traverse_avx2.cpp
namespace avx512 { SIMDBVH_WIDE_ISA_DECLS }  // src/avx512/traverse_avx512.cpp

#undef SIMDBVH_WIDE_ISA_DECLS

// One line per width in a per-ISA file: the two entry points of BvhN<N>.
#define SIMDBVH_WIDE_ISA_INSTANCES(N)                                                                               \
    template void intersect<N>(const BvhN<N>&, std::span<const Ray>, std::span<Hit>, const TraceOptions&);       \
    template void occluded<N>(const BvhN<N>&, std::span<const Ray>, std::span<Hit>, const TraceOptions&);

}  // namespace simdbvh::bvh8
