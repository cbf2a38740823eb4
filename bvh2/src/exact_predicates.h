#pragma once
// Exact signs of the two predicates the inside test needs, for float inputs
// (see docs/exact_crossings.md). A double-precision evaluation with an error
// bound decides almost every case; when the value is within its bound, the
// determinant is expanded into products of input coordinates (exact in double
// for two factors, a two-term expansion for three) and summed exactly
// (Shewchuk's expansion arithmetic), so the sign returned is the sign of the
// real-number determinant of the float inputs.
#include "simdbvh/kernels/vec.h"

namespace simdbvh::exact {

// Sign of (b - a) x (p - a) in the xy plane: +1 when p is left of a -> b
// (counter-clockwise seen from +z), -1 right, 0 on the line.
int orient2d(const Vec3& a, const Vec3& b, const Vec3& p);
// The same in the plane of coordinates i and j (0 x, 1 y, 2 z): the sign of
// (b - a)_i (p - a)_j - (b - a)_j (p - a)_i.
int orient2d(const Vec3& a, const Vec3& b, const Vec3& p, int i, int j);

// As orient2d, but for the point p + (eps, eps^2) (eps infinitely small): a
// symbolic perturbation that is never on a line through two distinct points,
// so the result is 0 only when a and b coincide in xy.
int orient2d_perturbed(const Vec3& a, const Vec3& b, const Vec3& p);

// Sign of n . (p - a) with n = (b - a) x (c - a): which side of the plane of
// triangle (a, b, c) the point p is on (0: on the plane).
int plane_side(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p);

// Whether p lies on the closed triangle (a, b, c) (edges and vertices
// included), exactly. False for triangles of zero area.
bool on_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p);

}  // namespace simdbvh::exact
