#pragma once
// Finite meshes whose boxes overflow float areas, the rays
// that probe them, and an OBJ writer for the CLI tests.
#include <filesystem>
#include <vector>

#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/mesh.h"

namespace test {

// The mesh that crashed the SAH collapse (SIGSEGV): one triangle
// (-1e19,-1e19,0) (1e19,-1e19,0) (0,1e19,0) (prim 0) and 8 small triangles
// near the origin at z = 1 (prims 1..8).
simdbvh::Mesh huge_triangle_mesh();
// Coordinates up to +-3e38 (box extents beyond FLT_MAX): clusters of
// triangles of size 1e37 at the 8 corners plus the huge_triangle_mesh().
simdbvh::Mesh extreme_mesh();
// Rays down onto the small triangles, onto each corner cluster (from 2e37
// above) and in every octant through the origin region.
std::vector<simdbvh::Ray> huge_mesh_rays(const simdbvh::Mesh& mesh);

void write_obj(const std::filesystem::path& file, const simdbvh::Mesh& mesh);

}  // namespace test
