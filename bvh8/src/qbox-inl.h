#pragma once
// The quantized node test (qnode.h) for the xsimd kernels: each plane's N
// bytes widened to floats and dequantized (origin + q * step, the product
// exact), then the conservative slab test of box8-inl.h on that box, so the
// mask and entry distances are, lane for lane, those of the scalar
// intersect_box on QBoxN::get(i). Include only from src/avx2 and src/avx512
// translation units (through simd_kernels-inl.h).
#include <cstring>

#include "simd/box8-inl.h"
#include "simdbvh/bvh8/qnode.h"

namespace simdbvh::simd {

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

// Lanes [lane0, lane0 + W) of a QBoxN, as box_lanes for a BoxN (the valid
// slots are masked by the caller).
template <class L, int N, class Arch>
SIMDBVH_FORCE_INLINE std::uint32_t qbox_lanes(const RayPack<Arch>& r, const QBoxN<N>& b, int lane0,
                                              const Batch<L>& tmax, Batch<L>& tnear) {
    using B = Batch<L>;
    const std::uint8_t* base = b.q + lane0;
    const B sx(b.scale(0)), sy(b.scale(1)), sz(b.scale(2));
    const B gx(b.origin[0]), gy(b.origin[1]), gz(b.origin[2]);
    // RayPack's plane offsets address a Box8 (planes 32 bytes apart); a QBoxN's planes are N bytes apart.
    auto plane = [&](std::uint32_t box8_offset, const B& step, const B& origin) {
        return xsimd::fma(load_u8<L>(base + (box8_offset / 32u) * std::uint32_t(N)), step, origin);
    };
    const B t0x = (plane(r.near_x, sx, gx) - r.ox) * r.rdx, t1x = (plane(r.far_x, sx, gx) - r.ox) * r.rdx;
    const B t0y = (plane(r.near_y, sy, gy) - r.oy) * r.rdy, t1y = (plane(r.far_y, sy, gy) - r.oy) * r.rdy;
    const B t0z = (plane(r.near_z, sz, gz) - r.oz) * r.rdz, t1z = (plane(r.far_z, sz, gz) - r.oz) * r.rdz;
    const B tn = max_ps<L>(t0x, max_ps<L>(t0y, max_ps<L>(t0z, B(r.tmin))));
    const B tf = min_ps<L>(t1x, min_ps<L>(t1y, min_ps<L>(t1z, tmax))) * B(kFarWiden) + B(r.far_slack);
    tnear = tn;
    return bits<L>(tn <= tf);
}

// One ray against the N boxes of a quantized node, as intersect_boxn.
template <class Arch, int N>
SIMDBVH_FORCE_INLINE std::uint32_t intersect_qboxn(const RayPack<Arch>& r, const QBoxN<N>& b, float tmax,
                                                   float* entries) {
    using X4 = typename Lanes<Arch>::X4;
    using X16 = typename Lanes<Arch>::X16;
    std::uint32_t m;
    if constexpr (N == 8) {
        Batch<Arch> tn;
        m = qbox_lanes<Arch, 8>(r, b, 0, Batch<Arch>(tmax), tn);
        tn.store_aligned(entries);
    } else if constexpr (N == 4) {
        Batch<X4> tn;
        m = qbox_lanes<X4, 4>(r, b, 0, Batch<X4>(tmax), tn);
        tn.store_aligned(entries);
    } else if constexpr (!std::is_void_v<X16>) {
        Batch<X16> tn;
        m = qbox_lanes<X16, 16>(r, b, 0, Batch<X16>(tmax), tn);
        tn.store_aligned(entries);
    } else {
        const Batch<Arch> t(tmax);
        Batch<Arch> lo, hi;
        const std::uint32_t mlo = qbox_lanes<Arch, 16>(r, b, 0, t, lo);
        const std::uint32_t mhi = qbox_lanes<Arch, 16>(r, b, 8, t, hi);
        lo.store_aligned(entries);
        hi.store_aligned(entries + 8);
        m = mlo | (mhi << 8);
    }
    return m & b.valid;
}

}  // namespace simdbvh::simd
