#pragma once
// The xsimd kernels (kernels/src/simd) behind traverse-inl.h's K interface:
// the N-wide node test and the 8-wide Tri8 tests. Include only from src/avx2
// and src/avx512 translation units.
#include <limits>

#include "simdbvh/bvh8/internal/qbox-inl.h"
#include "simdbvh/kernels/internal/simd/box8-inl.h"
#include "simdbvh/kernels/internal/simd/prepare8-inl.h"
#include "simdbvh/kernels/internal/simd/tri8-inl.h"

namespace simdbvh::bvh8 {

template <class Arch>
struct SimdKernels {
    using RayData = kernels::simd::RayPack<Arch>;
    static SIMDBVH_FORCE_INLINE void pack(RayData& d, const PreparedRay& r, const Ray& src) {
        kernels::simd::pack_ray_into<Arch>(d, r, &src);
    }
    // Rays [0, g) (g <= 8) prepared and tested against the tree's bounds in vector lanes (simd/prepare8-inl.h).
    static SIMDBVH_FORCE_INLINE std::uint32_t prepare8(const Ray* rays, std::size_t g, const Aabb* root,
                                                       PreparedRay* out, std::uint32_t* valid) {
        return kernels::simd::prepare8<Arch>(rays, g, root, out, valid);
    }
    template <int N>
    static SIMDBVH_FORCE_INLINE std::uint32_t box(const RayData& r, const BoxN<N>& b, float tmax, float* entries) {
        return kernels::simd::intersect_boxn<Arch, N>(r, b, tmax, entries);
    }
    template <int N>
    static SIMDBVH_FORCE_INLINE std::uint32_t box(const RayData& r, const QBoxN<N>& b, float tmax, float* entries) {
        return kernels::simd::intersect_qboxn<Arch, N>(r, b, tmax, entries);
    }
    // Streams (stream-inl.h): per child of the node, the rays (of up to 32,
    // one bit each) that hit it and their smallest entry distance, gathered
    // in vector lanes (N rounded up to 8) while the node's rays are tested:
    // each ray ORs its bit into, and mins its entry into, the lanes of the
    // children it hits (on AVX-512 one mask register does both).
    static constexpr bool kStreams = true;
    template <int N>
    struct StreamAcc {
        __m256i rays[(N + 7) / 8];
        __m256 nearest[(N + 7) / 8];
    };
    template <int N>
    static SIMDBVH_FORCE_INLINE StreamAcc<N> stream_init() {
        static_assert(N == 4 || N == 8 || N == 16, "node widths: 4, 8, 16");
        StreamAcc<N> a;
        for (auto& l : a.rays) l = _mm256_setzero_si256();
        for (auto& l : a.nearest) l = _mm256_set1_ps(std::numeric_limits<float>::infinity());
        return a;
    }
    // Ray `ray` hit the children in `hit_children`, entering them at
    // entries[i] (64-byte aligned, N rounded up to 8 floats).
    template <int N>
    static SIMDBVH_FORCE_INLINE void stream_add(StreamAcc<N>& a, int ray, std::uint32_t hit_children,
                                                const float* entries) {
        const __m256i bit = _mm256_set1_epi32(int(1u << ray));
        for (int g = 0; g < (N + 7) / 8; ++g) {
            const __m256 e = _mm256_load_ps(entries + 8 * g);
#if defined(__AVX512VL__)
            const __mmask8 k = static_cast<__mmask8>(hit_children >> (8 * g));
            a.rays[g] = _mm256_mask_or_epi32(a.rays[g], k, a.rays[g], bit);
            a.nearest[g] = _mm256_mask_min_ps(a.nearest[g], k, a.nearest[g], e);
#else
            const __m256i lane_bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
            const __m256i h = _mm256_set1_epi32(int((hit_children >> (8 * g)) & 0xffu));
            const __m256i m = _mm256_cmpeq_epi32(_mm256_and_si256(h, lane_bits), lane_bits);
            a.rays[g] = _mm256_or_si256(a.rays[g], _mm256_and_si256(m, bit));
            a.nearest[g] = _mm256_blendv_ps(a.nearest[g], _mm256_min_ps(a.nearest[g], e), _mm256_castsi256_ps(m));
#endif
        }
    }
    // rays_of[i] and near_of[i] per child (N rounded up to 8 each).
    template <int N>
    static SIMDBVH_FORCE_INLINE void stream_store(const StreamAcc<N>& a, std::uint32_t* rays_of, float* near_of) {
        for (int g = 0; g < (N + 7) / 8; ++g) {
            _mm256_storeu_si256(reinterpret_cast<__m256i*>(rays_of + 8 * g), a.rays[g]);
            _mm256_storeu_ps(near_of + 8 * g, a.nearest[g]);
        }
    }
    // The rays (of 32) whose cull bound is at or beyond `entry`: a stack entry still in front of them.
    static SIMDBVH_FORCE_INLINE std::uint32_t stream_front(const float* cull, float entry) {
        const __m256 e = _mm256_set1_ps(entry);
        std::uint32_t m = 0;
        for (int k = 0; k < 4; ++k)
            m |= std::uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(e, _mm256_load_ps(cull + 8 * k), _CMP_LE_OQ)))
                 << (8 * k);
        return m;
    }
    template <TriangleTest kTest>
    static SIMDBVH_FORCE_INLINE void closest(const RayData& r, const Tri8& b, Hit& best) {
        kernels::simd::intersect_tri8<Arch, kTest>(r, b, best);
    }
    template <TriangleTest kTest>
    static SIMDBVH_FORCE_INLINE bool any(const RayData& r, const Tri8& b, float tmax, Hit& hit) {
        return kernels::simd::occluded_tri8<Arch, kTest>(r, b, tmax, hit);
    }
};

}  // namespace simdbvh::bvh8
