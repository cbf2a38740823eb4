#pragma once
// SoA blocks of N boxes (BoxN, the wide nodes' child boxes) and of 8 triangles
// (Tri8, the leaf blocks of every width): the layout the SIMD kernels and the
// wide BVHs read. Empty box slots hold lo = +inf, hi = -inf (never hit); empty
// triangle slots hold NaN vertices and kInvalidPrim (never hit).
#include <cstdint>
#include <limits>

#include "simdbvh/kernels/aabb.h"
#include "simdbvh/kernels/hit.h"

namespace simdbvh {

// N boxes, SoA (N = 4, 8, 16: the node widths; the lo and hi arrays of an
// axis are 4 * N bytes apart).
template <int N>
struct alignas(4 * N) BoxN {
    static constexpr int kWidth = N;
    float lo_x[N], hi_x[N], lo_y[N], hi_y[N], lo_z[N], hi_z[N];

    void clear() {
        for (int i = 0; i < N; ++i) set_empty(i);
    }
    void set_empty(int i) {
        constexpr float inf = std::numeric_limits<float>::infinity();
        lo_x[i] = lo_y[i] = lo_z[i] = inf;
        hi_x[i] = hi_y[i] = hi_z[i] = -inf;
    }
    void set(int i, const Aabb& b) {
        lo_x[i] = b.lo.x;
        lo_y[i] = b.lo.y;
        lo_z[i] = b.lo.z;
        hi_x[i] = b.hi.x;
        hi_y[i] = b.hi.y;
        hi_z[i] = b.hi.z;
    }
    Aabb get(int i) const { return {{lo_x[i], lo_y[i], lo_z[i]}, {hi_x[i], hi_y[i], hi_z[i]}}; }
};
using Box4 = BoxN<4>;
using Box8 = BoxN<8>;
using Box16 = BoxN<16>;
static_assert(sizeof(Box4) == 96 && alignof(Box4) == 16);
static_assert(sizeof(Box16) == 384 && alignof(Box16) == 64);
static_assert(sizeof(Box8) == 192 && alignof(Box8) == 32);

// The leaf block width: triangles per Tri8 block, whatever the node width.
inline constexpr int kBlockWidth = 8;

struct alignas(32) Tri8 {
    float v0x[kBlockWidth], v0y[kBlockWidth], v0z[kBlockWidth], v1x[kBlockWidth], v1y[kBlockWidth], v1z[kBlockWidth],
        v2x[kBlockWidth], v2y[kBlockWidth], v2z[kBlockWidth];
    std::uint32_t prim[kBlockWidth];

    void clear() {
        for (int i = 0; i < kBlockWidth; ++i) set_empty(i);
    }
    void set_empty(int i) {
        constexpr float nan = std::numeric_limits<float>::quiet_NaN();
        v0x[i] = v0y[i] = v0z[i] = v1x[i] = v1y[i] = v1z[i] = v2x[i] = v2y[i] = v2z[i] = nan;
        prim[i] = kInvalidPrim;
    }
    void set(int i, const Vec3& a, const Vec3& b, const Vec3& c, std::uint32_t id) {
        v0x[i] = a.x;
        v0y[i] = a.y;
        v0z[i] = a.z;
        v1x[i] = b.x;
        v1y[i] = b.y;
        v1z[i] = b.z;
        v2x[i] = c.x;
        v2y[i] = c.y;
        v2z[i] = c.z;
        prim[i] = id;
    }
    Vec3 v0(int i) const { return {v0x[i], v0y[i], v0z[i]}; }
    Vec3 v1(int i) const { return {v1x[i], v1y[i], v1z[i]}; }
    Vec3 v2(int i) const { return {v2x[i], v2y[i], v2z[i]}; }
};
static_assert(sizeof(Tri8) == 320 && alignof(Tri8) == 32);

}  // namespace simdbvh
