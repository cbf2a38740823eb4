// Closest point queries: the per-triangle Voronoi regions against
// hand-computed answers, the unit cube against its analytic distance, and the
// BVH2 bit-identical to the brute force (ties to the lower id, max_distance,
// threads, bad points).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "simdbvh/query/closest_point.h"
#include "simdbvh/query/signed_distance.h"
#include "simdbvh/workloads/scenes.h"
#include "support/scene.h"

namespace simdbvh {
namespace {

bool same(const ClosestPoint& a, const ClosestPoint& b) {
    return std::memcmp(&a.point, &b.point, sizeof(Vec3)) == 0 && std::memcmp(&a.distance, &b.distance, 4) == 0 &&
           a.prim == b.prim && std::memcmp(&a.u, &b.u, 4) == 0 && std::memcmp(&a.v, &b.v, 4) == 0 &&
           std::memcmp(&a.distance2, &b.distance2, 8) == 0;
}

std::vector<Vec3> random_points(const Aabb& box, std::size_t n, unsigned seed, float grow = 0.5f) {
    std::mt19937 rng(seed);
    const Vec3 e = box.extent();
    std::uniform_real_distribution<float> u(-grow, 1.0f + grow);
    std::vector<Vec3> pts(n);
    for (Vec3& p : pts) p = {box.lo.x + e.x * u(rng), box.lo.y + e.y * u(rng), box.lo.z + e.z * u(rng)};
    return pts;
}

TEST(ClosestPointTriangle, EveryVoronoiRegion) {
    const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
    struct Case {
        Vec3 p;
        double x, y, z, u, v, d2;
    };
    const Case cases[] = {
        {{0.25f, 0.25f, 2.0f}, 0.25, 0.25, 0, 0.25, 0.25, 4.0},  // face
        {{-1.0f, -1.0f, 0.0f}, 0, 0, 0, 0, 0, 2.0},              // vertex v0
        {{2.0f, -1.0f, 0.0f}, 1, 0, 0, 1, 0, 2.0},               // vertex v1
        {{-1.0f, 3.0f, 1.0f}, 0, 1, 0, 0, 1, 6.0},               // vertex v2
        {{0.5f, -1.0f, 3.0f}, 0.5, 0, 0, 0.5, 0, 10.0},          // edge v0 v1
        {{-2.0f, 0.5f, 0.0f}, 0, 0.5, 0, 0, 0.5, 4.0},           // edge v0 v2
        {{1.0f, 1.0f, 0.0f}, 0.5, 0.5, 0, 0.5, 0.5, 0.5},        // edge v1 v2
        {{0.5f, 0.25f, 0.0f}, 0.5, 0.25, 0, 0.5, 0.25, 0.0},     // on the face
    };
    for (const Case& k : cases) {
        const TrianglePoint t = closest_point_on_triangle(k.p, a, b, c);
        EXPECT_DOUBLE_EQ(t.x, k.x) << k.p.x << " " << k.p.y << " " << k.p.z;
        EXPECT_DOUBLE_EQ(t.y, k.y) << k.p.x << " " << k.p.y << " " << k.p.z;
        EXPECT_DOUBLE_EQ(t.z, k.z) << k.p.x << " " << k.p.y << " " << k.p.z;
        EXPECT_DOUBLE_EQ(t.u, k.u) << k.p.x << " " << k.p.y << " " << k.p.z;
        EXPECT_DOUBLE_EQ(t.v, k.v) << k.p.x << " " << k.p.y << " " << k.p.z;
        EXPECT_DOUBLE_EQ(t.distance2, k.d2) << k.p.x << " " << k.p.y << " " << k.p.z;
    }
}

TEST(ClosestPointTriangle, DegenerateTrianglesAreTheirSegments) {
    // Collinear: the point's distance to the segment [0, 2] on the x axis.
    const TrianglePoint t = closest_point_on_triangle({1.5f, 1.0f, 0.0f}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0});
    EXPECT_DOUBLE_EQ(t.distance2, 1.0);
    EXPECT_DOUBLE_EQ(t.x, 1.5);
    // All three vertices equal: the vertex.
    const TrianglePoint q = closest_point_on_triangle({3.0f, 4.0f, 0.0f}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0});
    EXPECT_DOUBLE_EQ(q.distance2, 25.0);
    EXPECT_FALSE(std::isnan(q.u) || std::isnan(q.v));
}

