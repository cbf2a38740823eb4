#pragma once
// The xsimd kernels (kernels/src/simd) behind traverse-inl.h's K interface:
// the N-wide node test and the 8-wide Tri8 tests. Include only from src/avx2
// and src/avx512 translation units.
#include <limits>

#include "qbox-inl.h"
#include "simd/box8-inl.h"
#include "simd/prepare8-inl.h"
#include "simd/tri8-inl.h"

namespace simdbvh::bvh8 {

template <class Arch>
struct SimdKernels {
    using RayData = simd::RayPack<Arch>;
    static SIMDBVH_FORCE_INLINE void pack(RayData& d, const PreparedRay& r, const Ray& src) {
        simd::pack_ray_into<Arch>(d, r, &src);
    }
    // Rays [0, g) (g <= 8) prepared and tested against the tree's bounds in vector lanes (simd/prepare8-inl.h).
    static SIMDBVH_FORCE_INLINE std::uint32_t prepare8(const Ray* rays, std::size_t g, const Aabb* root,
                                                       PreparedRay* out, std::uint32_t* valid) {
        return simd::prepare8<Arch>(rays, g, root, out, valid);
    }
    template <int N>
    static SIMDBVH_FORCE_INLINE std::uint32_t box(const RayData& r, const BoxN<N>& b, float tmax, float* entries) {
        return simd::intersect_boxn<Arch, N>(r, b, tmax, entries);
    }
    template <int N>
    static SIMDBVH_FORCE_INLINE std::uint32_t box(const RayData& r, const QBoxN<N>& b, float tmax, float* entries) {
        return simd::intersect_qboxn<Arch, N>(r, b, tmax, entries);
    }
    // Streams (stream-inl.h): the child hit masks of up to 32 rays at one
    // node, one byte per ray and group of 8 children, transposed into one
    // 32-bit ray mask per child with a shift and a byte movemask per child.
    static constexpr bool kStreams = true;
    struct StreamMasks {
        alignas(32) std::uint8_t group[2][32];  // [child / 8][ray]: bit child % 8
    };
    static SIMDBVH_FORCE_INLINE void stream_clear(StreamMasks& m) {
        for (auto& g : m.group) _mm256_store_si256(reinterpret_cast<__m256i*>(g), _mm256_setzero_si256());
    }
    template <int N>
    static SIMDBVH_FORCE_INLINE void stream_set(StreamMasks& m, int ray, std::uint32_t hit_children) {
        m.group[0][ray] = static_cast<std::uint8_t>(hit_children);
        if constexpr (N > 8) m.group[1][ray] = static_cast<std::uint8_t>(hit_children >> 8);
    }
    // rays_of[i] for each child i in `children` (the union of the rays' masks);
    // leaves `m` cleared for the next node.
    template <int N>
    static SIMDBVH_FORCE_INLINE void stream_rays(StreamMasks& m, std::uint32_t children, std::uint32_t* rays_of) {
        static_assert(N == 4 || N == 8 || N == 16, "node widths: 4, 8, 16");
        for (int g = 0; g < (N + 7) / 8; ++g) {
            __m256i* p = reinterpret_cast<__m256i*>(m.group[g]);
            const __m256i v = _mm256_load_si256(p);
            for (std::uint32_t q = (children >> (8 * g)) & 0xffu; q != 0; q &= q - 1) {
                const int i = __builtin_ctz(q);  // bit i of every byte to its top bit
                rays_of[8 * g + i] = static_cast<std::uint32_t>(
                    _mm256_movemask_epi8(_mm256_sll_epi16(v, _mm_cvtsi32_si128(7 - i))));
            }
            _mm256_store_si256(p, _mm256_setzero_si256());
        }
    }
    // Nearest-first streams: per child, the smallest entry distance over the
    // rays that hit it, kept in registers over a node's rays (N rounded up to
    // 8 lanes).
    template <int N>
    struct StreamNearest {
        __m256 lanes[(N + 7) / 8];
    };
    template <int N>
    static SIMDBVH_FORCE_INLINE StreamNearest<N> stream_nearest_init() {
        StreamNearest<N> a;
        for (auto& l : a.lanes) l = _mm256_set1_ps(std::numeric_limits<float>::infinity());
        return a;
    }
    // a[i] = min(a[i], entries[i]) for each child i in `hit_children` (entries
    // are ordered there; 64-byte aligned, N rounded up to 8 floats).
    template <int N>
    static SIMDBVH_FORCE_INLINE void stream_nearest_min(StreamNearest<N>& a, const float* entries,
                                                        std::uint32_t hit_children) {
        const __m256i lane_bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
        for (int g = 0; g < (N + 7) / 8; ++g) {
            const __m256i h = _mm256_set1_epi32(int((hit_children >> (8 * g)) & 0xffu));
            const __m256 m = _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(h, lane_bits), lane_bits));
            a.lanes[g] = _mm256_blendv_ps(a.lanes[g], _mm256_min_ps(a.lanes[g], _mm256_load_ps(entries + 8 * g)), m);
        }
    }
    template <int N>
    static SIMDBVH_FORCE_INLINE void stream_nearest_store(const StreamNearest<N>& a, float* out) {
        for (int g = 0; g < (N + 7) / 8; ++g) _mm256_store_ps(out + 8 * g, a.lanes[g]);
    }
    // The rays (of 32) whose cull bound is at or beyond `entry`: a stack entry still in front of them.
    static SIMDBVH_FORCE_INLINE std::uint32_t stream_front(const float* cull, float entry) {
        const __m256 e = _mm256_set1_ps(entry);
        std::uint32_t m = 0;
        for (int k = 0; k < 4; ++k)
            m |= std::uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(e, _mm256_load_ps(cull + 8 * k), _CMP_LE_OQ))) << (8 * k);
        return m;
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
