#pragma once
// Internal: per-lane facts about a Tri8 block read in its SoA layout, shared by
// the wide trees' refit (refit.cpp), inside test (inside.cpp) and closest-point
// bounds (point_bounds-inl.h): which lanes hold a triangle, and the triangle
// boxes of lanes i..i+3 with SSE (the x86-64 baseline: no dispatch, no AVX).
#include "simdbvh/kernels/internal/simd/sse2.h"

#include <cstdint>

#include "simdbvh/kernels/soa.h"

namespace simdbvh::detail {

// Bit k set when lane k holds a triangle.
inline std::uint32_t used_lanes(const Tri8& t) {
    std::uint32_t m = 0;
    for (int k = 0; k < kBlockWidth; ++k)
        if (t.prim[k] != kInvalidPrim) m |= 1u << k;
    return m;
}

// The boxes of the triangles in lanes i..i+3 (i a multiple of 4), per axis.
// Empty lanes give meaningless boxes: callers mask them by id. With finite
// vertices min/max agree with fmin/fmax.
struct TriangleBoxes4 {
    __m128 lx, hx, ly, hy, lz, hz;
};

inline TriangleBoxes4 triangle_boxes4(const Tri8& t, int i) {
    TriangleBoxes4 r;
    auto axis = [&](const float* a, const float* b, const float* c, __m128& lo, __m128& hi) {
        const __m128 va = _mm_load_ps(a + i), vb = _mm_load_ps(b + i), vc = _mm_load_ps(c + i);
        lo = _mm_min_ps(_mm_min_ps(va, vb), vc);
        hi = _mm_max_ps(_mm_max_ps(va, vb), vc);
    };
    axis(t.v0x, t.v1x, t.v2x, r.lx, r.hx);
    axis(t.v0y, t.v1y, t.v2y, r.ly, r.hy);
    axis(t.v0z, t.v1z, t.v2z, r.lz, r.hz);
    return r;
}

}  // namespace simdbvh::detail