// The unit cube's distance field is known in closed form.
TEST(ClosestPoint, UnitCubeMatchesTheAnalyticDistance) {
    const Mesh cube = test::unit_cube();
    const Bvh2 bvh = Bvh2::build(cube);
    const auto pts = random_points(Aabb{{0, 0, 0}, {1, 1, 1}}, 5000, 3, 1.0f);
    for (const Vec3& p : pts) {
        double want2 = 0;
        const bool inside = p.x > 0 && p.x < 1 && p.y > 0 && p.y < 1 && p.z > 0 && p.z < 1;
        if (inside) {
            double m = 1;
            for (int k = 0; k < 3; ++k) m = std::min({m, double(p[k]), 1.0 - double(p[k])});
            want2 = m * m;
        } else {
            for (int k = 0; k < 3; ++k) {
                const double d = std::max({0.0, -double(p[k]), double(p[k]) - 1.0});
                want2 += d * d;
            }
        }
        const ClosestPoint c = closest_point(bvh, p);
        ASSERT_TRUE(c.found());
        EXPECT_NEAR(c.distance2, want2, 1e-12 * std::max(1.0, want2)) << p.x << " " << p.y << " " << p.z;
        // The point lies on the cube's surface and at that distance.
        const double dx = double(c.point.x) - p.x, dy = double(c.point.y) - p.y, dz = double(c.point.z) - p.z;
        EXPECT_NEAR(std::sqrt(dx * dx + dy * dy + dz * dz), std::sqrt(want2), 1e-6);
        const float on = std::min({c.point.x, c.point.y, c.point.z, 1 - c.point.x, 1 - c.point.y, 1 - c.point.z});
        EXPECT_NEAR(on, 0.0f, 1e-6f);
    }
}

void expect_bvh_equals_brute(const Mesh& mesh, const std::vector<Vec3>& pts, const PointQueryOptions& o,
                             const char* what) {
    const Bvh2 bvh = Bvh2::build(mesh);
    std::vector<ClosestPoint> batch(pts.size());
    closest_point(bvh, pts, batch, o);
    std::size_t bad = 0, found = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const ClosestPoint want = brute_force_closest_point(mesh, pts[i], o);
        found += want.found();
        if (!same(batch[i], want) && bad++ < 5)
            ADD_FAILURE() << what << " point " << i << ": bvh prim " << batch[i].prim << " d2 " << batch[i].distance2
                          << ", brute prim " << want.prim << " d2 " << want.distance2;
    }
    EXPECT_EQ(bad, 0u) << what;
    EXPECT_GT(found, 0u) << what;
}

TEST(ClosestPoint, Bvh2IsBitIdenticalToBruteForce) {
    const Mesh sphere = workloads::icosphere(3);
    expect_bvh_equals_brute(sphere, random_points(sphere.bounds(), 3000, 5), {}, "icosphere-3");
    const Mesh soup = workloads::random_soup(3000, 11);  // overlapping triangles: many near-equal distances
    expect_bvh_equals_brute(soup, random_points(soup.bounds(), 3000, 6), {}, "soup-3000");
    PointQueryOptions near;
    near.max_distance = 0.05f;
    expect_bvh_equals_brute(soup, random_points(soup.bounds(), 3000, 7), near, "soup-3000, max 0.05");
    PointQueryOptions threads;
    threads.threads = 2;
    expect_bvh_equals_brute(sphere, random_points(sphere.bounds(), 5000, 8), threads, "icosphere-3, 2 threads");
}

