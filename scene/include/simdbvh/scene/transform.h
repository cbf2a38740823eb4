#pragma once
// Affine transforms of instances: a 3x4 matrix [A | b] mapping object space to
// world space (x_world = A x_object + b), its inverse computed once in double
// and rounded once to float, and the object-space ray of a world ray.
//
// The ray's direction is transformed but not normalised, so a hit's t is the
// same parameter in both spaces: o' + t d' = A^-1 (o + t d - b). t stays the
// caller's world-space parameter (up to the rounding of o' and d').
#include <array>

#include "simdbvh/kernels/aabb.h"
#include "simdbvh/kernels/ray.h"

namespace simdbvh {

// Row-major 3x4: m[r][c], column 3 is the translation.
struct Affine3 {
    std::array<std::array<float, 4>, 3> m{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};

    static Affine3 identity() { return {}; }
    static Affine3 translation(Vec3 t);
    static Affine3 scaling(float s);
    // Rotation by `radians` about a unit axis (Rodrigues), computed in double.
    static Affine3 rotation(Vec3 axis, double radians);
};
Affine3 operator*(const Affine3& a, const Affine3& b);  // a after b, in double, rounded once

// The inverse of an instance's transform and what the scene needs to bound the
// error of rays mapped through it.
struct InverseAffine {
    Affine3 inv;        // A^-1 and -A^-1 b, computed in double, each entry rounded once to float
    double cond = 1.0;  // ||A||_inf * ||A^-1||_inf (row-sum norms), >= 1
};

// Throws simdbvh::Error for a non-finite entry or a singular A: |det A| at
// most 2^-40 of the sum of the magnitudes of its six terms (a ratio that
// per-axis scales leave unchanged; a truly singular A computes below it), or
// an inverse with an entry beyond the float range.
InverseAffine invert(const Affine3& t);

// x' = M x (point) and M v (vector), in double from float inputs, rounded once.
Vec3 transform_point(const Affine3& t, Vec3 p);
Vec3 transform_vector(const Affine3& t, Vec3 v);

// The world ray in object space: origin and direction through `inv` (in
// double, each component rounded once), tmin and tmax unchanged.
Ray object_ray(const Affine3& inv, const Ray& world);

// The world box of an object box: the union of its 8 transformed corners (in
// double, rounded outward). Empty in, empty out.
Aabb transform_box(const Affine3& t, const Aabb& b);

}  // namespace simdbvh
