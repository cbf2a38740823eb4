// Closest point on the wide trees: every field bit-identical to the BVH2's
// answer (which tests/query/closest_point_test.cpp checks against brute force)
// at widths 4, 8, 16, one and two threads, with and without a radius, on a
// soup of overlapping triangles (near-equal distances), on a sphere with
// points at its vertices and edge midpoints, and for points that are far,
// non-finite or beyond the radius.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "simdbvh/query/closest_point_wide.h"
#include "simdbvh/workloads/points.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh {
namespace {

bool same(const ClosestPoint& a, const ClosestPoint& b) {
    return a.prim == b.prim && std::memcmp(&a.point, &b.point, sizeof(Vec3)) == 0 &&
           std::memcmp(&a.distance, &b.distance, 4) == 0 && std::memcmp(&a.u, &b.u, 4) == 0 &&
           std::memcmp(&a.v, &b.v, 4) == 0 && std::memcmp(&a.distance2, &b.distance2, 8) == 0;
}

std::vector<Vec3> points_for(const Mesh& m) {
    std::vector<Vec3> p = workloads::random_points(m.bounds(), 1500, 3, 0.5f);
    for (std::size_t t = 0; t < m.size() && t < 600; t += 3) {
        const Vec3 a = m.vertex(t, 0), b = m.vertex(t, 1);
        p.push_back(a);
        p.push_back({0.5f * (a.x + b.x), 0.5f * (a.y + b.y), 0.5f * (a.z + b.z)});
    }
    p.push_back({1e30f, -1e30f, 1e30f});
    p.push_back({std::numeric_limits<float>::quiet_NaN(), 0, 0});
    p.push_back({std::numeric_limits<float>::infinity(), 0, 0});
    return p;
}

template <int N>
void check(const Mesh& mesh, const char* what, bool expect_pruning = true) {
    const Bvh2 bvh2 = Bvh2::build(mesh);
    const BvhN<N> wide = BvhN<N>::build(mesh);  // a different tree (bvh2_intersection_cost): same answers
    const std::vector<Vec3> pts = points_for(mesh);
    for (float radius : {std::numeric_limits<float>::infinity(), 0.05f}) {
        PointQueryOptions o;
        o.max_distance = radius;
        std::vector<ClosestPoint> want(pts.size());
        closest_point(bvh2, pts, want, o);
        std::size_t found = 0;
        for (const ClosestPoint& c : want) found += c.found();
        EXPECT_GT(found, pts.size() / 10) << what;
        for (int threads : {1, 2}) {
            o.threads = threads;
            std::vector<ClosestPoint> got(pts.size());
            closest_point(wide, pts, got, o);
            for (std::size_t i = 0; i < pts.size(); ++i)
                ASSERT_TRUE(same(got[i], want[i])) << what << " N=" << N << " point " << i << " prim " << got[i].prim
                                                   << " vs " << want[i].prim << " radius " << radius;
        }
        for (std::size_t i = 0; i < pts.size(); i += 97)
            ASSERT_TRUE(same(closest_point(wide, pts[i], o), want[i])) << what << " single point " << i;
    }
    PointQueryStats st;
    PointQueryOptions o;
    o.stats = &st;
    std::vector<ClosestPoint> got(pts.size());
    closest_point(wide, pts, got, o);
    EXPECT_EQ(st.points, pts.size());
    EXPECT_GT(st.exact_tests, 0u);
    if (expect_pruning) {
        EXPECT_LT(st.exact_tests, st.triangle_tests) << "the triangle boxes reject some triangles";
    }
}

TEST(WideClosestPoint, SoupOfOverlappingTriangles) {
    const Mesh m = workloads::random_soup(4000, 11);
    check<4>(m, "soup");
    check<8>(m, "soup");
    check<16>(m, "soup");
}

TEST(WideClosestPoint, SphereVerticesAndEdges) {
    const Mesh m = workloads::icosphere(4);
    check<8>(m, "icosphere");
    check<16>(m, "icosphere");
}

// The wide trees prune by float bounds (query/src/point_bounds-inl.h), which
// fall back to double where float squares overflow (distances above ~1.8e19)
// or underflow (below 2^-50): meshes at those scales still match the BVH2 and
// still prune. At 1e-24 the squared gaps round to 0 (never pruned): same
// answers, every triangle tested exactly.
TEST(WideClosestPoint, FloatBoundsAtExtremeScales) {
    for (float scale : {1e-24f, 1e-18f, 1e18f, 1e21f}) {
        Mesh m = workloads::icosphere(3);
        for (Vec3& v : m.positions) v = v * scale;
        const std::string what = "icosphere scaled by " + std::to_string(scale);
        check<8>(m, what.c_str(), scale > 1e-20f);
    }
}

TEST(WideClosestPoint, EmptyMeshAndBadRadius) {
    const Bvh8 empty = Bvh8::build(Mesh{});
    EXPECT_FALSE(closest_point(empty, Vec3{0, 0, 0}).found());
    const Bvh8 b = Bvh8::build(workloads::icosphere(1));
    PointQueryOptions o;
    o.max_distance = -1.0f;
    EXPECT_THROW(closest_point(b, Vec3{0, 0, 0}, o), Error);
    std::vector<ClosestPoint> small(1);
    const std::vector<Vec3> two{{0, 0, 0}, {1, 1, 1}};
    EXPECT_THROW(closest_point(b, two, small), Error);
}

}  // namespace
}  // namespace simdbvh