// A query point on a shared vertex is at distance 0 from every triangle
// around it: the lowest id among them wins, on every path.
TEST(ClosestPoint, TiesGoToTheLowerTriangleId) {
    const Mesh sphere = workloads::icosphere(2);
    const Bvh2 bvh = Bvh2::build(sphere);
    for (std::uint32_t v = 0; v < sphere.positions.size(); v += 7) {
        std::uint32_t lowest = kInvalidPrim;
        for (std::uint32_t t = 0; t < sphere.triangles.size(); ++t)
            for (int k = 0; k < 3; ++k)
                if (sphere.triangles[t][k] == v) lowest = std::min(lowest, t);
        const ClosestPoint c = closest_point(bvh, sphere.positions[v]);
        EXPECT_EQ(c.prim, lowest) << "vertex " << v;
        EXPECT_EQ(c.distance, 0.0f);
        EXPECT_TRUE(same(c, brute_force_closest_point(sphere, sphere.positions[v])));
    }
    // Duplicates: the same triangle as ids 0, 1 and 2; the query must return 0.
    Mesh dup = test::one_triangle();
    dup.triangles = {dup.triangles[0], dup.triangles[0], dup.triangles[0]};
    EXPECT_EQ(closest_point(Bvh2::build(dup), {0.2f, 0.2f, 1.0f}).prim, 0u);
}

TEST(ClosestPoint, MaxDistanceBadPointsAndEmptyMeshes) {
    const Mesh tri = test::one_triangle();
    const Bvh2 bvh = Bvh2::build(tri);
    PointQueryOptions o;
    o.max_distance = 2.0f;
    EXPECT_TRUE(closest_point(bvh, {0.25f, 0.25f, 2.0f}, o).found()) << "exactly at max_distance: included";
    EXPECT_FALSE(closest_point(bvh, {0.25f, 0.25f, 2.5f}, o).found());
    constexpr float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    for (const Vec3 p : {Vec3{nan, 0, 0}, Vec3{0, inf, 0}, Vec3{0, 0, -inf}}) {
        const ClosestPoint c = closest_point(bvh, p);
        EXPECT_FALSE(c.found());
        EXPECT_EQ(c.distance, inf);
        EXPECT_FALSE(brute_force_closest_point(tri, p).found());
    }
    o.max_distance = -1.0f;
    EXPECT_THROW(closest_point(bvh, {0, 0, 0}, o), Error);
    o.max_distance = nan;
    EXPECT_THROW(brute_force_closest_point(tri, {0, 0, 0}, o), Error);
    EXPECT_FALSE(closest_point(Bvh2::build(Mesh{}), {0, 0, 0}).found());
    std::vector<Vec3> pts(3);
    std::vector<ClosestPoint> out(2);
    EXPECT_THROW(closest_point(bvh, pts, out), Error);
}

}  // namespace
}  // namespace simdbvh

namespace simdbvh {
namespace {

// Signed distance on the unit cube: -(distance to the nearest face) inside,
// the analytic distance outside, 0 on the surface.
TEST(SignedDistance, UnitCube) {
    const Bvh2 bvh = Bvh2::build(test::unit_cube());
    const std::vector<Vec3> pts = {{0.5f, 0.5f, 0.25f}, {0.5f, 0.5f, 3.0f}, {1.0f, 0.5f, 0.5f}, {2.0f, 2.0f, 0.5f}};
    std::vector<SignedDistance> out(pts.size());
    signed_distance(bvh, pts, out);
    EXPECT_EQ(out[0].signed_distance(), -0.25f);
    EXPECT_EQ(out[1].signed_distance(), 2.0f);
    EXPECT_EQ(out[2].signed_distance(), 0.0f);
    EXPECT_EQ(out[2].side.side, Side::surface);
    EXPECT_FLOAT_EQ(out[3].signed_distance(), std::sqrt(2.0f));
    std::vector<SignedDistance> small(1);
    EXPECT_THROW(signed_distance(bvh, pts, small), Error);
}

}  // namespace
}  // namespace simdbvh
