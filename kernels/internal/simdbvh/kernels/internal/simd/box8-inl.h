#pragma once
// One ray against the boxes of a BoxN (N = 4, 8, 16; Box8 for the kernels'
// batch entry points): the conservative slab test of box.h (Ize 2013), bit for
// bit: same near/far choice, (plane - org) * rdir, the NaN-discarding
// max_ps/min_ps order, far bound widened by kFarWiden plus the ray's far slack.
#include <cstdint>
#include <type_traits>

#include "simdbvh/kernels/internal/simd/ray-inl.h"

namespace simdbvh::kernels::simd {

// vec.h max_ps(a, b) = a > b ? a : b and min_ps(a, b) = a < b ? a : b: `a` may
// be NaN, the result is then `b`. That is exactly x86 maxps/minps with `a` as
// the first operand (second operand returned on NaN or +-0 ties), which
// xsimd::max/min emit for sse2 (xmm), avx/avx2 (ymm) and avx512f (zmm); GCC
// does not commute them without -ffinite-math-only. The tests check NaN and
// +-0 slab values bit for bit.
template <class Arch>
inline constexpr bool kMaxMinOrderChecked =
    std::is_base_of_v<xsimd::sse2, Arch> || std::is_base_of_v<xsimd::avx, Arch> ||
    std::is_base_of_v<xsimd::avx512f, Arch>;
template <class Arch>
SIMDBVH_FORCE_INLINE Batch<Arch> max_ps(const Batch<Arch>& a, const Batch<Arch>& b) {
    static_assert(kMaxMinOrderChecked<Arch>, "maxps operand order: check the arch's max kernel");
    return xsimd::max(a, b);
}
template <class Arch>
SIMDBVH_FORCE_INLINE Batch<Arch> min_ps(const Batch<Arch>& a, const Batch<Arch>& b) {
    static_assert(kMaxMinOrderChecked<Arch>, "minps operand order: check the arch's min kernel");
    return xsimd::min(a, b);
}

// A plane (lo_x, hi_x, ...) of a BoxN: RayPack's near/far offsets address a
// Box8 (planes 32 bytes apart); a BoxN's planes are 4 * N bytes apart.
template <int N>
SIMDBVH_FORCE_INLINE std::uint32_t plane_offset(std::uint32_t box8_offset) {
    if constexpr (N == 8) return box8_offset;
    else if constexpr (N < 8) return box8_offset / std::uint32_t(8 / N);
    else return box8_offset * std::uint32_t(N / 8);
}
template <class L, int N>
SIMDBVH_FORCE_INLINE Batch<L> load_plane(const void* lanes, std::uint32_t box8_offset) {
    return Batch<L>::load_aligned(
        reinterpret_cast<const float*>(static_cast<const char*>(lanes) + plane_offset<N>(box8_offset)));
}

// The slab test of W lanes (W = the width of batch arch L; the ray pack is
// the Arch one) whose planes `planes.get(box8_offset, axis)` gives, addressed
// by RayPack's Box8 offsets (the axis, 0..2, a constant at each call). Returns W hit bits; `tnear` receives the entry
// distances.
template <class L, class Arch, class Planes>
SIMDBVH_FORCE_INLINE std::uint32_t slab_lanes(const RayPack<Arch>& r, const Planes& planes, const Batch<L>& tmax,
                                              Batch<L>& tnear) {
    using B = Batch<L>;
    const B t0x = (planes.get(r.near_x, 0) - r.ox) * r.rdx, t1x = (planes.get(r.far_x, 0) - r.ox) * r.rdx;
    const B t0y = (planes.get(r.near_y, 1) - r.oy) * r.rdy, t1y = (planes.get(r.far_y, 1) - r.oy) * r.rdy;
    const B t0z = (planes.get(r.near_z, 2) - r.oz) * r.rdz, t1z = (planes.get(r.far_z, 2) - r.oz) * r.rdz;
    const B tn = max_ps<L>(t0x, max_ps<L>(t0y, max_ps<L>(t0z, B(r.tmin))));
    const B tf = min_ps<L>(t1x, min_ps<L>(t1y, min_ps<L>(t1z, tmax))) * B(kFarWiden) + B(r.far_slack);
    tnear = tn;
    return bits<L>(tn <= tf);
}

// The planes of a BoxN's lanes from `base` (the lane0-th float of the box).
template <class L, int N>
struct BoxPlanes {
    const void* base;
    SIMDBVH_FORCE_INLINE Batch<L> get(std::uint32_t box8_offset, int) const {
        return load_plane<L, N>(base, box8_offset);
    }
};

// Lanes [lane0, lane0 + W) of a BoxN against the ray. Overloaded per box kind
// (qbox-inl.h: quantized nodes), for intersect_boxn below.
template <class L, int N, class Arch>
SIMDBVH_FORCE_INLINE std::uint32_t box_lanes(const RayPack<Arch>& r, const BoxN<N>& b, int lane0, const Batch<L>& tmax,
                                             Batch<L>& tnear) {
    return slab_lanes<L>(r, BoxPlanes<L, N>{reinterpret_cast<const char*>(&b) + 4 * lane0}, tmax, tnear);
}

// Returns the 8-bit hit mask (bit i: box i overlaps [tmin, tmax]); `tnear`
// receives the 8 entry distances (meaningful in hit lanes). Empty slots
// (lo = +inf, hi = -inf) never hit.
template <class Arch>
SIMDBVH_FORCE_INLINE std::uint32_t intersect_box8(const RayPack<Arch>& r, const Box8& b, const Batch<Arch>& tmax,
                                                  Batch<Arch>& tnear) {
    return box_lanes<Arch, 8>(r, b, 0, tmax, tnear);
}

// Convenience form: scalar tmax, entries stored to 8 floats.
template <class Arch>
SIMDBVH_FORCE_INLINE std::uint32_t intersect_box8(const RayPack<Arch>& r, const Box8& b, float tmax, float* entries) {
    Batch<Arch> tn;
    const std::uint32_t m = intersect_box8<Arch>(r, b, Batch<Arch>(tmax), tn);
    tn.store_unaligned(entries);
    return m;
}

// One ray against the N boxes of a node (N = 4, 8, 16), the node test of the
// wide BVHs, bit for bit the scalar intersect_box per lane: 4 lanes in one
// xmm batch, 8 in one batch of Arch, 16 in one zmm batch on AVX-512 or two
// 8-lane halves on AVX2. Returns the N-bit hit mask; `entries` (aligned to
// 4 * N bytes) receives the N entry distances. `Box`: a BoxN, or any box kind
// with a box_lanes overload (a QBoxN: qbox-inl.h).
template <class Arch, int N, class Box>
SIMDBVH_FORCE_INLINE std::uint32_t intersect_boxn(const RayPack<Arch>& r, const Box& b, float tmax, float* entries) {
    static_assert(N == 4 || N == 8 || N == 16, "node widths: 4, 8, 16");
    using X4 = typename Lanes<Arch>::X4;
    using X16 = typename Lanes<Arch>::X16;
    if constexpr (N == 8) {
        Batch<Arch> tn;
        const std::uint32_t m = box_lanes<Arch, 8>(r, b, 0, Batch<Arch>(tmax), tn);
        tn.store_aligned(entries);
        return m;
    } else if constexpr (N == 4) {
        Batch<X4> tn;
        const std::uint32_t m = box_lanes<X4, 4>(r, b, 0, Batch<X4>(tmax), tn);
        tn.store_aligned(entries);
        return m;
    } else if constexpr (!std::is_void_v<X16>) {
        Batch<X16> tn;
        const std::uint32_t m = box_lanes<X16, 16>(r, b, 0, Batch<X16>(tmax), tn);
        tn.store_aligned(entries);
        return m;
    } else {
        const Batch<Arch> t(tmax);
        Batch<Arch> lo, hi;
        const std::uint32_t mlo = box_lanes<Arch, 16>(r, b, 0, t, lo);
        const std::uint32_t mhi = box_lanes<Arch, 16>(r, b, 8, t, hi);
        lo.store_aligned(entries);
        hi.store_aligned(entries + 8);
        return mlo | (mhi << 8);
    }
}

}  // namespace simdbvh::kernels::simd
