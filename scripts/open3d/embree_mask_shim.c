/* SPDX-License-Identifier: MIT
 * LD_PRELOAD shim for Debian 12's python3-open3d (0.16.1) against Debian's
 * libembree3 (3.13.5): Open3D's RaycastingScene fills every ray with mask = 0
 * before rtcIntersect1M (cast_rays, count_intersections and with them
 * compute_occupancy and the sign of compute_signed_distance). Upstream Open3D
 * bundles an Embree built without ray masks, where the mask is ignored;
 * Debian's Embree is built with ray masks, so a zero mask hides every geometry
 * and every ray misses. This sets each ray's mask to all ones and calls the
 * real rtcIntersect1M (and rtcOccluded1M, for test_occlusion): one store per
 * ray, then Open3D's own code path.
 * Built and preloaded by scripts/compare_rays.py (docs/open3d.md). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stddef.h>
#include <embree3/rtcore.h>

typedef void (*Intersect1M)(RTCScene, struct RTCIntersectContext*, struct RTCRayHit*, unsigned int, size_t);
typedef void (*Occluded1M)(RTCScene, struct RTCIntersectContext*, struct RTCRay*, unsigned int, size_t);

/* Open3D's module is loaded RTLD_LOCAL: RTLD_NEXT may not see libembree3, its handle does. */
static void* real_symbol(const char* name) {
    void* h = dlopen("libembree3.so.3", RTLD_LAZY | RTLD_NOLOAD);
    return dlsym(h ? h : RTLD_NEXT, name);
}

void rtcIntersect1M(RTCScene scene, struct RTCIntersectContext* context, struct RTCRayHit* rays, unsigned int count,
                    size_t stride) {
    static Intersect1M real;
    if (!real) real = (Intersect1M)real_symbol("rtcIntersect1M");
    for (unsigned int i = 0; i < count; ++i) ((struct RTCRayHit*)((char*)rays + (size_t)i * stride))->ray.mask = ~0u;
    real(scene, context, rays, count, stride);
}

void rtcOccluded1M(RTCScene scene, struct RTCIntersectContext* context, struct RTCRay* rays, unsigned int count,
                   size_t stride) {
    static Occluded1M real;
    if (!real) real = (Occluded1M)real_symbol("rtcOccluded1M");
    for (unsigned int i = 0; i < count; ++i) ((struct RTCRay*)((char*)rays + (size_t)i * stride))->mask = ~0u;
    real(scene, context, rays, count, stride);
}
