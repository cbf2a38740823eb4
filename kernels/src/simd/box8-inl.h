#pragma once
// One ray against a Box8 (8 boxes): the conservative slab test of box.h
// (Ize 2013), bit for bit: same near/far choice, (plane - org) * rdir, the
// NaN-discarding max_ps/min_ps order, far bound widened by kFarWiden.
#include <cstdint>
#include <type_traits>

#include "simd/ray-inl.h"

namespace simdbvh::simd {

// vec.h max_ps(a, b) = a > b ? a : b and min_ps(a, b) = a < b ? a : b: `a` may
// be NaN, the result is then `b`. That is exactly x86 maxps/minps with `a` as
// the first operand (second operand returned on NaN or +-0 ties), which
// xsimd::max/min emit for avx/avx2; GCC does not commute them without
// -ffinite-math-only. The tests check NaN and +-0 slab values bit for bit.
template <class Arch>
SIMDBVH_FORCE_INLINE Batch<Arch> max_ps(const Batch<Arch>& a, const Batch<Arch>& b) {
    static_assert(std::is_base_of_v<xsimd::avx, Arch>, "maxps operand order: check the arch's max kernel");
    return xsimd::max(a, b);
}
template <class Arch>
SIMDBVH_FORCE_INLINE Batch<Arch> min_ps(const Batch<Arch>& a, const Batch<Arch>& b) {
    static_assert(std::is_base_of_v<xsimd::avx, Arch>, "minps operand order: check the arch's min kernel");
    return xsimd::min(a, b);
}

// Returns the 8-bit hit mask (bit i: box i overlaps [tmin, tmax]); `tnear`
// receives the 8 entry distances (meaningful in hit lanes). Empty slots
// (lo = +inf, hi = -inf) never hit.
template <class Arch>
SIMDBVH_FORCE_INLINE std::uint32_t intersect_box8(const RayPack<Arch>& r, const Box8& b, const Batch<Arch>& tmax,
                                                  Batch<Arch>& tnear) {
    using B = Batch<Arch>;
    const B t0x = (load8<Arch>(&b, r.near_x) - r.ox) * r.rdx, t1x = (load8<Arch>(&b, r.far_x) - r.ox) * r.rdx;
    const B t0y = (load8<Arch>(&b, r.near_y) - r.oy) * r.rdy, t1y = (load8<Arch>(&b, r.far_y) - r.oy) * r.rdy;
    const B t0z = (load8<Arch>(&b, r.near_z) - r.oz) * r.rdz, t1z = (load8<Arch>(&b, r.far_z) - r.oz) * r.rdz;
    const B tn = max_ps<Arch>(t0x, max_ps<Arch>(t0y, max_ps<Arch>(t0z, r.tmin)));
    const B tf = min_ps<Arch>(t1x, min_ps<Arch>(t1y, min_ps<Arch>(t1z, tmax))) * B(kFarWiden);
    tnear = tn;
    return bits<Arch>(tn <= tf);
}

// Convenience form: scalar tmax, entries stored to 8 floats.
template <class Arch>
SIMDBVH_FORCE_INLINE std::uint32_t intersect_box8(const RayPack<Arch>& r, const Box8& b, float tmax, float* entries) {
    Batch<Arch> tn;
    const std::uint32_t m = intersect_box8<Arch>(r, b, Batch<Arch>(tmax), tn);
    tn.store_unaligned(entries);
    return m;
}

}  // namespace simdbvh::simd
