#pragma once
// Ray (32 bytes, the ray-file record) and its once-per-ray setup.
#include <cmath>
#include <cstdint>
#include <limits>

#include "simdbvh/kernels/hit.h"
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
//
// Tiny and huge directions. A direction whose largest component is below
// 2^-32 or above 2^32 is rescaled by an exact power of two 2^t_exp so that the
// largest component lies in [1, 2), and tmin/tmax by 2^-t_exp: the same ray,
// parameterised differently (1/d no longer overflows for |d| < 2^-128, and the
// slab distances stay finite). Components below FLT_MIN (after any rescaling)
// are flushed to a zero of the same sign, on every path, so the box test (which
// needs 1/d) and the triangle test see the same direction. Kernels work in the
// rescaled parameter; to_caller() maps a hit's t back by 2^t_exp. Where that t
// exceeds FLT_MAX (say |d| = 2^-149 and a triangle at distance 1) the hit is
// reported with t = +inf and its triangle, u and v; where it falls below
// FLT_MIN it is rounded as ldexp() rounds. Power-of-two rescalings of a
// direction give the same triangle, u and v, and t scaled exactly (until it
// overflows or becomes subnormal).
struct PreparedRay {
    Vec3 org;
    Vec3 dir;   // the direction the kernels use (rescaled, subnormals flushed)
    Vec3 rdir;  // 1/d, +-inf for +-0 components (sign kept)
    float tmin = 0.0f;
    float tmax = 0.0f;
    int near_x = 0;  // 0: the near plane is the box's lower bound, 1: the upper bound
    int near_y = 0;
    int near_z = 0;
    int octant = 0;                         // bit i set when rdir[i] is negative (sign bit)
    int kx = 0, ky = 1, kz = 2;             // watertight permutation (Woop et al. 2013)
    float sx = 0.0f, sy = 0.0f, sz = 0.0f;  // watertight shear constants
    bool valid = false;                     // false: zero/NaN/Inf direction, NaN/Inf origin, NaN or empty interval
    int t_exp = 0;                          // a caller's t = ldexp(kernel t, t_exp)
    // Added to every widened far distance: 0 when tmin >= 0; for an interval
    // reaching behind the origin, the absolute error of a negative slab
    // distance (kFarWiden's relative widening shrinks a negative far bound).
    float far_slack = 0.0f;
};

// Directions with a largest component outside [kRescaleBelow, kRescaleAbove] are rescaled.
inline constexpr float kRescaleBelow = 0x1p-32f;
inline constexpr float kRescaleAbove = 0x1p32f;

// Ize 2013 ("Robust BVH Ray Traversal"): widen the far distance by 1 + 2*gamma(3),
// gamma(n) = n*u / (1 - n*u), u = 2^-24.
inline constexpr float kFarWiden = 1.0f + 2.0f * (3.0f * 0x1p-24f / (1.0f - 3.0f * 0x1p-24f));
// Traversals cull boxes against the closest hit so far widened by this factor:
// a triangle lying on its leaf box's entry face has a t computed with several
// more roundings than the box's entry distance (about 8 ulps worst case), and
// an equal-t hit with a lower id in that leaf must still be found. Culling only
// affects speed, never results, so the margin is generous (64 ulps).
inline constexpr float kCullWiden = 1.0f + 0x1p-18f;
// The culling distance for a closest hit at t: t widened away from the origin
// of the t axis' order, t + |t| 2^-18 (for t >= 0 the same float as
// t * kCullWiden; for a negative t, from tmin < 0, it is larger than t).
inline float cull_bound(float t) { return t + std::fabs(t) * 0x1p-18f; }
// The far-bound slack for tmin < 0: |t| 4 gamma(3) (kFarWiden - 1 = 2 gamma(3)
// covers near and far roundings relative to |t|; the relevant negative slab
// distances are no larger than |tmin|; doubled for the roundings of the slack
// itself and of the add).
inline float far_slack_for(float tmin) { return tmin < 0.0f ? -tmin * (2.0f * (kFarWiden - 1.0f)) : 0.0f; }

// A direction prepare() can use: finite and not zero.
inline bool usable_dir(const Vec3& d) { return is_finite(d) && (d.x != 0.0f || d.y != 0.0f || d.z != 0.0f); }
// PreparedRay::valid without the rest of prepare(): a usable direction, a
// finite origin, tmin and tmax not NaN, tmin <= tmax.
inline bool valid_ray(const Ray& r) {
    return usable_dir(r.dir) && is_finite(r.org) && !std::isnan(r.tmin) && !std::isnan(r.tmax) && r.tmin <= r.tmax;
}

