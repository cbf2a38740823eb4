#pragma once
// Analytic primitives of a scene: spheres, axis-aligned boxes, planes, and
// their ray tests. Each test takes a prepared ray (kernels/ray.h: the kernel's
// parameterisation, tmin/tmax included) and the current tmax, and reports a
// hit when tmin <= t <= tmax (t rounded to float), with u, v as in scene_hit.h.
// All arithmetic is in double from the float inputs, with one rounding of t,
// u, v to float, so every path that calls these gets the same bits.
#include <span>

#include "simdbvh/kernels/aabb.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/kernels/ray.h"

namespace simdbvh {

struct Sphere {  // 16 bytes
    Vec3 center;
    float radius = 0.0f;  // >= 0
};
static_assert(sizeof(Sphere) == 16);

struct Plane {  // unbounded; kept outside the hierarchies, tested per ray
    Vec3 point;
    Vec3 normal;  // not necessarily unit; non-zero
};

// Ray/sphere, after Haines, Guenther, Akenine-Moeller, "Precision Improvements
// for Ray/Sphere Intersection" (Ray Tracing Gems, 2019, ch. 7): the
// discriminant from the closest-approach vector (r^2 - |f - (f.d/d.d) d|^2,
// f = o - c, no cancellation of b^2 - ac for distant spheres) and the stable
// root pair q = b + sign(b) sqrt(d.d * disc), t = c/q and q/(d.d). The nearer
// root in [tmin, tmax] is reported (the far one when the origin is inside).
bool hit_sphere(const PreparedRay& r, const Sphere& s, float tmax, float* t, float* u, float* v);

// Ray/box slab test in double: each slab distance (plane - o) / d is one
// correctly rounded division of an exact difference (floats in double), so two
// boxes sharing a face compute the same t for it and a ray through the shared
// face enters one where it leaves the other (no crack between them when their
// other bounds are equal). A zero direction component keeps the slab when the
// origin lies in it. The entry t is reported, the exit t when the entry is
// before tmin (origin inside).
bool hit_box(const PreparedRay& r, const Aabb& b, float tmax, float* t, float* u, float* v);

// Ray/plane: t = (p - o).n / d.n in double; a ray parallel to the plane misses.
bool hit_plane(const PreparedRay& r, const Plane& p, float tmax, float* t);

// The nearest of `planes` that r hits in [tmin, tmax] (ties: the lower index;
// any: the first in index order), its t in *t; -1 if none. hit_plane's bits
// for that plane: the same arithmetic per plane, chosen without branches.
int nearest_plane(const PreparedRay& r, std::span<const Plane> planes, float tmax, bool any, float* t);

// nearest_plane for a batch: for each ray, on prepare_scaled(rays[i]) with
// its own tmax, plane[i] = the plane's index or -1 (none, or an invalid ray)
// and t[i] = its t in the caller's parameter (to_caller_t). The SIMD ISAs
// test four rays per vector of doubles with the same operations per lane as
// nearest_plane (the scalar one calls it per ray), so every ISA gives its
// bits. Throws simdbvh::Error when plane or t is smaller than rays.
void nearest_planes(std::span<const Ray> rays, std::span<const Plane> planes, bool any, std::span<int> plane,
                    std::span<float> t, Isa isa = active_isa());

// Conservative bounds for the hierarchies over spheres and boxes: the exact
// bounds widened by 2^-20 of their largest magnitude (plus FLT_MIN), far more
// than the double tests' rounding, so a box test that is conservative for the
// float ray (Ize 2013) never culls a primitive the test above would hit.
Aabb sphere_bounds(const Sphere& s);
Aabb padded_box(const Aabb& b);

}  // namespace simdbvh
