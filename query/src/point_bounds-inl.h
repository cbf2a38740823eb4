#pragma once
// Internal: float lower bounds on squared point-to-box distances, 4 lanes at a
// time with SSE (the x86-64 baseline: no dispatch, no AVX), for the wide
// trees' closest-point query: a node's N child boxes and a Tri8 block's 8
// triangle boxes, read in their SoA layout.
//
// Why a float bound is safe. Per axis the exact gap is g = max(lo - x, x - hi,
// 0); each float operation is correctly rounded (relative error at most
// u = 2^-24, and rounding is monotonic, so the max of rounded differences is
// the rounded max), so the float sum of squares is within (1 + u)^5 of g^2
// summed, and (1 - 2^-20) times it is below the exact distance. Two ranges
// break that argument and take the double computation instead: overflow (the
// float value is inf) and underflow (a nonzero value below 2^-100); an exact
// float 0 gives key 0 (never pruned: always safe).
// The result is a prune key: prune when key > best distance^2. Which nodes
// are pruned changes, never the answer (a box is pruned only when every point
// in it is strictly farther than the best).
#include "simdbvh/kernels/internal/simd/sse2.h"

#include <cmath>
#include <limits>

#include "simdbvh/query/internal/point_query-inl.h"
#include "simdbvh/kernels/soa.h"
#include "simdbvh/bvh8/internal/tri8_lanes-inl.h"

namespace simdbvh::detail {

inline constexpr double kFloatBoundScale = 1.0 - 0x1p-20;
inline constexpr float kFloatBoundTiny = 0x1p-100f;

// Squared gaps of 4 boxes (lo, hi per axis) from p, in float.
inline __m128 gap2_4(__m128 lx, __m128 hx, __m128 ly, __m128 hy, __m128 lz, __m128 hz, __m128 px, __m128 py,
                     __m128 pz) {
    const __m128 zero = _mm_setzero_ps();
    const __m128 gx = _mm_max_ps(_mm_max_ps(_mm_sub_ps(lx, px), _mm_sub_ps(px, hx)), zero);
    const __m128 gy = _mm_max_ps(_mm_max_ps(_mm_sub_ps(ly, py), _mm_sub_ps(py, hy)), zero);
    const __m128 gz = _mm_max_ps(_mm_max_ps(_mm_sub_ps(lz, pz), _mm_sub_ps(pz, hz)), zero);
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(gx, gx), _mm_mul_ps(gy, gy)), _mm_mul_ps(gz, gz));
}

// The prune key of one lane from its float bound f; `exact` gives the
// double box distance for the overflow case.
template <class Exact>
inline double prune_key(float f, Exact&& exact) {
    if (f >= kFloatBoundTiny && f <= std::numeric_limits<float>::max()) return double(f) * kFloatBoundScale;
    if (f == 0.0f) return 0.0;     // inside the box (or every gap below ~1e-23): never pruned
    return exact() * kPruneSlack;  // tiny, inf (overflow) or NaN: the double path
}

// Prune keys of a node's N child boxes (empty slots give +inf).
template <int N>
inline void box_keys(const BoxN<N>& b, const Vec3& p, double key[N]) {
    const __m128 px = _mm_set1_ps(p.x), py = _mm_set1_ps(p.y), pz = _mm_set1_ps(p.z);
    alignas(16) float f[N];
    for (int i = 0; i < N; i += 4)
        _mm_store_ps(f + i,
                     gap2_4(_mm_load_ps(b.lo_x + i), _mm_load_ps(b.hi_x + i), _mm_load_ps(b.lo_y + i),
                            _mm_load_ps(b.hi_y + i), _mm_load_ps(b.lo_z + i), _mm_load_ps(b.hi_z + i), px, py, pz));
    for (int i = 0; i < N; ++i) key[i] = prune_key(f[i], [&] { return box_distance2(p, b.get(i)); });
}

// Prune keys of a Tri8 block's triangle boxes (empty lanes: meaningless,
// the caller skips them by id).
inline void triangle_keys(const Tri8& t, const Vec3& p, double key[kBlockWidth]) {
    const __m128 px = _mm_set1_ps(p.x), py = _mm_set1_ps(p.y), pz = _mm_set1_ps(p.z);
    alignas(16) float f[kBlockWidth];
    for (int i = 0; i < kBlockWidth; i += 4) {
        const TriangleBoxes4 x = triangle_boxes4(t, i);
        _mm_store_ps(f + i, gap2_4(x.lx, x.hx, x.ly, x.hy, x.lz, x.hz, px, py, pz));
    }
    for (int i = 0; i < kBlockWidth; ++i)
        key[i] = prune_key(f[i], [&] {
            Aabb tb;
            tb.grow(t.v0(i));
            tb.grow(t.v1(i));
            tb.grow(t.v2(i));
            return box_distance2(p, tb);
        });
}

}  // namespace simdbvh::detail
