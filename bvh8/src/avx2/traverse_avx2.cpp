// BVH8 traversal, AVX2 + FMA build of traverse-inl.h (xsimd::avx2).
#include "simd_kernels-inl.h"
#include "traverse-inl.h"
#include "traverse.h"

namespace simdbvh::bvh8::avx2 {

using K = SimdKernels<simd::Avx2>;

template <int N>
SIMDBVH_FLATTEN void intersect(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits,
                               const TraceOptions& o) {
    detail::trace<K, false>(bvh, rays, hits, o);
}
template <int N>
SIMDBVH_FLATTEN void occluded(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits,
                              const TraceOptions& o) {
    detail::trace<K, true>(bvh, rays, hits, o);
}
SIMDBVH_WIDE_ISA_INSTANCES(8)

}  // namespace simdbvh::bvh8::avx2
