#pragma once
// CGAL references for the point queries, when the build found CGAL
// (Debian libcgal-dev): Side_of_triangle_mesh for inside/outside and an AABB
// tree for the closest point, both with the exact-predicates kernel
// (Exact_predicates_inexact_constructions_kernel: exact predicates, distances
// computed in double). Without CGAL, have_cgal() is false and the functions
// throw simdbvh::Error.
#include <cstdint>
#include <span>
#include <vector>

#include "simdbvh/query/inside.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::reference {

bool have_cgal();

// CGAL's side of each point: outside, inside or surface (ON_BOUNDARY). The
// mesh must be closed (CGAL's precondition); throws simdbvh::Error otherwise.
std::vector<Side> cgal_sides(const Mesh& mesh, std::span<const Vec3> points);

struct CgalNearest {
    double distance2 = 0;  // squared distance to CGAL's closest point
    std::uint32_t prim = 0;
};
std::vector<CgalNearest> cgal_closest(const Mesh& mesh, std::span<const Vec3> points);

}  // namespace simdbvh::reference
