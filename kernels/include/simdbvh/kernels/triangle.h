#pragma once
// Scalar ray/triangle tests. Plain C++, no SIMD: the reference arithmetic that
// every SIMD triangle kernel reproduces bit for bit (build with -ffp-contract=off).
#include <algorithm>
#include <cmath>

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

// The comparison of a hit's t with tmin = 0 near 0. The box tests decide which
// side of the origin a slab lies on exactly (the sign of (bound - origin) * (1/d)
// survives rounding), but a float t from the sheared depths carries an error
// of a few ulps of the triangle's largest depth, so a ray that leaves a face
// from within rounding of it (true t slightly below tmin) could round to a t
// at or above 0: the brute force would take that hit and the trees, whose
// boxes lie behind the origin, would not. So with tmin = 0, where the float t
// lies within kTminBand of the largest depth from 0, the side of the origin is
// decided on the t of the triangle's plane computed in double from the
// vertices, origin and direction; a hit kept there reports max(t, 0), never -0
// (another tmin keeps the float comparison, so a hit re-traced with
// tmin = tmax = its t hits again) (docs/accuracy.md,
// "Rays that start on or near a surface"). Every path calls this (the SIMD
// kernels send such lanes to the scalar test), so all agree bit for bit.
inline constexpr float kTminBand = 0x1p-12f;

inline float tmin_band(const PreparedRay& r, const ShearedTriangle& s) {
    const float az = std::fabs(r.sz * s.a[r.kz]), bz = std::fabs(r.sz * s.b[r.kz]), cz = std::fabs(r.sz * s.c[r.kz]);
    return kTminBand * std::max(std::max(az, bz), cz);
}

// The t at which the ray meets the plane of (v0, v1, v2), in double (the
// differences of floats are exact there; the products carry 2^-53 errors).
inline double plane_t(const Vec3& org, const Vec3& dir, const Vec3& v0, const Vec3& v1, const Vec3& v2) {
    const double e1x = double(v1.x) - v0.x, e1y = double(v1.y) - v0.y, e1z = double(v1.z) - v0.z;
    const double e2x = double(v2.x) - v0.x, e2y = double(v2.y) - v0.y, e2z = double(v2.z) - v0.z;
    const double nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;
    const double px = double(v0.x) - org.x, py = double(v0.y) - org.y, pz = double(v0.z) - org.z;
    return (nx * px + ny * py + nz * pz) / (nx * dir.x + ny * dir.y + nz * dir.z);
}

// Whether a hit at float t lies in [tmin, tmax]; with tmin = 0 near 0 (see
// kTminBand) decided in double, and then t is raised to 0 if it rounded below.
inline bool accept_t(const PreparedRay& r, const ShearedTriangle& s, const Vec3& v0, const Vec3& v1, const Vec3& v2,
                     float tmax, float* t) {
    if (r.tmin == 0.0f && std::fabs(*t) <= tmin_band(r, s)) {
        if (!(*t <= tmax) || !(plane_t(r.org, r.dir, v0, v1, v2) >= 0.0)) return false;
        *t = std::max(*t, 0.0f) + 0.0f;  // + 0: -0 becomes +0
        return true;
    }
    return *t >= r.tmin && *t <= tmax;  // also rejects NaN
}

}  // namespace detail

// Watertight ray/triangle test (Woop, Benthin, Wald 2013, JCGT 2(1)), both faces.
// Hit when tmin <= t <= tmax; u, v are the barycentrics of v1, v2.
inline bool intersect_watertight(const PreparedRay& r, const Vec3& v0, const Vec3& v1, const Vec3& v2, float tmax,
                                 float* t, float* u, float* v) {
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
    float tt = detail::sheared_t(r, s, eu, ev, ew, det);
    if (!detail::accept_t(r, s, v0, v1, v2, tmax, &tt)) return false;
    *t = tt;
    *u = ev / det;
    *v = ew / det;
    return true;
}

// Moller-Trumbore (1997), no epsilon: the fast, non-watertight comparison variant.
inline bool intersect_moller(const PreparedRay& r, const Vec3& v0, const Vec3& v1, const Vec3& v2, float tmax, float* t,
                             float* u, float* v) {
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
