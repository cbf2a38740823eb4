#pragma once
// Eight rays' prepare() (ray.h) and their test against one box (box.h's
// intersect_box, each ray's own interval), in vector lanes: the once-per-ray
// set-up of a batched traversal without prepare()'s data-dependent branches
// (which axis is largest, its sign) and its six scalar divisions per ray.
// Each lane runs prepare()'s operations in prepare()'s order, so every
// PreparedRay is prepare()'s bit for bit (tests/kernels: every field, every
// ISA). A ray whose direction prepare() rescales (largest component below
// 2^-32 or above 2^32, t_exp != 0) goes through prepare() itself.
#include <cstddef>
#include <cstdint>
#include <limits>

#include "simdbvh/kernels/internal/simd/arch-inl.h"
#include "simdbvh/kernels/internal/simd/box8-inl.h"
#include "simdbvh/kernels/aabb.h"
#include "simdbvh/kernels/box.h"
#include "simdbvh/kernels/ray.h"

namespace simdbvh::kernels::simd {

// The eight 32-byte rays as columns: c[0..2] origin, c[3] tmin, c[4..6]
// direction, c[7] tmax (Ray's layout). A template on Arch, so no copy is
// ever shared between the ISAs' objects.
template <class Arch>
SIMDBVH_FORCE_INLINE void transpose_rays8(const Ray* rays, std::size_t g, __m256 c[8]) {
    __m256 r[8];
    for (std::size_t l = 0; l < 8; ++l) r[l] = _mm256_loadu_ps(&rays[l < g ? l : 0].org.x);
    const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
    const __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
    const __m256 t4 = _mm256_unpacklo_ps(r[4], r[5]), t5 = _mm256_unpackhi_ps(r[4], r[5]);
    const __m256 t6 = _mm256_unpacklo_ps(r[6], r[7]), t7 = _mm256_unpackhi_ps(r[6], r[7]);
    const __m256 u0 = _mm256_shuffle_ps(t0, t2, 0x44), u1 = _mm256_shuffle_ps(t0, t2, 0xEE);
    const __m256 u2 = _mm256_shuffle_ps(t1, t3, 0x44), u3 = _mm256_shuffle_ps(t1, t3, 0xEE);
    const __m256 u4 = _mm256_shuffle_ps(t4, t6, 0x44), u5 = _mm256_shuffle_ps(t4, t6, 0xEE);
    const __m256 u6 = _mm256_shuffle_ps(t5, t7, 0x44), u7 = _mm256_shuffle_ps(t5, t7, 0xEE);
    c[0] = _mm256_permute2f128_ps(u0, u4, 0x20);
    c[1] = _mm256_permute2f128_ps(u1, u5, 0x20);
    c[2] = _mm256_permute2f128_ps(u2, u6, 0x20);
    c[3] = _mm256_permute2f128_ps(u3, u7, 0x20);
    c[4] = _mm256_permute2f128_ps(u0, u4, 0x31);
    c[5] = _mm256_permute2f128_ps(u1, u5, 0x31);
    c[6] = _mm256_permute2f128_ps(u2, u6, 0x31);
    c[7] = _mm256_permute2f128_ps(u3, u7, 0x31);
}

// Eight rays in vector lanes, as far as the slab test needs them:
// prepare_scaled()'s validity and flush of subnormal components, prepare()'s
// reciprocals, near planes and far slack. `alone`: the valid lanes whose
// direction prepare() rescales, whose fields here are not prepare()'s (they
// go through prepare() itself). Shared by prepare8 and collect_boxes.
template <class Arch>
struct RayLanes8 {
    Batch<Arch> ox, oy, oz, dx, dy, dz, tmin, tmax;  // dx, dy, dz flushed
    Batch<Arch> rdx, rdy, rdz, slack;
    Mask<Arch> hx, hy, hz;  // the near plane is the box's upper bound (the reciprocal is negative)
    std::uint32_t valid, alone;
};

// rays[0 .. g), 1 <= g <= 8 (lanes >= g repeat ray 0 and are never valid).
template <class Arch>
SIMDBVH_FORCE_INLINE RayLanes8<Arch> ray_lanes8(const Ray* rays, std::size_t g) {
    using B = Batch<Arch>;
    static_assert(B::size == 8, "8 rays per batch");
    __m256 c[8];
    transpose_rays8<Arch>(rays, g, c);
    const B tmin(c[3]), tmax(c[7]);
    B ox(c[0]), oy(c[1]), oz(c[2]), dx(c[4]), dy(c[5]), dz(c[6]);
    const B inf(std::numeric_limits<float>::infinity()), zero(0.0f), one(1.0f);
    // valid_ray() (NaN compares false), and which directions prepare_scaled() rescales.
    const B ax = xsimd::abs(dx), ay = xsimd::abs(dy), az = xsimd::abs(dz);
    const auto ok = (ax < inf) & (ay < inf) & (az < inf) & (xsimd::abs(ox) < inf) & (xsimd::abs(oy) < inf) &
                    (xsimd::abs(oz) < inf) & ((dx != zero) | (dy != zero) | (dz != zero)) & (tmin <= tmax);
    const B big = xsimd::max(ax, xsimd::max(ay, az));
    const auto rescaled = (big < B(kRescaleBelow)) | (big > B(kRescaleAbove));
    const std::uint32_t valid = bits<Arch>(ok) & ((1u << g) - 1u);
    // The flush of subnormal components to zeros of the same sign (direction and origin).
    const B tiny(std::numeric_limits<float>::min()), sign(-0.0f);
    dx = xsimd::select(ax < tiny, dx & sign, dx);
    dy = xsimd::select(ay < tiny, dy & sign, dy);
    dz = xsimd::select(az < tiny, dz & sign, dz);
    ox = xsimd::select(xsimd::abs(ox) < tiny, ox & sign, ox);
    oy = xsimd::select(xsimd::abs(oy) < tiny, oy & sign, oy);
    oz = xsimd::select(xsimd::abs(oz) < tiny, oz & sign, oz);
    // Reciprocals (1 / +-0 = +-inf), whose sign bits pick the near planes
    // (never 0 or NaN for a finite direction), and far_slack_for(tmin).
    const B rdx = one / dx, rdy = one / dy, rdz = one / dz;
    const B slack = xsimd::select(tmin < zero, (-tmin) * B(2.0f * (kFarWiden - 1.0f)), zero);
    return {ox,
            oy,
            oz,
            dx,
            dy,
            dz,
            tmin,
            tmax,
            rdx,
            rdy,
            rdz,
            slack,
            rdx < zero,
            rdy < zero,
            rdz < zero,
            valid,
            valid & bits<Arch>(rescaled)};
}

// intersect_box(r, b, r.tmax) in every lane (box.h's conservative slab test,
// the same operations in the same order): the lanes whose ray hits `b`
// (including lanes that are not valid or go alone: mask them), entries in `tn`.
template <class Arch>
SIMDBVH_FORCE_INLINE std::uint32_t box_lanes8(const RayLanes8<Arch>& r, const Aabb& b, Batch<Arch>& tn) {
    using B = Batch<Arch>;
    const B lx(b.lo.x), ux(b.hi.x), ly(b.lo.y), uy(b.hi.y), lz(b.lo.z), uz(b.hi.z);
    const B t0x = (xsimd::select(r.hx, ux, lx) - r.ox) * r.rdx, t1x = (xsimd::select(r.hx, lx, ux) - r.ox) * r.rdx;
    const B t0y = (xsimd::select(r.hy, uy, ly) - r.oy) * r.rdy, t1y = (xsimd::select(r.hy, ly, uy) - r.oy) * r.rdy;
    const B t0z = (xsimd::select(r.hz, uz, lz) - r.oz) * r.rdz, t1z = (xsimd::select(r.hz, lz, uz) - r.oz) * r.rdz;
    tn = max_ps<Arch>(t0x, max_ps<Arch>(t0y, max_ps<Arch>(t0z, r.tmin)));
    const B tf = min_ps<Arch>(t1x, min_ps<Arch>(t1y, min_ps<Arch>(t1z, r.tmax))) * B(kFarWiden) + r.slack;
    return bits<Arch>(tn <= tf);
}

// rays[0 .. g), 1 <= g <= 8. Returns bit l set when ray l is valid and hits
// `bounds` (none when bounds is null), with out[l] = prepare(rays[l]) for
// those rays (the other entries are left unspecified); *valid gets bit l
// when prepare(rays[l]).valid (when bounds is not null).
template <class Arch>
SIMDBVH_FORCE_INLINE std::uint32_t prepare8(const Ray* rays, std::size_t g, const Aabb* bounds, PreparedRay* out,
                                            std::uint32_t* valid) {
    *valid = 0;
    if (!bounds) return 0;
    using B = Batch<Arch>;
    const RayLanes8<Arch> r = ray_lanes8<Arch>(rays, g);
    *valid = r.valid;
    const std::uint32_t vec = r.valid & ~r.alone;
    std::uint32_t hit = 0;
    if (vec != 0) {
        B tn;
        hit = box_lanes8<Arch>(r, *bounds, tn) & vec;
    }
    if (hit != 0) {
        // The watertight permutation: kz the largest |d| (the first of equals),
        // kx, ky the next two cyclically, swapped when d[kz] < 0.
        const B zero(0.0f), one(1.0f);
        const B ax = xsimd::abs(r.dx), ay = xsimd::abs(r.dy), az = xsimd::abs(r.dz);
        const auto c0 = (ax >= ay) & (ax >= az), c1 = ay >= az;
        const B dkz = xsimd::select(c0, r.dx, xsimd::select(c1, r.dy, r.dz));
        const B dkx0 = xsimd::select(c0, r.dy, xsimd::select(c1, r.dz, r.dx));
        const B dky0 = xsimd::select(c0, r.dz, xsimd::select(c1, r.dx, r.dy));
        const auto neg = dkz < zero;
        const B dkx = xsimd::select(neg, dky0, dkx0), dky = xsimd::select(neg, dkx0, dky0);
        const B sx = dkx / dkz, sy = dky / dkz, sz = one / dkz;
        alignas(32) float f[15][8];
        r.ox.store_aligned(f[0]);
        r.oy.store_aligned(f[1]);
        r.oz.store_aligned(f[2]);
        r.dx.store_aligned(f[3]);
        r.dy.store_aligned(f[4]);
        r.dz.store_aligned(f[5]);
        r.rdx.store_aligned(f[6]);
        r.rdy.store_aligned(f[7]);
        r.rdz.store_aligned(f[8]);
        r.tmin.store_aligned(f[9]);
        r.tmax.store_aligned(f[10]);
        sx.store_aligned(f[11]);
        sy.store_aligned(f[12]);
        sz.store_aligned(f[13]);
        r.slack.store_aligned(f[14]);
        const std::uint32_t bx = bits<Arch>(r.hx), by = bits<Arch>(r.hy), bz = bits<Arch>(r.hz);
        const std::uint32_t b0 = bits<Arch>(c0), b1 = bits<Arch>(c1), bn = bits<Arch>(neg);
        for (std::uint32_t m = hit; m != 0; m &= m - 1) {
            const int l = __builtin_ctz(m);
            // kz = 0 when c0, else 1 when c1, else 2; kx = kz + 1, ky = kz + 2 (mod 3), swapped when neg.
            const int kz = (b0 >> l & 1u) ? 0 : ((b1 >> l & 1u) ? 1 : 2);
            const int k1 = kz == 2 ? 0 : kz + 1, k2 = k1 == 2 ? 0 : k1 + 1;
            const bool sw = (bn >> l & 1u) != 0;
            PreparedRay& p = out[l];
            p.org = {f[0][l], f[1][l], f[2][l]};
            p.dir = {f[3][l], f[4][l], f[5][l]};
            p.rdir = {f[6][l], f[7][l], f[8][l]};
            p.tmin = f[9][l];
            p.tmax = f[10][l];
            p.near_x = int(bx >> l & 1u);
            p.near_y = int(by >> l & 1u);
            p.near_z = int(bz >> l & 1u);
            p.octant = p.near_x | (p.near_y << 1) | (p.near_z << 2);
            p.kx = sw ? k2 : k1;
            p.ky = sw ? k1 : k2;
            p.kz = kz;
            p.sx = f[11][l];
            p.sy = f[12][l];
            p.sz = f[13][l];
            p.valid = true;
            p.t_exp = 0;
            p.far_slack = f[14][l];
        }
    }
    for (std::uint32_t m = r.alone; m != 0; m &= m - 1) {
        const int l = __builtin_ctz(m);
        out[l] = prepare(rays[l]);
        float entry;
        if (intersect_box(out[l], *bounds, out[l].tmax, &entry)) hit |= 1u << l;
    }
    return hit;
}

}  // namespace simdbvh::kernels::simd
