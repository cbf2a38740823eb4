#pragma once
// Inside/outside of points against a closed triangle mesh, from one ray per
// point, exactly (docs/exact_crossings.md): the ray from p along an axis
// direction (by default the one that leaves the mesh's bounds soonest), the
// crossings decided with exact predicates on the float coordinates and a
// symbolic perturbation of p, so a ray through an edge or a vertex counts each
// crossing of the surface exactly once.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh {

// Whether a mesh bounds a volume: its edges after welding vertices with equal
// coordinates. Closed: every edge is shared by exactly two triangles;
// consistently oriented: they use it in opposite directions. Triangles with
// two equal corners are ignored.
struct MeshClosure {
    std::size_t edges = 0;
    std::size_t boundary_edges = 0;     // used by one triangle
    std::size_t nonmanifold_edges = 0;  // used by three or more
    std::size_t misoriented_edges = 0;  // used twice in the same direction
    bool closed() const { return boundary_edges == 0 && nonmanifold_edges == 0; }
    bool consistently_oriented() const { return closed() && misoriented_edges == 0; }
};
MeshClosure mesh_closure(const Mesh& mesh);

enum class Side : std::uint8_t { outside = 0, inside = 1, surface = 2 };

// The axis direction of the ray a point's crossings are counted along.
enum class CountRay : std::uint8_t { plus_x, minus_x, plus_y, minus_y, plus_z, minus_z, shortest };

// The names of the rays, indexed by CountRay: "+x", "-x", "+y", "-y", "+z",
// "-z", "shortest" (the CLI's --ray and Python's ray=). Throws simdbvh::Error
// naming the value and the choices for any other name.
CountRay count_ray_named(std::string_view name);

struct PointSide {
    Side side = Side::outside;
    CountRay ray = CountRay::plus_z;  // the ray counted along (never shortest)
    std::int32_t winding = 0;     // sum over crossings of the sign of the triangle's normal along the ray (+1 leaving)
    std::uint32_t crossings = 0;  // crossings of the ray
};

struct InsideOptions {
    // How crossings decide inside: nonzero winding (right for closed, consistently
    // oriented meshes, overlapping parts included) or odd crossing count.
    enum class Rule : std::uint8_t { winding, parity } rule = Rule::winding;
    // The ray from each point: shortest = the axis direction toward the nearest
    // face of the mesh's bounds (the union of its triangles' boxes; the first of
    // +z, -z, +x, -x, +y, -y on a tie), which leaves the tree soonest; or one
    // fixed direction. For a closed mesh every direction gives the same side (and,
    // consistently oriented, the same winding); for an open one the side follows
    // the crossings of the ray counted along.
    CountRay ray = CountRay::shortest;
    int threads = 1;
};

// surface: p lies on a triangle (edges and vertices included); a point on no
// triangle is inside or outside by its crossings (see the docs page).
// A non-finite point is outside with no crossings (ray plus_z).
PointSide classify_point(const Bvh2& bvh, const Vec3& p, const InsideOptions& opts = {});
void classify_points(const Bvh2& bvh, std::span<const Vec3> points, std::span<PointSide> out,
                     const InsideOptions& opts = {});
// O(triangles) per point, the same predicates.
PointSide brute_force_classify_point(const Mesh& mesh, const Vec3& p, const InsideOptions& opts = {});

}  // namespace simdbvh
