// Ray tests of the analytic primitives, in double from the float inputs.
#include "simdbvh/scene_accel/shapes.h"
#include "directed_rounding.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace simdbvh {

namespace {

bool in_range(const PreparedRay& r, float t, float tmax) { return t >= r.tmin && t <= tmax; }  // rejects NaN

float clamp01(double x) { return static_cast<float>(std::clamp(x, 0.0, 1.0)); }

using scene_accel_detail::down;
using scene_accel_detail::up;

Aabb widen(double lo[3], double hi[3]) {
    double m = 0;
    for (int a = 0; a < 3; ++a) m = std::max({m, std::fabs(lo[a]), std::fabs(hi[a])});
    const double pad = m * 0x1p-20 + double(std::numeric_limits<float>::min());
    Aabb b;
    for (int a = 0; a < 3; ++a) {
        b.lo[a] = down(lo[a] - pad);
        b.hi[a] = up(hi[a] + pad);
    }
    return b;
}

}  // namespace

bool hit_sphere(const PreparedRay& r, const Sphere& s, float tmax, float* t, float* u, float* v) {
    const double fx = double(r.org.x) - double(s.center.x);
    const double fy = double(r.org.y) - double(s.center.y);
    const double fz = double(r.org.z) - double(s.center.z);
    const double dx = r.dir.x, dy = r.dir.y, dz = r.dir.z;
    const double a = dx * dx + dy * dy + dz * dz;
    const double b = -(fx * dx + fy * dy + fz * dz);  // the half-b of a t^2 - 2 b t + c
    const double rr = double(s.radius) * double(s.radius);
    // Closest approach: l = f + (b / a) d, disc = r^2 - |l|^2 (Haines 2019 eq. 7.5).
    // sphere_candidates() (shape_traverse-inl.h) computes this disc four spheres
    // at a time with the same operations in the same order: change both or neither.
    const double tc = b / a;
    const double lx = fx + tc * dx, ly = fy + tc * dy, lz = fz + tc * dz;
    const double disc = rr - (lx * lx + ly * ly + lz * lz);
    if (!(disc >= 0.0)) return false;
    const double c = (fx * fx + fy * fy + fz * fz) - rr;
    const double q = b + std::copysign(std::sqrt(a * disc), b);  // no cancellation
    double t0 = q != 0.0 ? c / q : 0.0, t1 = q / a;  // q == 0: b == 0 and disc == 0, one root at 0 = c/q's limit
    if (t0 > t1) std::swap(t0, t1);
    double th;
    float tf;
    if (in_range(r, tf = static_cast<float>(t0), tmax)) th = t0;
    else if (in_range(r, tf = static_cast<float>(t1), tmax)) th = t1;
    else return false;
    *t = tf;
    const double inv_r = s.radius > 0.0f ? 1.0 / double(s.radius) : 0.0;
    const double nx = (fx + th * dx) * inv_r, ny = (fy + th * dy) * inv_r, nz = (fz + th * dz) * inv_r;
    *u = clamp01((std::atan2(ny, nx) + std::numbers::pi) / (2.0 * std::numbers::pi));
    *v = clamp01(std::acos(std::clamp(nz, -1.0, 1.0)) / std::numbers::pi);
    return true;
}

bool hit_box(const PreparedRay& r, const Aabb& b, float tmax, float* t, float* u, float* v) {
    double tn = -std::numeric_limits<double>::infinity(), tf = std::numeric_limits<double>::infinity();
    int an = -1, af = -1;
    for (int a = 0; a < 3; ++a) {
        const double o = r.org[a], d = r.dir[a], lo = b.lo[a], hi = b.hi[a];
        if (d == 0.0) {
            if (o < lo || o > hi) return false;
            continue;
        }
        double t0 = (lo - o) / d, t1 = (hi - o) / d;
        if (t0 > t1) std::swap(t0, t1);
        if (t0 > tn) { tn = t0; an = a; }
        if (t1 < tf) { tf = t1; af = a; }
    }
    if (!(tn <= tf)) return false;
    double th;
    int axis;
    float tv;
    if (an >= 0 && in_range(r, tv = static_cast<float>(tn), tmax)) { th = tn; axis = an; }
    else if (af >= 0 && in_range(r, tv = static_cast<float>(tf), tmax)) { th = tf; axis = af; }
    else return false;
    *t = tv;
    const int a1 = axis == 0 ? 1 : 0, a2 = axis == 2 ? 1 : 2;
    auto face = [&](int k) {
        const double e = double(b.hi[k]) - double(b.lo[k]);
        const double p = double(r.org[k]) + th * double(r.dir[k]);
        return e > 0.0 ? clamp01((p - double(b.lo[k])) / e) : 0.0f;
    };
    *u = face(a1);
    *v = face(a2);
    return true;
}

bool hit_plane(const PreparedRay& r, const Plane& p, float tmax, float* t) {
    const double nx = p.normal.x, ny = p.normal.y, nz = p.normal.z;
    const double dn = double(r.dir.x) * nx + double(r.dir.y) * ny + double(r.dir.z) * nz;
    if (dn == 0.0) return false;
    const double num = (double(p.point.x) - double(r.org.x)) * nx + (double(p.point.y) - double(r.org.y)) * ny +
                       (double(p.point.z) - double(r.org.z)) * nz;
    const float tv = static_cast<float>(num / dn);
    if (!in_range(r, tv, tmax)) return false;
    *t = tv;
    return true;
}

Aabb sphere_bounds(const Sphere& s) {
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = double(s.center[a]) - double(s.radius);
        hi[a] = double(s.center[a]) + double(s.radius);
    }
    return widen(lo, hi);
}

Aabb padded_box(const Aabb& b) {
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = b.lo[a];
        hi[a] = b.hi[a];
    }
    return widen(lo, hi);
}

}  // namespace simdbvh
