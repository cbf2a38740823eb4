#pragma once
// Internal: the box around a geometry's primitives, for the scene's extent
// (normals.cpp: world_bounds) and validate's range check (validate.cpp).
#include "simdbvh/scene_accel/scene.h"

namespace simdbvh {

// Mesh vertices, sphere_bounds() per sphere, and each box as it is (`padded`
// false) or as the bottom tree bounds it (padded_box(), `padded` true).
Aabb geometry_bounds(const Geometry& g, bool padded);

}  // namespace simdbvh
