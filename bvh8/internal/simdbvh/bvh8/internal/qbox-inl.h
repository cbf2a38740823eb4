#pragma once
// The quantized node test (qnode.h) for the xsimd kernels: each plane's N
// bytes widened to floats and dequantized (origin + q * step, the product
// exact), then the conservative slab test of box8-inl.h on that box, so the
// mask and entry distances are, lane for lane, those of the scalar
// intersect_box on QBoxN::get(i). Include only from src/avx2 and src/avx512
// translation units (through simd_kernels-inl.h).
#include <cstring>

#include "simdbvh/kernels/internal/simd/box8-inl.h"
#include "simdbvh/bvh8/qnode.h"

namespace simdbvh::kernels::simd {

// W bytes at p as W floats, W = the width of batch arch L (4, 8 or 16).
template <class L>
SIMDBVH_FORCE_INLINE Batch<L> load_u8(const std::uint8_t* p) {
    constexpr std::size_t W = Batch<L>::size;
    if constexpr (W == 4) {
        int v;
        std::memcpy(&v, p, 4);
        return Batch<L>(_mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(v))));
    } else if constexpr (W == 8) {
        return Batch<L>(_mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)))));
    } else {
        static_assert(W == 16);
        return Batch<L>(_mm512_cvtepi32_ps(_mm512_cvtepu8_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)))));
    }
}

// The dequantized planes of a QBoxN's lanes from lane0: origin + q * step,
// the product exact, so fused or not it is QBoxN::plane's value.
template <class L, int N>
struct QBoxPlanes {
    const QBoxN<N>& b;
    int lane0;
    SIMDBVH_FORCE_INLINE Batch<L> get(std::uint32_t box8_offset, int axis) const {
        const std::uint32_t p = box8_offset / 32u;  // RayPack addresses a Box8: planes 32 bytes apart; here N bytes
        return xsimd::fma(load_u8<L>(b.q + p * std::uint32_t(N) + std::uint32_t(lane0)), Batch<L>(b.scale(axis)),
                          Batch<L>(b.origin[axis]));
    }
};

// Lanes [lane0, lane0 + W) of a QBoxN: box_lanes of box8-inl.h for the
// quantized kind (the used slots are masked by intersect_qboxn).
template <class L, int N, class Arch>
SIMDBVH_FORCE_INLINE std::uint32_t box_lanes(const RayPack<Arch>& r, const QBoxN<N>& b, int lane0, const Batch<L>& tmax,
                                             Batch<L>& tnear) {
    return slab_lanes<L>(r, QBoxPlanes<L, N>{b, lane0}, tmax, tnear);
}

// One ray against the N boxes of a quantized node, as intersect_boxn, empty slots masked.
template <class Arch, int N>
SIMDBVH_FORCE_INLINE std::uint32_t intersect_qboxn(const RayPack<Arch>& r, const QBoxN<N>& b, float tmax,
                                                   float* entries) {
    return intersect_boxn<Arch, N>(r, b, tmax, entries) & b.valid;
}

}  // namespace simdbvh::kernels::simd
