#pragma once
// SSE2, the x86-64 baseline the ISA-neutral code (no dispatch, no AVX) runs 4
// lanes at a time with: the binned SAH's bins, the wide trees' refit, inside
// and closest-point bounds, the scalar sphere roots. On x86-64 this is
// <emmintrin.h>. On any other processor it is the same operations, each with
// the rounding, NaN and out-of-range rules of its SSE instruction (min/max
// return the second operand unless the first compares less/greater, the
// conversion gives INT_MIN out of range), written per lane on GCC vector
// types, so those paths give the x86 bits. Only the operations used are here.
#if defined(__x86_64__)
#include <emmintrin.h>
#else
#include <cmath>
#include <cstdint>
#include <cstring>

typedef float __m128 __attribute__((vector_size(16), aligned(16)));
typedef double __m128d __attribute__((vector_size(16), aligned(16)));
typedef long long __m128i __attribute__((vector_size(16), aligned(16)));

#define _MM_SHUFFLE(z, y, x, w) (((z) << 6) | ((y) << 4) | ((x) << 2) | (w))

namespace simdbvh::kernels::simd::sse2 {
using F4 = float __attribute__((vector_size(16)));
using I4 = std::int32_t __attribute__((vector_size(16)));
inline I4 bits(__m128 a) {
    I4 r;
    std::memcpy(&r, &a, 16);
    return r;
}
inline __m128 floats(I4 a) {
    __m128 r;
    std::memcpy(&r, &a, 16);
    return r;
}
}  // namespace simdbvh::kernels::simd::sse2

inline __m128 _mm_set1_ps(float a) { return __m128{a, a, a, a}; }
inline __m128 _mm_setr_ps(float a, float b, float c, float d) { return __m128{a, b, c, d}; }
inline __m128 _mm_setzero_ps() { return __m128{0.0f, 0.0f, 0.0f, 0.0f}; }
inline __m128 _mm_load_ps(const float* p) {
    __m128 r;
    std::memcpy(&r, p, 16);
    return r;
}
inline void _mm_store_ps(float* p, __m128 a) { std::memcpy(p, &a, 16); }
inline void _mm_store_si128(__m128i* p, __m128i a) { std::memcpy(p, &a, 16); }
inline __m128 _mm_add_ps(__m128 a, __m128 b) { return a + b; }
inline __m128 _mm_sub_ps(__m128 a, __m128 b) { return a - b; }
inline __m128 _mm_mul_ps(__m128 a, __m128 b) { return a * b; }
inline __m128 _mm_min_ps(__m128 a, __m128 b) {  // minps: a < b ? a : b (b when either is NaN)
    __m128 r;
    for (int i = 0; i < 4; ++i) r[i] = a[i] < b[i] ? a[i] : b[i];
    return r;
}
inline __m128 _mm_max_ps(__m128 a, __m128 b) {  // maxps: a > b ? a : b (b when either is NaN)
    __m128 r;
    for (int i = 0; i < 4; ++i) r[i] = a[i] > b[i] ? a[i] : b[i];
    return r;
}
inline __m128 _mm_cmple_ps(__m128 a, __m128 b) {
    simdbvh::kernels::simd::sse2::I4 m;
    for (int i = 0; i < 4; ++i) m[i] = a[i] <= b[i] ? -1 : 0;
    return simdbvh::kernels::simd::sse2::floats(m);
}
inline __m128 _mm_and_ps(__m128 a, __m128 b) {
    using namespace simdbvh::kernels::simd::sse2;
    return floats(bits(a) & bits(b));
}
inline __m128 _mm_xor_ps(__m128 a, __m128 b) {
    using namespace simdbvh::kernels::simd::sse2;
    return floats(bits(a) ^ bits(b));
}
inline int _mm_movemask_ps(__m128 a) {
    const simdbvh::kernels::simd::sse2::I4 b = simdbvh::kernels::simd::sse2::bits(a);
    int m = 0;
    for (int i = 0; i < 4; ++i) m |= int(std::uint32_t(b[i]) >> 31) << i;
    return m;
}
// shufps: lanes 0-1 from a, 2-3 from b, each chosen by two bits of imm.
inline __m128 _mm_shuffle_ps(__m128 a, __m128 b, int imm) {
    return __m128{a[imm & 3], a[(imm >> 2) & 3], b[(imm >> 4) & 3], b[(imm >> 6) & 3]};
}
// cvttps2dq: truncation; NaN and values out of int32 range give INT32_MIN.
inline __m128i _mm_cvttps_epi32(__m128 a) {
    simdbvh::kernels::simd::sse2::I4 r;
    for (int i = 0; i < 4; ++i) r[i] = (a[i] > -2147483904.0f && a[i] < 2147483648.0f) ? std::int32_t(a[i]) : INT32_MIN;
    __m128i out;
    std::memcpy(&out, &r, 16);
    return out;
}
inline __m128d _mm_sqrt_pd(__m128d a) { return __m128d{std::sqrt(a[0]), std::sqrt(a[1])}; }
#endif
