#pragma once
// Ray (32 bytes, the ray-file record) and its once-per-ray setup.
#include <cmath>
#include <cstdint>
#include <limits>

#include "simdbvh/kernels/vec.h"

namespace simdbvh {

struct Ray {
    Vec3 org;
    float tmin = 0.0f;
    Vec3 dir;
    float tmax = std::numeric_limits<float>::infinity();
};
static_assert(sizeof(Ray) == 32);

// Everything the box and triangle kernels need, computed once per ray in
// ISA-neutral code so every path starts from identical values.
struct PreparedRay {
    Vec3 org;
    Vec3 dir;
    Vec3 rdir;         // 1/d, +-inf for +-0 components (sign kept)
    float tmin = 0.0f;
    float tmax = 0.0f;
    int near_x = 0;    // 0: the near plane is the box's lower bound, 1: the upper bound
    int near_y = 0;
    int near_z = 0;
    int octant = 0;    // bit i set when rdir[i] is negative (sign bit)
    int kx = 0, ky = 1, kz = 2;  // watertight permutation (Woop et al. 2013)
    float sx = 0.0f, sy = 0.0f, sz = 0.0f;  // watertight shear constants
    bool valid = false;  // false: zero/NaN/Inf direction, NaN/Inf origin, NaN or empty interval
};

// Ize 2013 ("Robust BVH Ray Traversal"): widen the far distance by 1 + 2*gamma(3),
// gamma(n) = n*u / (1 - n*u), u = 2^-24.
inline constexpr float kFarWiden = 1.0f + 2.0f * (3.0f * 0x1p-24f / (1.0f - 3.0f * 0x1p-24f));
// Traversals cull boxes against the closest hit so far widened by this factor:
// a triangle lying on its leaf box's entry face has a t computed with several
// more roundings than the box's entry distance (about 8 ulps worst case), and
// an equal-t hit with a lower id in that leaf must still be found. Culling only
// affects speed, never results, so the margin is generous (64 ulps).
inline constexpr float kCullWiden = 1.0f + 0x1p-18f;

inline PreparedRay prepare(const Ray& r) {
    PreparedRay p;
    p.org = r.org;
    p.dir = r.dir;
    p.tmin = r.tmin;
    p.tmax = r.tmax;
    const bool dir_ok = is_finite(r.dir) && (r.dir.x != 0.0f || r.dir.y != 0.0f || r.dir.z != 0.0f);
    p.valid = dir_ok && is_finite(r.org) && !std::isnan(r.tmin) && !std::isnan(r.tmax) && r.tmin <= r.tmax;
    // 1/(+-0) = +-inf, written without dividing by zero (UBSan's float-divide-by-zero).
    auto rcp = [](float d) { return d != 0.0f ? 1.0f / d : std::copysign(std::numeric_limits<float>::infinity(), d); };
    p.rdir = {rcp(r.dir.x), rcp(r.dir.y), rcp(r.dir.z)};
    p.near_x = std::signbit(p.rdir.x) ? 1 : 0;
    p.near_y = std::signbit(p.rdir.y) ? 1 : 0;
    p.near_z = std::signbit(p.rdir.z) ? 1 : 0;
    p.octant = p.near_x | (p.near_y << 1) | (p.near_z << 2);
    const Vec3 a{std::fabs(r.dir.x), std::fabs(r.dir.y), std::fabs(r.dir.z)};
    int kz = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (r.dir[kz] < 0.0f) { int t = kx; kx = ky; ky = t; }  // keep the winding
    p.kx = kx; p.ky = ky; p.kz = kz;
    if (p.valid) {
        p.sx = r.dir[kx] / r.dir[kz];
        p.sy = r.dir[ky] / r.dir[kz];
        p.sz = 1.0f / r.dir[kz];
    }
    return p;
}

}  // namespace simdbvh
