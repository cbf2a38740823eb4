// BVH8 traversal, AVX-512 (VL, 8 x float) build of traverse-inl.h (simd::Avx512).
#include "simd_kernels-inl.h"
#include "traverse-inl.h"
#include "traverse.h"

namespace simdbvh::bvh8::avx512 {

using K = SimdKernels<simd::Avx512>;

SIMDBVH_FLATTEN void intersect(const Bvh8& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    detail::trace<K, false>(bvh, rays, hits, o);
}
SIMDBVH_FLATTEN void occluded(const Bvh8& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& o) {
    detail::trace<K, true>(bvh, rays, hits, o);
}

}  // namespace simdbvh::bvh8::avx512