// The first stage of prepare(): org (subnormals flushed), dir (rescaled, subnormals flushed),
// tmin, tmax, t_exp and valid, the same values prepare() gives; the
// reciprocals, near planes, octant, watertight permutation and shear are left
// at their defaults. For tests that read only those fields (the scenes'
// planes, shapes.h's hit_plane).
// Both are always inlined: a per-ISA translation unit must never emit an
// out-of-line copy (a weak symbol the linker may share with another ISA's
// objects; tests/kernels/check_isa_objects.cmake), and GCC's flatten gave up
// on them in the wide traversal's stream loop (bvh8/internal/simdbvh/bvh8/internal/stream-inl.h).
inline __attribute__((always_inline)) PreparedRay prepare_scaled(const Ray& r) {
    PreparedRay p;
    // Subnormal origin components flushed to zeros of the same sign (as the
    // direction's below): the triangle test's products underflow there, so it
    // treats them as zero, and the box tests must see the ray where it does.
    auto flush = [](float d) { return std::fabs(d) < std::numeric_limits<float>::min() ? std::copysign(0.0f, d) : d; };
    p.org = {flush(r.org.x), flush(r.org.y), flush(r.org.z)};
    p.dir = r.dir;
    p.tmin = r.tmin;
    p.tmax = r.tmax;
    const bool dir_ok = usable_dir(r.dir);
    p.valid = valid_ray(r);
    if (dir_ok) {
        // Finite components here, so a plain comparison is fmax (std::fmax is a libm call without -ffinite-math-only).
        const float ax = std::fabs(r.dir.x), ay = std::fabs(r.dir.y), az = std::fabs(r.dir.z);
        const float m = ax > ay ? (ax > az ? ax : az) : (ay > az ? ay : az);
        if (m < kRescaleBelow || m > kRescaleAbove) {
            const int k = -std::ilogb(m);  // m * 2^k in [1, 2)
            p.dir = {std::ldexp(r.dir.x, k), std::ldexp(r.dir.y, k), std::ldexp(r.dir.z, k)};
            p.tmin = std::ldexp(r.tmin, -k);
            p.tmax = std::ldexp(r.tmax, -k);
            p.t_exp = k;
        }
        p.dir = {flush(p.dir.x), flush(p.dir.y), flush(p.dir.z)};
    }
    return p;
}

inline __attribute__((always_inline)) PreparedRay prepare(const Ray& r) {
    PreparedRay p = prepare_scaled(r);
    const Vec3 d = p.dir;
    // 1/(+-0) = +-inf, written without dividing by zero (UBSan's float-divide-by-zero).
    auto rcp = [](float d) { return d != 0.0f ? 1.0f / d : std::copysign(std::numeric_limits<float>::infinity(), d); };
    p.rdir = {rcp(d.x), rcp(d.y), rcp(d.z)};
    p.near_x = std::signbit(p.rdir.x) ? 1 : 0;
    p.near_y = std::signbit(p.rdir.y) ? 1 : 0;
    p.near_z = std::signbit(p.rdir.z) ? 1 : 0;
    p.octant = p.near_x | (p.near_y << 1) | (p.near_z << 2);
    const Vec3 a{std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)};
    int kz = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (d[kz] < 0.0f) {
        int t = kx;
        kx = ky;
        ky = t;
    }  // keep the winding
    p.kx = kx;
    p.ky = ky;
    p.kz = kz;
    p.far_slack = std::isnan(p.tmin) ? 0.0f : far_slack_for(p.tmin);
    if (p.valid) {
        p.sx = d[kx] / d[kz];
        p.sy = d[ky] / d[kz];
        p.sz = 1.0f / d[kz];
    }
    return p;
}

// A kernel's t (in the prepared ray's parameter) as the caller's t.
inline float to_caller_t(int t_exp, float t) { return t_exp == 0 ? t : std::ldexp(t, t_exp); }
inline float to_caller_t(const PreparedRay& p, float t) { return to_caller_t(p.t_exp, t); }

// A kernel's hit as the caller's hit (misses pass through).
inline Hit to_caller(int t_exp, Hit h) {
    if (t_exp != 0 && h.hit()) h.t = std::ldexp(h.t, t_exp);
    return h;
}
inline Hit to_caller(const PreparedRay& p, const Hit& h) { return to_caller(p.t_exp, h); }

}  // namespace simdbvh
