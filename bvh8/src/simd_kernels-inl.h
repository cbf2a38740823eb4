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
    // Packets (packet-inl.h): detail::kPacket rays, one per lane of an Arch batch.
    static constexpr bool kPackets = true;
    struct Packet {
        simd::Batch<Arch> ox, oy, oz, rx, ry, rz, tmin, slack, cull;
    };
    template <class Lanes>
    static SIMDBVH_FORCE_INLINE void packet_load(Packet& p, const Lanes& l) {
        using B = simd::Batch<Arch>;
        static_assert(B::size == sizeof(l.ox) / sizeof(float));
        p.ox = B::load_aligned(l.ox), p.oy = B::load_aligned(l.oy), p.oz = B::load_aligned(l.oz);
        p.rx = B::load_aligned(l.rx), p.ry = B::load_aligned(l.ry), p.rz = B::load_aligned(l.rz);
        p.tmin = B::load_aligned(l.tmin), p.slack = B::load_aligned(l.slack), p.cull = B::load_aligned(l.cull);
    }
    template <class Lanes>
    static SIMDBVH_FORCE_INLINE void packet_cull(Packet& p, const Lanes& l) {
        p.cull = simd::Batch<Arch>::load_aligned(l.cull);
    }
    // One box (its near and far planes for the packet's octant) against the
    // packet: box8-inl.h's slab_lanes per lane, with the box's planes
    // broadcast instead of the ray's values, so each lane's entry and hit bit
    // are those of that ray's own node test. Returns the hit rays among
    // `live`; `entries` receives the lanes' entry distances when there are any.
    static SIMDBVH_FORCE_INLINE std::uint32_t packet_box(const Packet& p, float nx, float fx, float ny, float fy,
                                                         float nz, float fz, std::uint32_t live, float* entries) {
        using B = simd::Batch<Arch>;
        const B t0x = (B(nx) - p.ox) * p.rx, t1x = (B(fx) - p.ox) * p.rx;
        const B t0y = (B(ny) - p.oy) * p.ry, t1y = (B(fy) - p.oy) * p.ry;
        const B t0z = (B(nz) - p.oz) * p.rz, t1z = (B(fz) - p.oz) * p.rz;
        const B tn = simd::max_ps<Arch>(t0x, simd::max_ps<Arch>(t0y, simd::max_ps<Arch>(t0z, p.tmin)));
        const B tf = simd::min_ps<Arch>(t1x, simd::min_ps<Arch>(t1y, simd::min_ps<Arch>(t1z, p.cull))) * B(kFarWiden) +
                     p.slack;
        const std::uint32_t h = simd::bits<Arch>(tn <= tf) & live;
        if (h != 0) tn.store_aligned(entries);
        return h;
    }
    // The rays whose cull bound is at or beyond `entry` (a stack entry still in front of them).
    static SIMDBVH_FORCE_INLINE std::uint32_t packet_front(const Packet& p, float entry) {
        return simd::bits<Arch>(simd::Batch<Arch>(entry) <= p.cull);
    }
    // Any-hit streams (stream-inl.h): the child hit masks of up to 32 rays at
    // one node, one byte per ray and group of 8 children, transposed into one
    // 32-bit ray mask per child with a shift and a byte movemask per child.
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
