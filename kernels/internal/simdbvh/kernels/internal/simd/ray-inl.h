#pragma once
// RayPack<Arch>: one PreparedRay's values as the kernels use them, plus the
// once-per-ray byte offsets that select the near/far box planes (Box8) and the
// watertight permutation kx, ky, kz (Tri8). Built once per ray, reused for
// every node/leaf. The values are scalars, broadcast where used (a broadcast
// from memory costs one load, like a vector load): the BVH8 keeps several rays
// in flight, and a pack of floats is 4x cheaper to build and to switch to than
// one of 8-lane batches.
#include <cstddef>
#include <cstdint>

#include "simdbvh/kernels/internal/simd/arch-inl.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/soa.h"

namespace simdbvh::kernels::simd {

static_assert(offsetof(Box8, hi_x) == 32 && offsetof(Box8, lo_y) == 64 && offsetof(Box8, lo_z) == 128);
static_assert(offsetof(Tri8, v0y) == 32 && offsetof(Tri8, v1x) == 96 && offsetof(Tri8, v2x) == 192 &&
              offsetof(Tri8, prim) == 288);

template <class Arch>
struct RayPack {
    float ox, oy, oz;     // origin
    float dx, dy, dz;     // direction (Moller-Trumbore)
    float rdx, rdy, rdz;  // 1/d (box)
    float tmin;
    float far_slack;                       // PreparedRay::far_slack
    float okx, oky, okz;                   // origin permuted by kx, ky, kz (watertight)
    float sx, sy, sz;                      // watertight shear
    std::uint32_t near_x, near_y, near_z;  // byte offsets into Box8 of the near planes
    std::uint32_t far_x, far_y, far_z;     // ... and of the far planes
    std::uint32_t kx, ky, kz;              // byte offsets of components kx, ky, kz within a Tri8 vertex
    // For the rare exact (double) watertight lanes: the prepared ray (must
    // outlive the pack), or when null, the ray it was prepared from (prepared
    // again there: prepare() is deterministic).
    const PreparedRay* ray;
    const Ray* src;
};

// In place (the BVH8 packs into its per-ray state). Keeps a pointer to `r`,
// or with `src` (the ray `r` was prepared from), to `src` only.
template <class Arch>
SIMDBVH_FORCE_INLINE void pack_ray_into(RayPack<Arch>& p, const PreparedRay& r, const Ray* src = nullptr) {
    p.ox = r.org.x;
    p.oy = r.org.y;
    p.oz = r.org.z;
    p.dx = r.dir.x;
    p.dy = r.dir.y;
    p.dz = r.dir.z;
    p.rdx = r.rdir.x;
    p.rdy = r.rdir.y;
    p.rdz = r.rdir.z;
    p.tmin = r.tmin;
    p.far_slack = r.far_slack;
    p.okx = r.org[r.kx];
    p.oky = r.org[r.ky];
    p.okz = r.org[r.kz];
    p.sx = r.sx;
    p.sy = r.sy;
    p.sz = r.sz;
    // near = lo when near_* == 0, hi when 1 (box.h); lo/hi arrays are 32 bytes apart.
    p.near_x = 0 + 32u * std::uint32_t(r.near_x);
    p.far_x = 0 + 32u * std::uint32_t(1 - r.near_x);
    p.near_y = 64 + 32u * std::uint32_t(r.near_y);
    p.far_y = 64 + 32u * std::uint32_t(1 - r.near_y);
    p.near_z = 128 + 32u * std::uint32_t(r.near_z);
    p.far_z = 128 + 32u * std::uint32_t(1 - r.near_z);
    p.kx = 32u * std::uint32_t(r.kx);
    p.ky = 32u * std::uint32_t(r.ky);
    p.kz = 32u * std::uint32_t(r.kz);
    p.ray = src ? nullptr : &r;
    p.src = src;
}

template <class Arch>
SIMDBVH_FORCE_INLINE RayPack<Arch> pack_ray(const PreparedRay& r) {  // keeps a pointer to `r`
    RayPack<Arch> p;
    pack_ray_into<Arch>(p, r);
    return p;
}

}  // namespace simdbvh::kernels::simd
