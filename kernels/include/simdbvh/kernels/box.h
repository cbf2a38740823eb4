#pragma once
// Scalar ray/box slab test, conservative (Ize 2013). Plain C++, no SIMD: the
// reference that every SIMD box kernel reproduces bit for bit.
#include "simdbvh/kernels/aabb.h"
#include "simdbvh/kernels/ray.h"

namespace simdbvh {

// Returns true when the ray's [tmin, tmax] interval overlaps the box; *entry
// receives the entry distance (>= tmin). Zero direction components give
// +-inf or NaN slab distances; NaN is discarded by the min_ps/max_ps order.
// `widen` = 1 gives the plain (non-conservative) slab test, a comparison
// variant (no far slack either). The conservative far bound is
// tf * kFarWiden + r.far_slack (the slack is 0 unless tmin < 0).
inline bool intersect_box(const PreparedRay& r, const Aabb& b, float tmax, float* entry, float widen = kFarWiden) {
    const float nx = r.near_x ? b.hi.x : b.lo.x, fx = r.near_x ? b.lo.x : b.hi.x;
    const float ny = r.near_y ? b.hi.y : b.lo.y, fy = r.near_y ? b.lo.y : b.hi.y;
    const float nz = r.near_z ? b.hi.z : b.lo.z, fz = r.near_z ? b.lo.z : b.hi.z;
    const float t0x = (nx - r.org.x) * r.rdir.x, t1x = (fx - r.org.x) * r.rdir.x;
    const float t0y = (ny - r.org.y) * r.rdir.y, t1y = (fy - r.org.y) * r.rdir.y;
    const float t0z = (nz - r.org.z) * r.rdir.z, t1z = (fz - r.org.z) * r.rdir.z;
    const float tn = max_ps(t0x, max_ps(t0y, max_ps(t0z, r.tmin)));
    const float tf0 = min_ps(t1x, min_ps(t1y, min_ps(t1z, tmax)));
    const float tf = widen == 1.0f ? tf0 : tf0 * widen + r.far_slack;
    *entry = tn;
    return tn <= tf;
}

}  // namespace simdbvh
