#pragma once
// Internal: the u, v of a sphere hit (scene_hit.h: longitude and colatitude of
// the hit point's direction from the centre, each over its range), from the
// root th that hit_sphere chose, in double as hit_sphere computes them.
// hit_sphere (shapes.cpp) and the SIMD sphere leaves (shape_traverse-inl.h,
// which find the roots four spheres at a time) both call it, so a hit's u, v
// are the same bits on every path.
#include "simdbvh/kernels/ray.h"
#include "simdbvh/scene/shapes.h"

namespace simdbvh {

void sphere_uv(const PreparedRay& r, const Sphere& s, double th, float* u, float* v);

}  // namespace simdbvh
