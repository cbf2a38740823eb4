#pragma once
// Scalar ray/triangle tests. Plain C++, no SIMD: the reference arithmetic that
// every SIMD triangle kernel reproduces bit for bit (build with -ffp-contract=off).
#include "simdbvh/kernels/ray.h"

namespace simdbvh {

enum class TriangleTest : std::uint8_t { watertight, moller };

namespace detail {

// A triangle in the ray's sheared frame (Woop et al. 2013): its vertices
// relative to the origin and their sheared kx, ky coordinates. Every triangle
// sharing a vertex computes the same floats for it, which is what makes the
// test watertight. Shared by intersect_watertight and the crossing queries.
struct ShearedTriangle {
    Vec3 a, b, c;
    float ax, ay, bx, by, cx, cy;
};

inline ShearedTriangle shear(const PreparedRay& r, const Vec3& v0, const Vec3& v1, const Vec3& v2) {
    ShearedTriangle s;
    s.a = v0 - r.org;
    s.b = v1 - r.org;
    s.c = v2 - r.org;
    s.ax = s.a[r.kx] - r.sx * s.a[r.kz];
    s.ay = s.a[r.ky] - r.sy * s.a[r.kz];
    s.bx = s.b[r.kx] - r.sx * s.b[r.kz];
    s.by = s.b[r.ky] - r.sy * s.b[r.kz];
    s.cx = s.c[r.kx] - r.sx * s.c[r.kz];
    s.cy = s.c[r.ky] - r.sy * s.c[r.kz];
    return s;
}

// Edge functions U (edge v1 v2), V (v2 v0), W (v0 v1), in float.
inline void edge_functions(const ShearedTriangle& s, float* u, float* v, float* w) {
    *u = s.cx * s.by - s.cy * s.bx;
    *v = s.ax * s.cy - s.ay * s.cx;
    *w = s.bx * s.ay - s.by * s.ax;
}

// The same from products of floats, exact in double: 0 only when the ray
// passes exactly through the edge's line.
inline void edge_functions_exact(const ShearedTriangle& s, double* u, double* v, double* w) {
    *u = double(s.cx) * double(s.by) - double(s.cy) * double(s.bx);
    *v = double(s.ax) * double(s.cy) - double(s.ay) * double(s.cx);
    *w = double(s.bx) * double(s.ay) - double(s.by) * double(s.ax);
}

// The hit distance (in the prepared ray's parameter) from the edge functions.
inline float sheared_t(const PreparedRay& r, const ShearedTriangle& s, float eu, float ev, float ew, float det) {
    const float az = r.sz * s.a[r.kz], bz = r.sz * s.b[r.kz], cz = r.sz * s.c[r.kz];
    return (eu * az + ev * bz + ew * cz) / det;
}

}  // namespace detail

// Watertight ray/triangle test (Woop, Benthin, Wald 2013, JCGT 2(1)), both faces.
// Hit when tmin <= t <= tmax; u, v are the barycentrics of v1, v2.
inline bool intersect_watertight(const PreparedRay& r, const Vec3& v0, const Vec3& v1, const Vec3& v2,
                                 float tmax, float* t, float* u, float* v) {
    const detail::ShearedTriangle s = detail::shear(r, v0, v1, v2);
    float eu, ev, ew;
    detail::edge_functions(s, &eu, &ev, &ew);
    if (eu == 0.0f || ev == 0.0f || ew == 0.0f) {  // exactly on an edge: decide in double
        double du, dv, dw;
        detail::edge_functions_exact(s, &du, &dv, &dw);
        eu = static_cast<float>(du);
        ev = static_cast<float>(dv);
        ew = static_cast<float>(dw);
    }
    if ((eu < 0.0f || ev < 0.0f || ew < 0.0f) && (eu > 0.0f || ev > 0.0f || ew > 0.0f)) return false;
    const float det = eu + ev + ew;
    if (det == 0.0f) return false;
    const float tt = detail::sheared_t(r, s, eu, ev, ew, det);
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
