#pragma once
// The xsimd kernels (kernels/src/simd) behind traverse-inl.h's K interface:
// the N-wide node test and the 8-wide Tri8 tests. Include only from src/avx2
// and src/avx512 translation units.
#include "qbox-inl.h"
#include "simd/box8-inl.h"
#include "simd/tri8-inl.h"

namespace simdbvh::bvh8 {

template <class Arch>
struct SimdKernels {
    using RayData = simd::RayPack<Arch>;
    static SIMDBVH_FORCE_INLINE void pack(RayData& d, const PreparedRay& r, const Ray& src) {
        simd::pack_ray_into<Arch>(d, r, &src);
    }
    template <int N>
    static SIMDBVH_FORCE_INLINE std::uint32_t box(const RayData& r, const BoxN<N>& b, float tmax, float* entries) {
        return simd::intersect_boxn<Arch, N>(r, b, tmax, entries);
    }
    template <int N>
    static SIMDBVH_FORCE_INLINE std::uint32_t box(const RayData& r, const QBoxN<N>& b, float tmax, float* entries) {
        return simd::intersect_qboxn<Arch, N>(r, b, tmax, entries);
    }
    template <TriangleTest kTest>
    static SIMDBVH_FORCE_INLINE void closest(const RayData& r, const Tri8& b, Hit& best) {
        simd::intersect_tri8<Arch, kTest>(r, b, best);
    }
    template <TriangleTest kTest>
    static SIMDBVH_FORCE_INLINE bool any(const RayData& r, const Tri8& b, float tmax, Hit& hit) {
        return simd::occluded_tri8<Arch, kTest>(r, b, tmax, hit);
    }
};

}  // namespace simdbvh::bvh8
