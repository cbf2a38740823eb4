#pragma once
// Internal: the box around a geometry's primitives, for the scene's extent
// (normals.cpp: world_bounds) and a mesh's box in validate (validate.cpp).
#include "simdbvh/scene/scene.h"

namespace simdbvh {

// Mesh vertices, sphere_bounds() per sphere, and each box as it is.
Aabb geometry_bounds(const Geometry& g);

}  // namespace simdbvh
