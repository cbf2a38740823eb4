// CGAL references (see simdbvh/reference/cgal.h).
#include "simdbvh/reference/cgal.h"

#include "simdbvh/kernels/error.h"

#if SIMDBVH_HAVE_CGAL
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#endif

namespace simdbvh::reference {

#if SIMDBVH_HAVE_CGAL
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
Point to_cgal(const Vec3& v) { return Point(double(v.x), double(v.y), double(v.z)); }
}  // namespace

bool have_cgal() { return true; }

std::vector<Side> cgal_sides(const Mesh& mesh, std::span<const Vec3> points) {
    validate(mesh);
    const MeshClosure closure = mesh_closure(mesh);
    if (!closure.closed()) throw Error("cgal_sides: the mesh is not closed (CGAL's Side_of_triangle_mesh needs it)");
    using SM = CGAL::Surface_mesh<Point>;
    SM sm;
    std::vector<SM::Vertex_index> v;
    v.reserve(mesh.positions.size());
    for (const Vec3& p : mesh.positions) v.push_back(sm.add_vertex(to_cgal(p)));
    for (const Triangle& t : mesh.triangles)
        if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) sm.add_face(v[t[0]], v[t[1]], v[t[2]]);
    const CGAL::Side_of_triangle_mesh<SM, K> side(sm);
    std::vector<Side> out(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const CGAL::Bounded_side b = side(to_cgal(points[i]));
        out[i] = b == CGAL::ON_BOUNDED_SIDE ? Side::inside : (b == CGAL::ON_BOUNDARY ? Side::surface : Side::outside);
    }
    return out;
}

std::vector<CgalNearest> cgal_closest(const Mesh& mesh, std::span<const Vec3> points) {
    validate(mesh);
    std::vector<K::Triangle_3> tris;
    tris.reserve(mesh.triangles.size());
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
        tris.emplace_back(to_cgal(mesh.vertex(i, 0)), to_cgal(mesh.vertex(i, 1)), to_cgal(mesh.vertex(i, 2)));
    using Iterator = std::vector<K::Triangle_3>::const_iterator;
    using Primitive = CGAL::AABB_triangle_primitive<K, Iterator>;
    using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
    std::vector<CgalNearest> out(points.size());
    if (tris.empty()) return out;
    Tree tree(tris.cbegin(), tris.cend());
    tree.accelerate_distance_queries();
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Point q = to_cgal(points[i]);
        const auto [pt, id] = tree.closest_point_and_primitive(q);
        out[i] = CgalNearest{CGAL::to_double(CGAL::squared_distance(q, pt)), std::uint32_t(id - tris.cbegin())};
    }
    return out;
}
#else
bool have_cgal() { return false; }
std::vector<Side> cgal_sides(const Mesh&, std::span<const Vec3>) {
    throw Error("this build has no CGAL (install libcgal-dev and reconfigure)");
}
std::vector<CgalNearest> cgal_closest(const Mesh&, std::span<const Vec3>) {
    throw Error("this build has no CGAL (install libcgal-dev and reconfigure)");
}
#endif

}  // namespace simdbvh::reference
