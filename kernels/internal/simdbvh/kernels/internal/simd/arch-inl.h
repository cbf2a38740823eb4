#pragma once
// Arch types and helpers shared by the Arch-templated SIMD kernels
// (box8-inl.h, tri8-inl.h). Include only from per-ISA translation units
// (src/avx2/*.cpp, src/avx512/*.cpp of any module), never from public headers.
//
// Arch tags:
//   simdbvh::kernels::simd::Avx2   = xsimd::avx2            (src/avx2/ files: -mavx2 -mfma ...)
//   simdbvh::kernels::simd::Avx512 = simd::avx512vl_ymm     (src/avx512/ files: + AVX-512F/VL/DQ/BW/CD)
// Avx512 is the same 8 x float (ymm) batch as avx2, but a distinct type: every
// xsimd template instantiated for it gets its own mangled name, so the linker
// can never merge an AVX-512-encoded copy with the AVX2 one (a silent SIGILL on
// AVX2-only CPUs). The compiler emits EVEX encodings and uses ymm16-31 there.
//
// Node batches of other widths (box8-inl.h, intersect_boxn), distinct per ISA
// for the same reason: Lanes<Arch>::X4 is a 4 x float (xmm) batch,
// Lanes<Arch>::X16 a 16 x float (zmm) batch on AVX-512, void on AVX2 (two
// 8-wide halves instead).
#include <immintrin.h>

#include <cstdint>
#include <xsimd/xsimd.hpp>

// Kernels are force-inlined into the per-ISA loop that calls them; callers
// should also mark their per-ISA entry functions SIMDBVH_FLATTEN so no xsimd
// helper is left out of line (see the ODR check in tests/kernels).
#define SIMDBVH_FORCE_INLINE inline __attribute__((always_inline))
#define SIMDBVH_FLATTEN __attribute__((flatten))

#if !defined(__AVX2__) || !defined(__FMA__)
#error "simd/*-inl.h must be compiled with the AVX2 (or AVX-512) per-ISA flags"
#endif

namespace simdbvh::kernels::simd {

using Avx2 = xsimd::avx2;

#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512DQ__) && defined(__AVX512BW__)
struct avx512vl_ymm : xsimd::avx2 {
    static constexpr bool supported() noexcept { return true; }
    static constexpr bool available() noexcept { return true; }
    static constexpr char const* name() noexcept { return "avx512vl_ymm"; }
};
using Avx512 = avx512vl_ymm;
#endif

struct avx2_xmm : xsimd::sse4_2 {
    static constexpr bool supported() noexcept { return true; }
    static constexpr bool available() noexcept { return true; }
    static constexpr char const* name() noexcept { return "avx2_xmm"; }
};
#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512DQ__) && defined(__AVX512BW__)
struct avx512vl_xmm : xsimd::sse4_2 {
    static constexpr bool supported() noexcept { return true; }
    static constexpr bool available() noexcept { return true; }
    static constexpr char const* name() noexcept { return "avx512vl_xmm"; }
};
struct avx512_zmm : xsimd::avx512bw {
    static constexpr bool supported() noexcept { return true; }
    static constexpr bool available() noexcept { return true; }
    static constexpr char const* name() noexcept { return "avx512_zmm"; }
};
#endif

template <class Arch>
struct Lanes;
template <>
struct Lanes<Avx2> {
    using X4 = avx2_xmm;
    using X16 = void;
};
#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512DQ__) && defined(__AVX512BW__)
template <>
struct Lanes<Avx512> {
    using X4 = avx512vl_xmm;
    using X16 = avx512_zmm;
};
#endif

template <class Arch>
using Batch = xsimd::batch<float, Arch>;
template <class Arch>
using Mask = xsimd::batch_bool<float, Arch>;

// W lanes -> W bits (lane i -> bit i), W = 4 (xmm), 8 (ymm), 16 (zmm opmask).
template <class Arch>
SIMDBVH_FORCE_INLINE std::uint32_t bits(const Mask<Arch>& m) {
    constexpr std::size_t kW = Batch<Arch>::size;
    static_assert(kW == 4 || kW == 8 || kW == 16, "4, 8 or 16 x float batches");
    if constexpr (kW == 16) {
        return static_cast<std::uint32_t>(static_cast<__mmask16>(m));
    } else if constexpr (kW == 8) {
        return static_cast<std::uint32_t>(_mm256_movemask_ps(static_cast<__m256>(m)));
    } else {
        return static_cast<std::uint32_t>(_mm_movemask_ps(static_cast<__m128>(m)));
    }
}

// Aligned load of 8 floats at `base + byte_offset` (Embree-style plane
// selection: the offset is chosen once per ray).
template <class Arch>
SIMDBVH_FORCE_INLINE Batch<Arch> load8(const void* base, std::uint32_t byte_offset) {
    return Batch<Arch>::load_aligned(reinterpret_cast<const float*>(static_cast<const char*>(base) + byte_offset));
}

}  // namespace simdbvh::kernels::simd

namespace xsimd::types {
XSIMD_DECLARE_SIMD_REGISTER_ALIAS(simdbvh::kernels::simd::avx2_xmm, sse4_2);
#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512DQ__) && defined(__AVX512BW__)
XSIMD_DECLARE_SIMD_REGISTER_ALIAS(simdbvh::kernels::simd::avx512vl_ymm, avx2);
XSIMD_DECLARE_SIMD_REGISTER_ALIAS(simdbvh::kernels::simd::avx512vl_xmm, sse4_2);
XSIMD_DECLARE_SIMD_REGISTER_ALIAS(simdbvh::kernels::simd::avx512_zmm, avx512bw);
template <class T>
struct get_bool_simd_register<T, simdbvh::kernels::simd::avx512_zmm> {
    using type = simd_avx512_bool_register<T>;
};
#endif
}  // namespace xsimd::types
