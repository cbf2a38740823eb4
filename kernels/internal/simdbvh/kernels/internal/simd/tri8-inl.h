#pragma once
// One ray against a Tri8 (8 triangles): watertight (Woop, Benthin, Wald 2013)
// and Moller-Trumbore (1997), with exactly the operation order of the scalar
// reference in triangle.h, so every lane's t, u, v are bit-identical to it.
//
// Closest hit: lanes are tested against [tmin, best.t]; the winner is the lane
// minimum by (t, prim) under closer() (hit.h), which equals looping the scalar
// test over lanes 0..7 while shrinking tmax. Any hit: the lowest lane that hits.
#include <algorithm>
#include <cstdint>

#include "simdbvh/kernels/internal/simd/ray-inl.h"
#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/triangle.h"

namespace simdbvh::kernels::simd {

namespace detail {
// The scalar reference intersect_watertight, compiled once in the baseline
// (non-AVX) scalar translation unit: called for lanes where an edge function
// is exactly 0 (the double-precision path), so no ISA-flagged copy of it exists.
bool watertight_exact(const PreparedRay& r, const Tri8& b, int lane, float tmax, float* t, float* u, float* v);
// simdbvh::detail::plane_t(origin, direction, lane's vertices) >= 0, compiled
// there too: for lanes whose float t lies in the band of tmin = 0 (triangle.h,
// detail::accept_t).
bool plane_in_front(float ox, float oy, float oz, float dx, float dy, float dz, const Tri8& b, int lane);
}  // namespace detail

// Per-lane results of one block: bit i of `hits` = lane i hits (float path);
// bit i of `exact` = lane i must be decided by detail::watertight_exact; bit i
// of `near` (a subset of `hits`) = lane i's t lies in the band of tmin = 0 and
// its side of the origin is decided by detail::plane_in_front.
template <class Arch>
struct Tri8Lanes {
    std::uint32_t hits = 0;
    std::uint32_t exact = 0;
    std::uint32_t near = 0;
    Batch<Arch> t, u_num, v_num, den;  // u = u_num / den, v = v_num / den (den = 1: already divided)
};

template <class Arch>
SIMDBVH_FORCE_INLINE Tri8Lanes<Arch> watertight_lanes(const RayPack<Arch>& r, const Tri8& b, const Batch<Arch>& tmax) {
    using B = Batch<Arch>;
    constexpr std::uint32_t kV0 = 0, kV1 = 96, kV2 = 192;
    Tri8Lanes<Arch> out;
    const B akx = load8<Arch>(&b, kV0 + r.kx) - r.okx, aky = load8<Arch>(&b, kV0 + r.ky) - r.oky,
            akz = load8<Arch>(&b, kV0 + r.kz) - r.okz;
    const B bkx = load8<Arch>(&b, kV1 + r.kx) - r.okx, bky = load8<Arch>(&b, kV1 + r.ky) - r.oky,
            bkz = load8<Arch>(&b, kV1 + r.kz) - r.okz;
    const B ckx = load8<Arch>(&b, kV2 + r.kx) - r.okx, cky = load8<Arch>(&b, kV2 + r.ky) - r.oky,
            ckz = load8<Arch>(&b, kV2 + r.kz) - r.okz;
    const B ax = akx - r.sx * akz, ay = aky - r.sy * akz;
    const B bx = bkx - r.sx * bkz, by = bky - r.sy * bkz;
    const B cx = ckx - r.sx * ckz, cy = cky - r.sy * ckz;
    const B eu = cx * by - cy * bx;
    const B ev = ax * cy - ay * cx;
    const B ew = bx * ay - by * ax;
    const B zero(0.0f);
    out.exact = bits<Arch>((eu == zero) | (ev == zero) | (ew == zero));
    // Same signs (NaN lanes fail here; in the reference they fail at the t test).
    const Mask<Arch> inside =
        ((eu >= zero) & (ev >= zero) & (ew >= zero)) | ((eu <= zero) & (ev <= zero) & (ew <= zero));
    std::uint32_t cand = bits<Arch>(inside) & ~out.exact;
    if (cand == 0) {
        out.t = out.u_num = out.v_num = out.den = zero;
        return out;
    }
    const B det = eu + ev + ew;
    const B az = r.sz * akz, bz = r.sz * bkz, cz = r.sz * ckz;
    const B tt = (eu * az + ev * bz + ew * cz) / det;
    // With tmin = 0, lanes whose t lies within the band of 0 take the side of
    // the origin from the plane in double (detail::accept_t in triangle.h).
    if (r.tmin == 0.0f) {
        const B band =
            B(simdbvh::detail::kTminBand) * xsimd::max(xsimd::max(xsimd::abs(az), xsimd::abs(bz)), xsimd::abs(cz));
        const std::uint32_t in_band = cand & bits<Arch>(xsimd::abs(tt) <= band);
        out.near = in_band & bits<Arch>((det != zero) & (tt <= tmax));
        cand &= ~in_band;
    }
    // det != 0 (ordered): a NaN det also fails here; the reference rejects it at the t test.
    cand &= bits<Arch>((det != zero) & (tt >= r.tmin) & (tt <= tmax));
    out.hits = cand | out.near;
    out.t = tt;
    out.u_num = ev;
    out.v_num = ew;
    out.den = det;
    return out;
}

template <class Arch>
SIMDBVH_FORCE_INLINE Tri8Lanes<Arch> moller_lanes(const RayPack<Arch>& r, const Tri8& b, const Batch<Arch>& tmax) {
    using B = Batch<Arch>;
    Tri8Lanes<Arch> out;
    const B v0x = B::load_aligned(b.v0x), v0y = B::load_aligned(b.v0y), v0z = B::load_aligned(b.v0z);
    const B e1x = B::load_aligned(b.v1x) - v0x, e1y = B::load_aligned(b.v1y) - v0y, e1z = B::load_aligned(b.v1z) - v0z;
    const B e2x = B::load_aligned(b.v2x) - v0x, e2y = B::load_aligned(b.v2y) - v0y, e2z = B::load_aligned(b.v2z) - v0z;
    const B px = r.dy * e2z - r.dz * e2y, py = r.dz * e2x - r.dx * e2z, pz = r.dx * e2y - r.dy * e2x;
    const B det = e1x * px + e1y * py + e1z * pz;
    const B inv = B(1.0f) / det;
    const B sx = r.ox - v0x, sy = r.oy - v0y, sz = r.oz - v0z;
    const B uu = (sx * px + sy * py + sz * pz) * inv;
    const B zero(0.0f), one(1.0f);
    // det != 0 (ordered): a NaN det makes uu NaN, which the reference rejects too.
    const Mask<Arch> ok_u = (det != zero) & (uu >= zero) & (uu <= one);
    if (bits<Arch>(ok_u) == 0) {
        out.t = out.u_num = out.v_num = out.den = zero;
        return out;
    }
    const B qx = sy * e1z - sz * e1y, qy = sz * e1x - sx * e1z, qz = sx * e1y - sy * e1x;
    const B vv = (r.dx * qx + r.dy * qy + r.dz * qz) * inv;
    const B tt = (e2x * qx + e2y * qy + e2z * qz) * inv;
    out.hits = bits<Arch>(ok_u & (vv >= zero) & (uu + vv <= one) & (tt >= r.tmin) & (tt <= tmax));
    out.t = tt;
    out.u_num = uu;
    out.v_num = vv;
    out.den = one;
    return out;
}

template <class Arch, TriangleTest kTest>
SIMDBVH_FORCE_INLINE Tri8Lanes<Arch> tri8_lanes(const RayPack<Arch>& r, const Tri8& b, float tmax) {
    if constexpr (kTest == TriangleTest::watertight) return watertight_lanes<Arch>(r, b, Batch<Arch>(tmax));
    else return moller_lanes<Arch>(r, b, Batch<Arch>(tmax));
}

// Lane i's (t, u, v) if it hits [tmin, tmax]; the exact path for `exact` lanes.
template <class Arch, TriangleTest kTest>
SIMDBVH_FORCE_INLINE bool lane_result(const RayPack<Arch>& r, const Tri8& b, const Tri8Lanes<Arch>& l, const float* t,
                                      const float* un, const float* vn, const float* den, int i, float tmax, float* ot,
                                      float* ou, float* ov) {
    if constexpr (kTest == TriangleTest::watertight) {
        if ((l.exact >> i) & 1u) {
            if (r.ray) return detail::watertight_exact(*r.ray, b, i, tmax, ot, ou, ov);
            const PreparedRay pr = prepare(*r.src);
            return detail::watertight_exact(pr, b, i, tmax, ot, ou, ov);
        }
        *ot = t[i];
        if ((l.near >> i) & 1u) {
            if (!detail::plane_in_front(r.ox, r.oy, r.oz, r.dx, r.dy, r.dz, b, i)) return false;
            *ot = std::max(t[i], 0.0f) + 0.0f;  // as accept_t: -0 becomes +0
        }
        *ou = un[i] / den[i];
        *ov = vn[i] / den[i];
    } else {
        (void)den;
        *ot = t[i];
        *ou = un[i];
        *ov = vn[i];
    }
    return true;
}

// Spills the lanes' t and barycentric numerators (and the watertight
// denominator) for the per-lane loop; nothing when only exact lanes remain.
template <class Arch, TriangleTest kTest>
SIMDBVH_FORCE_INLINE void store_lanes(const Tri8Lanes<Arch>& l, float* t, float* un, float* vn, float* den) {
    if (l.hits == 0) return;
    l.t.store_aligned(t);
    l.u_num.store_aligned(un);
    l.v_num.store_aligned(vn);
    if constexpr (kTest == TriangleTest::watertight) l.den.store_aligned(den);
}

// Closest hit: updates `best` (interval [tmin, best.t], tie rule closer())
// with the block's closest lane; returns whether `best` changed.
template <class Arch, TriangleTest kTest>
SIMDBVH_FORCE_INLINE bool intersect_tri8(const RayPack<Arch>& r, const Tri8& b, Hit& best) {
    const float tmax = best.t;
    const Tri8Lanes<Arch> l = tri8_lanes<Arch, kTest>(r, b, tmax);
    std::uint32_t m = l.hits | l.exact;
    if (m == 0) return false;
    alignas(32) float t[8], un[8], vn[8], den[8];
    store_lanes<Arch, kTest>(l, t, un, vn, den);
    bool changed = false;
    for (; m != 0; m &= m - 1) {
        const int i = __builtin_ctz(m);
        const std::uint32_t prim = b.prim[i];
        if (((l.exact >> i) & 1u) == 0 && !closer(t[i], prim, best)) continue;  // skip the divisions
        float tt, uu, vv;
        if (!lane_result<Arch, kTest>(r, b, l, t, un, vn, den, i, tmax, &tt, &uu, &vv)) continue;
        if (closer(tt, prim, best)) {
            best = Hit{tt, uu, vv, prim};
            changed = true;
        }
    }
    return changed;
}

// Any hit in [tmin, tmax]: the lowest lane that hits; fills `hit`.
template <class Arch, TriangleTest kTest>
SIMDBVH_FORCE_INLINE bool occluded_tri8(const RayPack<Arch>& r, const Tri8& b, float tmax, Hit& hit) {
    const Tri8Lanes<Arch> l = tri8_lanes<Arch, kTest>(r, b, tmax);
    std::uint32_t m = l.hits | l.exact;
    if (m == 0) return false;
    alignas(32) float t[8], un[8], vn[8], den[8];
    store_lanes<Arch, kTest>(l, t, un, vn, den);
    for (; m != 0; m &= m - 1) {
        const int i = __builtin_ctz(m);
        float tt, uu, vv;
        if (lane_result<Arch, kTest>(r, b, l, t, un, vn, den, i, tmax, &tt, &uu, &vv)) {
            hit = Hit{tt, uu, vv, b.prim[i]};
            return true;
        }
    }
    return false;
}

}  // namespace simdbvh::kernels::simd
