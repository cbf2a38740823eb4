#pragma once
// Exact signs of the two predicates the inside test needs, for float inputs
// (see docs/exact_crossings.md). A double-precision evaluation with an error
// bound decides almost every case; when the value is within its bound, the
// determinant is expanded into products of input coordinates (exact in double
// for two factors, a two-term expansion for three) and summed exactly
// (Shewchuk's expansion arithmetic), so the sign returned is the sign of the
// real-number determinant of the float inputs.
#include <cmath>

#include "simdbvh/kernels/vec.h"

namespace simdbvh::query::exact {

// orient2d's filter, inline (the inside test calls it about five times per
// point): differences of floats rounded once in double, two products, one
// difference; the error is below 8 u (|t1| + |t2|), u = 2^-53 (the
// coordinates are floats, so nothing underflows). The sign when that decides
// it, else kUndecided.
inline constexpr int kUndecided = 2;
inline int orient2d_filtered(double ax, double ay, double bx, double by, double px, double py) {
    const double t1 = (bx - ax) * (py - ay);
    const double t2 = (by - ay) * (px - ax);
    const double d = t1 - t2;
    const double bound = 0x1p-50 * (std::fabs(t1) + std::fabs(t2));
    if (d > bound) return 1;
    if (-d > bound) return -1;
    return kUndecided;
}
// The exact sign of the same determinant (expansion arithmetic), for float inputs.
int orient2d_expansion(double ax, double ay, double bx, double by, double px, double py);

// Sign of (b - a) x (p - a) in the xy plane: +1 when p is left of a -> b
// (counter-clockwise seen from +z), -1 right, 0 on the line.
inline int orient2d(const Vec3& a, const Vec3& b, const Vec3& p) {
    const int s = orient2d_filtered(a.x, a.y, b.x, b.y, p.x, p.y);
    return s != kUndecided ? s : orient2d_expansion(a.x, a.y, b.x, b.y, p.x, p.y);
}
// The same in the plane of coordinates i and j (0 x, 1 y, 2 z): the sign of
// (b - a)_i (p - a)_j - (b - a)_j (p - a)_i.
int orient2d(const Vec3& a, const Vec3& b, const Vec3& p, int i, int j);

// As orient2d, but for the point p + (eps, eps^2) (eps infinitely small): a
// symbolic perturbation that is never on a line through two distinct points,
// so the result is 0 only when a and b coincide in xy.
inline int orient2d_perturbed(const Vec3& a, const Vec3& b, const Vec3& p) {
    const int s = orient2d(a, b, p);
    if (s != 0) return s;
    // orient2d(a, b, p + (e, e^2)) = orient2d(a, b, p) - (by - ay) e + (bx - ax) e^2.
    if (a.y != b.y) return a.y > b.y ? 1 : -1;
    if (a.x != b.x) return b.x > a.x ? 1 : -1;
    return 0;
}

// Sign of n . (p - a) with n = (b - a) x (c - a): which side of the plane of
// triangle (a, b, c) the point p is on (0: on the plane).
int plane_side(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p);

// Whether p lies on the closed triangle (a, b, c) (edges and vertices
// included), exactly. False for triangles of zero area.
bool on_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p);

}  // namespace simdbvh::query::exact
