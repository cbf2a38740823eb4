#pragma once
// Arch types and helpers shared by the Arch-templated SIMD kernels
// (box8-inl.h, tri8-inl.h). Include only from per-ISA translation units
// (src/avx2/*.cpp, src/avx512/*.cpp of any module), never from public headers.
//
// Arch tags:
//   simdbvh::simd::Avx2   = xsimd::avx2            (src/avx2/ files: -mavx2 -mfma ...)
//   simdbvh::simd::Avx512 = simd::avx512vl_ymm     (src/avx512/ files: + AVX-512F/VL/DQ/BW/CD)
// Avx512 is the same 8 x float (ymm) batch as avx2, but a distinct type: every
// xsimd template instantiated for it gets its own mangled name, so the linker
// can never merge an AVX-512-encoded copy with the AVX2 one (a silent SIGILL on
// AVX2-only CPUs). The compiler emits EVEX encodings and uses ymm16-31 there.
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

namespace simdbvh::simd {

using Avx2 = xsimd::avx2;

#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512DQ__) && defined(__AVX512BW__)
struct avx512vl_ymm : xsimd::avx2 {
    static constexpr bool supported() noexcept { return true; }
    static constexpr bool available() noexcept { return true; }
    static constexpr char const* name() noexcept { return "avx512vl_ymm"; }
};
using Avx512 = avx512vl_ymm;
#endif

template <class Arch>
using Batch = xsimd::batch<float, Arch>;
template <class Arch>
using Mask = xsimd::batch_bool<float, Arch>;

// 8 lanes -> 8 bits (lane i -> bit i).
template <class Arch>
SIMDBVH_FORCE_INLINE std::uint32_t bits(const Mask<Arch>& m) {
    static_assert(Batch<Arch>::size == 8, "the 8-wide kernels need an 8 x float batch");
    return static_cast<std::uint32_t>(_mm256_movemask_ps(static_cast<__m256>(m)));
}

// Aligned load of 8 floats at `base + byte_offset` (Embree-style plane
// selection: the offset is chosen once per ray).
template <class Arch>
SIMDBVH_FORCE_INLINE Batch<Arch> load8(const void* base, std::uint32_t byte_offset) {
    return Batch<Arch>::load_aligned(
        reinterpret_cast<const float*>(static_cast<const char*>(base) + byte_offset));
}

}  // namespace simdbvh::simd

#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512DQ__) && defined(__AVX512BW__)
namespace xsimd::types {
XSIMD_DECLARE_SIMD_REGISTER_ALIAS(simdbvh::simd::avx512vl_ymm, avx2);
}
#endif
