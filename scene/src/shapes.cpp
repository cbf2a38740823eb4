// Ray tests of the analytic primitives, in double from the float inputs.
#include "simdbvh/scene/shapes.h"
#include "directed_rounding.h"
#include "sphere_uv.h"
#include "plane_batch.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/internal/by_isa.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>

namespace simdbvh {

namespace {

bool in_range(const PreparedRay& r, float t, float tmax) { return t >= r.tmin && t <= tmax; }  // rejects NaN

float clamp01(double x) { return static_cast<float>(std::clamp(x, 0.0, 1.0)); }

// Branch-free select: the bits of a if c, else b's.
double pick(bool c, double a, double b) {
    const std::uint64_t m = std::uint64_t(0) - std::uint64_t(c);
    return std::bit_cast<double>((std::bit_cast<std::uint64_t>(a) & m) | (std::bit_cast<std::uint64_t>(b) & ~m));
}

// atan2(y, x) to within 1.1e-14 for finite y, x, for two (y, x) pairs at
// once (a sphere hit's u and v), lane by lane in a fixed sequence of
// operations (the same bits from every caller) and without branches. libm's
// atan2 and acos cost the sphere's u, v 45 ns per hit, a sixth of an
// incoherent ray's time on spheres-1000 (one lane of this: 11 ns against
// libm's 25 ns per call on random quadrants, where its branches mispredict).
// With m = min / max of |x|, |y|: m > tan(pi/8) reduces by atan(m) = pi/4 +
// atan((m - 1) / (m + 1)), then atan(a) = a P(a^2), P a degree-8
// least-squares fit on Chebyshev nodes of [0, tan(pi/8)^2] (worst error
// 1.1e-14), evaluated by Estrin's scheme. Quadrants and signed zeros as
// atan2's: atan2(+-0, +0) = +-0, atan2(+-0, -0) = +-pi. Two lanes of SSE2,
// the baseline of every x86-64 CPU, so this file needs no ISA flags.
typedef double Double2 __attribute__((vector_size(16)));
typedef long long Long2 __attribute__((vector_size(16)));

// Lanes of a where c (all ones or zero per lane), else b's.
Double2 pick2(Long2 c, Double2 a, Double2 b) { return Double2((Long2(a) & c) | (Long2(b) & ~c)); }

Double2 poly_atan2(Double2 y, Double2 x) {
    constexpr double kPi = std::numbers::pi, kTanPi8 = 0.41421356237309503;
    const Long2 sign = Long2{} + std::numeric_limits<long long>::min();
    const Double2 ax = Double2(Long2(x) & ~sign), ay = Double2(Long2(y) & ~sign);
    const Long2 swap = ay > ax;
    const Double2 mx = pick2(swap, ay, ax), mn = pick2(swap, ax, ay);
    const Long2 reduce = mn > kTanPi8 * mx;
    const Double2 a = pick2(reduce, mn - mx, mn) / pick2(reduce, mn + mx, pick2(mx == 0.0, Double2{} + 1.0, mx));
    const Double2 s = a * a, s2 = s * s, s4 = s2 * s2;
    constexpr double c0 = 0.9999999999999728, c1 = -0.3333333333086919, c2 = 0.1999999961282265,
                     c3 = -0.142856907900981, c4 = 0.1111039336712796, c5 = -0.09078494812490004,
                     c6 = 0.07564406649945972, c7 = -0.058770120425809196, c8 = 0.030698749319849665;
    const Double2 p = ((c0 + c1 * s) + s2 * (c2 + c3 * s)) + s4 * (((c4 + c5 * s) + s2 * (c6 + c7 * s)) + s4 * c8);
    Double2 r = pick2(reduce, Double2{} + kPi / 4, Double2{}) + a * p;  // atan(mn / mx), in [0, pi/4]
    r = pick2(swap, kPi / 2 - r, r);
    r = pick2((Long2(x) & sign) != 0, kPi - r, r);           // x's sign bit
    return Double2((Long2(r) & ~sign) | (Long2(y) & sign));  // copysign(r, y)
}

using scene::detail::down;
using scene::detail::up;

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
    // sphere_roots() (shape_traverse-inl.h) computes this disc, c, q and both
    // roots four spheres at a time with the same operations in the same
    // order: change both or neither.
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
    sphere_uv(r, s, th, u, v);
    return true;
}

void sphere_uv(const PreparedRay& r, const Sphere& s, double th, float* u, float* v) {
    const double fx = double(r.org.x) - double(s.center.x);
    const double fy = double(r.org.y) - double(s.center.y);
    const double fz = double(r.org.z) - double(s.center.z);
    const double dx = r.dir.x, dy = r.dir.y, dz = r.dir.z;
    const double inv_r = s.radius > 0.0f ? 1.0 / double(s.radius) : 0.0;
    const double nx = (fx + th * dx) * inv_r, ny = (fy + th * dy) * inv_r, nz = (fz + th * dz) * inv_r;
    // u from atan2(n.y, n.x), v from atan2(|n.xy|, n.z) (acos(n.z) for a unit n), in one call.
    const Double2 at = poly_atan2(Double2{ny, std::sqrt(nx * nx + ny * ny)}, Double2{nx, nz});
    *u = clamp01((at[0] + std::numbers::pi) / (2.0 * std::numbers::pi));
    *v = clamp01(at[1] / std::numbers::pi);
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
        if (t0 > tn) {
            tn = t0;
            an = a;
        }
        if (t1 < tf) {
            tf = t1;
            af = a;
        }
    }
    if (!(tn <= tf)) return false;
    double th;
    int axis;
    float tv;
    if (an >= 0 && in_range(r, tv = static_cast<float>(tn), tmax)) {
        th = tn;
        axis = an;
    } else if (af >= 0 && in_range(r, tv = static_cast<float>(tf), tmax)) {
        th = tf;
        axis = af;
    } else return false;
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

namespace {
// t = (p - o).n / d.n in double, rounded once to float; *parallel when
// d.n == 0 (then t is meaningless: the division is by 1, never by zero).
// hit_plane and nearest_plane both take their t here.
inline float plane_t(const PreparedRay& r, const Plane& p, bool* parallel) {
    const double nx = p.normal.x, ny = p.normal.y, nz = p.normal.z;
    const double dn = double(r.dir.x) * nx + double(r.dir.y) * ny + double(r.dir.z) * nz;
    const double num = (double(p.point.x) - double(r.org.x)) * nx + (double(p.point.y) - double(r.org.y)) * ny +
                       (double(p.point.z) - double(r.org.z)) * nz;
    *parallel = dn == 0.0;
    return static_cast<float>(num / pick(*parallel, 1.0, dn));
}
}  // namespace

bool hit_plane(const PreparedRay& r, const Plane& p, float tmax, float* t) {
    bool parallel;
    const float tv = plane_t(r, p, &parallel);
    if (parallel || !in_range(r, tv, tmax)) return false;
    *t = tv;
    return true;
}

int nearest_plane(const PreparedRay& r, std::span<const Plane> planes, float tmax, bool any, float* t) {
    // Every plane's t (the divisions overlap), then the choice by selects:
    // which planes a ray hits, and which is nearest, is as good as random per
    // ray, and branches on it mispredicted.
    std::uint32_t best = std::uint32_t(planes.size());  // none
    float bt = std::numeric_limits<float>::infinity();
    for (std::uint32_t k = 0; k < planes.size(); ++k) {
        bool parallel;
        const float tv = plane_t(r, planes[k], &parallel);
        // In range, and nearer than the best so far (ties: the lower plane;
        // any: the first plane hit, so nothing after it replaces it). Bit
        // masks, not ?: (GCC turned those back into branches).
        const bool take = !parallel & (tv >= r.tmin) & (tv <= tmax) & ((best == planes.size()) | (!any & (tv < bt)));
        const std::uint32_t m = 0u - std::uint32_t(take);
        best = (k & m) | (best & ~m);
        bt = std::bit_cast<float>((std::bit_cast<std::uint32_t>(tv) & m) | (std::bit_cast<std::uint32_t>(bt) & ~m));
    }
    if (best == planes.size()) return -1;
    *t = bt;
    return int(best);
}

void nearest_planes(std::span<const Ray> rays, std::span<const Plane> planes, bool any, std::span<int> plane,
                    std::span<float> t, Isa isa) {
    require(isa);
    simdbvh::detail::check_size(plane.size(), rays.size(), "nearest_planes: plane");
    simdbvh::detail::check_size(t.size(), rays.size(), "nearest_planes: t");
    namespace sa = scene::detail;
#if defined(__x86_64__)
    using Avx2 = sa::avx2::PlaneTag;
    using Avx512 = sa::avx512::PlaneTag;
#else  // not built here (require() has refused every ISA but scalar)
    using Avx2 = void;
    using Avx512 = void;
#endif
    // The scalar set is void: nearest_plane per ray.
    kernels::detail::by_isa<void, Avx2, Avx512>(isa, [&]<class Tag>() {
        if constexpr (!std::is_void_v<Tag>) {
            sa::PlaneBatch<Tag>::nearest(rays, planes, any, plane.data(), t.data());
        } else {
            for (std::size_t i = 0; i < rays.size(); ++i) {
                const PreparedRay r = prepare_scaled(rays[i]);
                float ti = 0.0f;
                plane[i] = r.valid ? nearest_plane(r, planes, r.tmax, any, &ti) : -1;
                t[i] = plane[i] < 0 ? 0.0f : to_caller_t(r, ti);
            }
        }
    });
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
