// The exact inside test and the closest point against CGAL:
// Side_of_triangle_mesh and an AABB tree with exact predicates, on procedural
// closed meshes and the cached real scenes, for random points, points on
// dyadic grids (rays through vertices and along edges), the mesh's vertices
// and points 1 ulp off them. Expected: no wrong inside/outside answer, the
// same surface points, distances equal to CGAL's within double rounding.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "simdbvh/query/closest_point.h"
#include "simdbvh/query/inside.h"
#include "simdbvh/reference/cgal.h"
#include "simdbvh/workloads/points.h"
#include "simdbvh/workloads/scenes.h"
#include "support/sanitizer.h"
#include "support/scene.h"

namespace simdbvh {
namespace {

std::vector<Vec3> query_points(const Mesh& mesh, std::size_t random_count) {
    std::vector<Vec3> pts = workloads::random_points(mesh.bounds(), random_count, 17);
    // About 1,000 vertices, and each one float step off along each axis.
    const std::size_t stride = std::max<std::size_t>(1, mesh.positions.size() / 1000);
    for (std::size_t v = 0; v < mesh.positions.size(); v += stride) {
        const Vec3 p = mesh.positions[v];
        pts.push_back(p);
        for (int k = 0; k < 3; ++k) {
            Vec3 q = p;
            q[k] = std::nextafter(q[k], 1e30f);
            pts.push_back(q);
            q[k] = std::nextafter(p[k], -1e30f);
            pts.push_back(q);
        }
    }
    // A grid with spacing 1/64 of the bounds (dyadic in the mesh's units when the bounds are).
    const Aabb b = mesh.bounds();
    const Vec3 e = b.extent();
    for (int i = 0; i <= 16; ++i)
        for (int j = 0; j <= 16; ++j)
            for (int k = 0; k <= 16; k += 4)
                pts.push_back({b.lo.x + e.x * float(i) / 16.0f, b.lo.y + e.y * float(j) / 16.0f,
                               b.lo.z + e.z * float(k) / 16.0f});
    return pts;
}

void check_against_cgal(const std::string& name, const Mesh& mesh, std::size_t random_count) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(mesh_closure(mesh).consistently_oriented());
    const Bvh2 bvh = Bvh2::build(mesh);
    const auto pts = query_points(mesh, random_count);
    // CGAL's Side_of_triangle_mesh counts crossings by parity: compare with our
    // parity rule, and count separately where the winding rule says otherwise
    // (self-intersecting meshes: nested sheets have winding number 2).
    std::vector<PointSide> ours(pts.size());
    InsideOptions parity;
    parity.rule = InsideOptions::Rule::parity;
    classify_points(bvh, pts, ours, parity);
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<Side> cgal = reference::cgal_sides(mesh, pts);
    std::fprintf(stderr, "%s: CGAL classified %zu points in %.2f s\n", name.c_str(), pts.size(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    std::size_t wrong = 0, surface = 0, inside = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        surface += cgal[i] == Side::surface;
        inside += cgal[i] == Side::inside;
        if (ours[i].side != cgal[i] && wrong++ < 5)
            ADD_FAILURE() << "point " << i << " (" << pts[i].x << " " << pts[i].y << " " << pts[i].z << "): ours "
                          << int(ours[i].side) << ", CGAL " << int(cgal[i]);
    }
    EXPECT_EQ(wrong, 0u) << "of " << pts.size() << " points";
    std::size_t nested = 0;
    for (const PointSide& o : ours) nested += o.side != Side::surface && std::abs(o.winding) >= 2;
    std::fprintf(stderr,
                 "%s: %zu points of %zu have winding number >= 2 (inside by the winding rule, outside by parity)\n",
                 name.c_str(), nested, pts.size());
    EXPECT_GT(surface, 10u) << "the vertices are on the surface";
    EXPECT_GT(inside, 10u);
    // Closest points: the same distance within double rounding, the same
    // triangle unless another one is as near.
    const std::size_t n = std::min<std::size_t>(pts.size(), 3000);
    const std::span<const Vec3> some(pts.data(), n);
    std::vector<ClosestPoint> near(n);
    closest_point(bvh, some, near);
    const auto ref = reference::cgal_closest(mesh, some);
    std::size_t other_triangle = 0, ties = 0;
    double magnitude = 0;
    for (const Vec3& v : mesh.positions)
        for (int k = 0; k < 3; ++k) magnitude = std::max(magnitude, double(std::fabs(v[k])));
    for (std::size_t i = 0; i < n; ++i) {
        // Both compute in double from the float coordinates: the rounding of
        // differences of coordinates of magnitude m is about m 2^-52.
        const double scale = 1e-9 * ref[i].distance2 + 8.0 * 0x1p-52 * magnitude * std::sqrt(ref[i].distance2) + 1e-30;
        ASSERT_NEAR(near[i].distance2, ref[i].distance2, scale) << "point " << i;
        if (near[i].prim == ref[i].prim) continue;
        // A different triangle: a tie at a shared edge or vertex, where our rule
        // takes the lower id (CGAL takes any).
        const TrianglePoint theirs = closest_point_on_triangle(
            some[i], mesh.vertex(ref[i].prim, 0), mesh.vertex(ref[i].prim, 1), mesh.vertex(ref[i].prim, 2));
        if (theirs.distance2 == near[i].distance2) {
            ++ties;
            ASSERT_LT(near[i].prim, ref[i].prim) << "point " << i << ": a tie goes to the lower id";
        } else {
            ASSERT_GT(theirs.distance2, near[i].distance2) << "point " << i << ": CGAL's triangle is nearer";
            ++other_triangle;
        }
    }
    std::fprintf(stderr, "%s: closest point: %zu ties (lower id taken), %zu CGAL triangles farther by rounding\n",
                 name.c_str(), ties, other_triangle);
}

TEST(CgalPoints, ProceduralClosedMeshes) {
    if (!reference::have_cgal()) GTEST_SKIP() << "built without CGAL (libcgal-dev)";
    check_against_cgal("icosphere-3", workloads::icosphere(3), 20000);
    check_against_cgal("cube", test::unit_cube(), 5000);
    Mesh far = workloads::icosphere(2, 0.5f, {1048576.0f, -3.0f, 0.25f});
    check_against_cgal("icosphere-2 at 2^20", far, 5000);
}

TEST(CgalPoints, RealScenes) {
    if (!reference::have_cgal()) GTEST_SKIP() << "built without CGAL (libcgal-dev)";
    // (dragon-res4 and dragon-res2 have non-manifold edges, the teapot has
    // holes: CGAL's Side_of_triangle_mesh needs a closed mesh.)
    // Under a sanitizer (10x slower) the bunny only; the dragon in the plain builds.
    std::vector<const char*> names = {"bunny"};
    if (!test::kUnderSanitizer) names.push_back("dragon");
    for (const char* name : names) {
        if (!test::available(name)) GTEST_SKIP() << test::skip_message(name);
        const Mesh m = test::load_or_skip(name);
        check_against_cgal(name, m, 5000);
    }
}

}  // namespace
}  // namespace simdbvh
