// Affine transforms: composition, inversion in double (rounded once to
// float), points, vectors, rays and boxes through them.
#include "simdbvh/scene/transform.h"
#include "directed_rounding.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "simdbvh/kernels/error.h"

namespace simdbvh {

namespace {

using D34 = std::array<std::array<double, 4>, 3>;

D34 to_double(const Affine3& t) {
    D34 d{};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) d[r][c] = double(t.m[r][c]);
    return d;
}
Affine3 to_float(const D34& d) {
    Affine3 t;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) t.m[r][c] = static_cast<float>(d[r][c]);
    return t;
}
double row_norm(const D34& d) {  // ||A||_inf of the 3x3 part
    double n = 0;
    for (int r = 0; r < 3; ++r) n = std::max(n, std::fabs(d[r][0]) + std::fabs(d[r][1]) + std::fabs(d[r][2]));
    return n;
}
// M x + w * translation, in double from floats, one rounding per component.
Vec3 apply(const Affine3& t, Vec3 p, double w) {
    Vec3 out;
    for (int r = 0; r < 3; ++r) {
        const auto& m = t.m[r];
        out[r] = static_cast<float>(
            ((double(m[0]) * double(p.x) + double(m[1]) * double(p.y)) + double(m[2]) * double(p.z)) +
            w * double(m[3]));
    }
    return out;
}
using scene::detail::down;
using scene::detail::up;

}  // namespace

Affine3 Affine3::translation(Vec3 t) {
    Affine3 a;
    a.m[0][3] = t.x;
    a.m[1][3] = t.y;
    a.m[2][3] = t.z;
    return a;
}
Affine3 Affine3::scaling(float s) {
    Affine3 a;
    a.m[0][0] = a.m[1][1] = a.m[2][2] = s;
    return a;
}
Affine3 Affine3::rotation(Vec3 axis, double radians) {
    const double x = axis.x, y = axis.y, z = axis.z;
    const double n = std::sqrt(x * x + y * y + z * z);
    if (!(n > 0) || !std::isfinite(n)) throw Error("rotation: the axis must be finite and non-zero");
    const double ux = x / n, uy = y / n, uz = z / n;
    const double c = std::cos(radians), s = std::sin(radians), k = 1.0 - c;
    D34 d{{{c + ux * ux * k, ux * uy * k - uz * s, ux * uz * k + uy * s, 0},
           {uy * ux * k + uz * s, c + uy * uy * k, uy * uz * k - ux * s, 0},
           {uz * ux * k - uy * s, uz * uy * k + ux * s, c + uz * uz * k, 0}}};
    return to_float(d);
}

Affine3 operator*(const Affine3& a, const Affine3& b) {
    const D34 x = to_double(a), y = to_double(b);
    D34 d{};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) {
            double s = x[r][0] * y[0][c] + x[r][1] * y[1][c] + x[r][2] * y[2][c];
            if (c == 3) s += x[r][3];
            d[r][c] = s;
        }
    return to_float(d);
}

InverseAffine invert(const Affine3& t) {
    for (const auto& row : t.m)
        for (float v : row)
            if (!std::isfinite(v)) throw Error("transform: non-finite entry");
    const D34 a = to_double(t);
    // Cofactors of the 3x3 part.
    const double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
    const double c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
    const double c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
    const double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
    const double na = row_norm(a);
    // The condition test: |det| against the sum of the magnitudes of its six
    // terms (the permanent of |A|). The ratio is 1 for any per-axis scale,
    // scaled rotation or permutation, and scaling rows or columns leaves it
    // unchanged (scale [1e-11, 1e10, 1] passes). The products of two floats
    // are exact in double, so the computed det is within 4u = 2^-51 of that
    // sum from the true one: a singular A (true det 0) stays below 2^-40.
    const double terms = std::fabs(a[0][0]) * (std::fabs(a[1][1] * a[2][2]) + std::fabs(a[1][2] * a[2][1])) +
                         std::fabs(a[0][1]) * (std::fabs(a[1][2] * a[2][0]) + std::fabs(a[1][0] * a[2][2])) +
                         std::fabs(a[0][2]) * (std::fabs(a[1][0] * a[2][1]) + std::fabs(a[1][1] * a[2][0]));
    constexpr double kMinRatio = 0x1p-40;
    if (!(std::fabs(det) > kMinRatio * terms)) {
        char ratio[32];
        std::snprintf(ratio, sizeof ratio, "%.3g", terms > 0 ? std::fabs(det) / terms : 0.0);
        throw Error(std::string("transform: singular: |det| is ") + ratio +
                    " of the sum of the magnitudes of its six terms, at most 2^-40 (9.1e-13): A is singular or "
                    "too close to it to invert (per-axis scales do not change this ratio)");
    }
    D34 inv{};
    inv[0][0] = c00 / det;
    inv[1][0] = c01 / det;
    inv[2][0] = c02 / det;
    inv[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) / det;
    inv[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) / det;
    inv[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) / det;
    inv[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det;
    inv[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) / det;
    inv[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det;
    for (int r = 0; r < 3; ++r) inv[r][3] = -(inv[r][0] * a[0][3] + inv[r][1] * a[1][3] + inv[r][2] * a[2][3]);
    const double max_float = std::numeric_limits<float>::max();
    for (const auto& row : inv)
        for (double v : row)
            if (!(std::fabs(v) <= max_float)) throw Error("transform: singular (the inverse overflows)");
    InverseAffine out;
    out.inv = to_float(inv);
    out.cond = std::max(1.0, na * row_norm(inv));
    return out;
}

Vec3 transform_point(const Affine3& t, Vec3 p) { return apply(t, p, 1.0); }
Vec3 transform_vector(const Affine3& t, Vec3 v) { return apply(t, v, 0.0); }

Ray object_ray(const Affine3& inv, const Ray& world) {
    Ray r = world;
    r.org = apply(inv, world.org, 1.0);
    r.dir = apply(inv, world.dir, 0.0);
    return r;
}

Aabb transform_box(const Affine3& t, const Aabb& b) {
    Aabb out;
    if (b.is_empty()) return out;
    const D34 d = to_double(t);
    double lo[3], hi[3];
    for (int r = 0; r < 3; ++r) {
        lo[r] = hi[r] = d[r][3];
        for (int c = 0; c < 3; ++c) {  // the extreme corners per row: min/max of each term
            const double p = d[r][c] * double(b.lo[c]), q = d[r][c] * double(b.hi[c]);
            lo[r] += std::min(p, q);
            hi[r] += std::max(p, q);
        }
    }
    for (int r = 0; r < 3; ++r) {
        // A few double roundings: widen by a relative 2^-40 before rounding outward.
        const double m = std::max(std::fabs(lo[r]), std::fabs(hi[r])) * 0x1p-40;
        out.lo[r] = down(lo[r] - m);
        out.hi[r] = up(hi[r] + m);
    }
    return out;
}

}  // namespace simdbvh
