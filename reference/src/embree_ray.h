#pragma once
// Internal: our Ray as Embree's RTCRayHit (no hit yet), for rtcIntersect1.
#include <embree3/rtcore.h>

#include "simdbvh/kernels/ray.h"

namespace simdbvh::reference {

inline RTCRayHit embree_ray_hit(const Ray& r) {
    alignas(16) RTCRayHit rh;
    rh.ray.org_x = r.org.x;
    rh.ray.org_y = r.org.y;
    rh.ray.org_z = r.org.z;
    rh.ray.tnear = r.tmin;
    rh.ray.dir_x = r.dir.x;
    rh.ray.dir_y = r.dir.y;
    rh.ray.dir_z = r.dir.z;
    rh.ray.time = 0.0f;
    rh.ray.tfar = r.tmax;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

}  // namespace simdbvh::reference
