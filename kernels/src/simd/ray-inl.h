#pragma once
// RayPack<Arch>: one PreparedRay broadcast to 8 lanes, plus the once-per-ray
// byte offsets that select the near/far box planes (Box8) and the watertight
// permutation kx, ky, kz (Tri8). Built once per ray, reused for every node/leaf.
#include <cstddef>
#include <cstdint>

#include "simd/arch-inl.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/soa.h"

namespace simdbvh::simd {

static_assert(offsetof(Box8, hi_x) == 32 && offsetof(Box8, lo_y) == 64 && offsetof(Box8, lo_z) == 128);
static_assert(offsetof(Tri8, v0y) == 32 && offsetof(Tri8, v1x) == 96 && offsetof(Tri8, v2x) == 192 &&
              offsetof(Tri8, prim) == 288);

template <class Arch>
struct RayPack {
    using B = Batch<Arch>;
    B ox, oy, oz;        // origin
    B dx, dy, dz;        // direction (Moller-Trumbore)
    B rdx, rdy, rdz;     // 1/d (box)
    B tmin;
    B okx, oky, okz;     // origin permuted by kx, ky, kz (watertight)
    B sx, sy, sz;        // watertight shear
    std::uint32_t near_x, near_y, near_z;  // byte offsets into Box8 of the near planes
    std::uint32_t far_x, far_y, far_z;     // ... and of the far planes
    std::uint32_t kx, ky, kz;              // byte offsets of components kx, ky, kz within a Tri8 vertex
    PreparedRay ray;     // for the rare exact (double) watertight lanes
};

template <class Arch>
SIMDBVH_FORCE_INLINE RayPack<Arch> pack_ray(const PreparedRay& r) {
    using B = Batch<Arch>;
    RayPack<Arch> p;
    p.ox = B(r.org.x); p.oy = B(r.org.y); p.oz = B(r.org.z);
    p.dx = B(r.dir.x); p.dy = B(r.dir.y); p.dz = B(r.dir.z);
    p.rdx = B(r.rdir.x); p.rdy = B(r.rdir.y); p.rdz = B(r.rdir.z);
    p.tmin = B(r.tmin);
    p.okx = B(r.org[r.kx]); p.oky = B(r.org[r.ky]); p.okz = B(r.org[r.kz]);
    p.sx = B(r.sx); p.sy = B(r.sy); p.sz = B(r.sz);
    // near = lo when near_* == 0, hi when 1 (box.h); lo/hi arrays are 32 bytes apart.
    p.near_x = 0 + 32u * std::uint32_t(r.near_x);   p.far_x = 0 + 32u * std::uint32_t(1 - r.near_x);
    p.near_y = 64 + 32u * std::uint32_t(r.near_y);  p.far_y = 64 + 32u * std::uint32_t(1 - r.near_y);
    p.near_z = 128 + 32u * std::uint32_t(r.near_z); p.far_z = 128 + 32u * std::uint32_t(1 - r.near_z);
    p.kx = 32u * std::uint32_t(r.kx); p.ky = 32u * std::uint32_t(r.ky); p.kz = 32u * std::uint32_t(r.kz);
    p.ray = r;
    return p;
}

}  // namespace simdbvh::simd
