#pragma once
// Scalar ray/triangle tests. Plain C++, no SIMD: the reference arithmetic that
// every SIMD triangle kernel reproduces bit for bit (build with -ffp-contract=off).
#include "simdbvh/kernels/ray.h"

namespace simdbvh {

enum class TriangleTest : std::uint8_t { watertight, moller };

// Watertight ray/triangle test (Woop, Benthin, Wald 2013, JCGT 2(1)), both faces.
// Hit when tmin <= t <= tmax; u, v are the barycentrics of v1, v2.
inline bool intersect_watertight(const PreparedRay& r, const Vec3& v0, const Vec3& v1, const Vec3& v2,
                                 float tmax, float* t, float* u, float* v) {
    const Vec3 a = v0 - r.org, b = v1 - r.org, c = v2 - r.org;
    const float ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
    const float bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
    const float cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
    float eu = cx * by - cy * bx;
    float ev = ax * cy - ay * cx;
    float ew = bx * ay - by * ax;
    if (eu == 0.0f || ev == 0.0f || ew == 0.0f) {  // exactly on an edge: decide in double
        eu = static_cast<float>(double(cx) * double(by) - double(cy) * double(bx));
        ev = static_cast<float>(double(ax) * double(cy) - double(ay) * double(cx));
        ew = static_cast<float>(double(bx) * double(ay) - double(by) * double(ax));
    }
    if ((eu < 0.0f || ev < 0.0f || ew < 0.0f) && (eu > 0.0f || ev > 0.0f || ew > 0.0f)) return false;
    const float det = eu + ev + ew;
    if (det == 0.0f) return false;
    const float az = r.sz * a[r.kz], bz = r.sz * b[r.kz], cz = r.sz * c[r.kz];
    const float tt = (eu * az + ev * bz + ew * cz) / det;
    if (!(tt >= r.tmin && tt <= tmax)) return false;  // also rejects NaN
    *t = tt;
    *u = ev / det;
    *v = ew / det;
    return true;
}

// Moller-Trumbore (1997), no epsilon: the fast, non-watertight comparison variant.
inline bool intersect_moller(const PreparedRay& r, const Vec3& v0, const Vec3& v1, const Vec3& v2, float tmax,
                             float* t, float* u, float* v) {
    const Vec3 e1 = v1 - v0, e2 = v2 - v0;
    const Vec3 p = cross(r.dir, e2);
    const float det = dot(e1, p);
    if (det == 0.0f) return false;
    const float inv = 1.0f / det;
    const Vec3 s = r.org - v0;
    const float uu = dot(s, p) * inv;
    if (!(uu >= 0.0f && uu <= 1.0f)) return false;
    const Vec3 q = cross(s, e1);
    const float vv = dot(r.dir, q) * inv;
    if (!(vv >= 0.0f && uu + vv <= 1.0f)) return false;
    const float tt = dot(e2, q) * inv;
    if (!(tt >= r.tmin && tt <= tmax)) return false;
    *t = tt;
    *u = uu;
    *v = vv;
    return true;
}

template <TriangleTest kTest>
inline bool intersect_triangle(const PreparedRay& r, const Vec3& v0, const Vec3& v1, const Vec3& v2, float tmax,
                               float* t, float* u, float* v) {
    if constexpr (kTest == TriangleTest::watertight) return intersect_watertight(r, v0, v1, v2, tmax, t, u, v);
    else return intersect_moller(r, v0, v1, v2, tmax, t, u, v);
}

}  // namespace simdbvh
