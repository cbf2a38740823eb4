#pragma once
// SoA blocks of 8 boxes and 8 triangles: the layout the 8-wide kernels and the
// BVH8 read. Empty box slots hold lo = +inf, hi = -inf (never hit); empty
// triangle slots hold NaN vertices and kInvalidPrim (never hit).
#include <cstdint>
#include <limits>

#include "simdbvh/kernels/aabb.h"
#include "simdbvh/kernels/hit.h"

namespace simdbvh {

struct alignas(32) Box8 {
    float lo_x[8], hi_x[8], lo_y[8], hi_y[8], lo_z[8], hi_z[8];

    void clear() {
        for (int i = 0; i < 8; ++i) set_empty(i);
    }
    void set_empty(int i) {
        constexpr float inf = std::numeric_limits<float>::infinity();
        lo_x[i] = lo_y[i] = lo_z[i] = inf;
        hi_x[i] = hi_y[i] = hi_z[i] = -inf;
    }
    void set(int i, const Aabb& b) {
        lo_x[i] = b.lo.x; lo_y[i] = b.lo.y; lo_z[i] = b.lo.z;
        hi_x[i] = b.hi.x; hi_y[i] = b.hi.y; hi_z[i] = b.hi.z;
    }
    Aabb get(int i) const { return {{lo_x[i], lo_y[i], lo_z[i]}, {hi_x[i], hi_y[i], hi_z[i]}}; }
};
static_assert(sizeof(Box8) == 192 && alignof(Box8) == 32);

struct alignas(32) Tri8 {
    float v0x[8], v0y[8], v0z[8], v1x[8], v1y[8], v1z[8], v2x[8], v2y[8], v2z[8];
    std::uint32_t prim[8];

    void clear() {
        for (int i = 0; i < 8; ++i) set_empty(i);
    }
    void set_empty(int i) {
        constexpr float nan = std::numeric_limits<float>::quiet_NaN();
        v0x[i] = v0y[i] = v0z[i] = v1x[i] = v1y[i] = v1z[i] = v2x[i] = v2y[i] = v2z[i] = nan;
        prim[i] = kInvalidPrim;
    }
    void set(int i, const Vec3& a, const Vec3& b, const Vec3& c, std::uint32_t id) {
        v0x[i] = a.x; v0y[i] = a.y; v0z[i] = a.z;
        v1x[i] = b.x; v1y[i] = b.y; v1z[i] = b.z;
        v2x[i] = c.x; v2y[i] = c.y; v2z[i] = c.z;
        prim[i] = id;
    }
    Vec3 v0(int i) const { return {v0x[i], v0y[i], v0z[i]}; }
    Vec3 v1(int i) const { return {v1x[i], v1y[i], v1z[i]}; }
    Vec3 v2(int i) const { return {v2x[i], v2y[i], v2z[i]}; }
};
static_assert(sizeof(Tri8) == 320 && alignof(Tri8) == 32);

}  // namespace simdbvh
