// Crossing counts and all hits: every crossing of a closed mesh is
// counted exactly once, including rays aimed exactly at vertices and along
// edges, on every ray; the BVH2 equals the brute force.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "simdbvh/query/crossings.h"
#include "simdbvh/workloads/families.h"
#include "simdbvh/workloads/scenes.h"
#include "support/scene.h"

namespace simdbvh {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// The watertight family: origins inside a closed icosphere or torus, each ray
// aimed at a vertex or an edge midpoint. Leaving the solid once more than
// entering it: winding +1 and an odd number of crossings, on every ray.
TEST(Crossings, RaysFromInsideThroughVerticesAndEdgesCountOnce) {
    workloads::FamilyOptions fo;
    fo.quick = true;
    std::size_t rays = 0, exact_ties = 0;
    for (const workloads::FamilyCase& c : workloads::make_family(workloads::Family::watertight, fo)) {
        SCOPED_TRACE(c.name);
        const Bvh2 bvh = Bvh2::build(c.mesh);
        for (std::size_t i = 0; i < c.rays.size(); ++i) {
            const CrossingCount n = count_crossings(bvh, c.rays[i]);
            ASSERT_EQ(n.winding, 1) << "ray " << i << " crossings " << n.crossings;
            ASSERT_EQ(n.crossings % 2u, 1u) << "ray " << i;
            const CrossingCount b = brute_force_count_crossings(c.mesh, c.rays[i]);
            ASSERT_EQ(b.winding, n.winding) << "ray " << i;
            ASSERT_EQ(b.crossings, n.crossings) << "ray " << i;
            ++rays;
            // Rays whose closest hit lies exactly on an edge or vertex (several triangles at the same t).
            const AllHits all = intersect_all(bvh, Ray{c.rays[i].org, 0.0f, c.rays[i].dir, kInf});
            for (std::size_t k = 1; k < all.hits.size(); ++k) exact_ties += all.hits[k].t == all.hits[k - 1].t;
        }
    }
    EXPECT_GT(rays, 1000u);
    std::printf("%zu rays, %zu equal-t neighbours in all-hit lists\n", rays, exact_ties);
}

// Axis rays through the unit cube's vertices, edges and face diagonals (dyadic
// origins): from below, 0 or 2 crossings with winding 0; strictly inside the
// square, always 2; from inside the cube, exactly one crossing leaving.
TEST(Crossings, AxisRaysThroughACubesVerticesAndEdges) {
    const Mesh cube = test::unit_cube();
    const Bvh2 bvh = Bvh2::build(cube);
    for (int axis = 0; axis < 3; ++axis)
        for (float sign : {1.0f, -1.0f})
            for (int i = -1; i <= 5; ++i)
                for (int j = -1; j <= 5; ++j) {
                    Vec3 below, inside, dir;
                    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
                    below[a1] = inside[a1] = 0.25f * float(i);
                    below[a2] = inside[a2] = 0.25f * float(j);
                    below[axis] = sign > 0 ? -1.0f : 2.0f;
                    inside[axis] = 0.5f;
                    dir[axis] = sign;
                    const CrossingCount from_below = count_crossings(bvh, Ray{below, 0.0f, dir, kInf});
                    EXPECT_EQ(from_below.winding, 0) << axis << " " << i << " " << j;
                    EXPECT_TRUE(from_below.crossings == 0 || from_below.crossings == 2) << axis << " " << i << " " << j;
                    const bool strictly = i > 0 && i < 4 && j > 0 && j < 4;
                    const bool outside = i < 0 || i > 4 || j < 0 || j > 4;
                    if (strictly) {
                        EXPECT_EQ(from_below.crossings, 2u) << axis << " " << i << " " << j;
                    }
                    if (outside) {
                        EXPECT_EQ(from_below.crossings, 0u) << axis << " " << i << " " << j;
                    }
                    if (strictly) {
                        const CrossingCount in = count_crossings(bvh, Ray{inside, 0.0f, dir, kInf});
                        EXPECT_EQ(in.winding, 1) << axis << " " << i << " " << j;
                        EXPECT_EQ(in.crossings, 1u) << axis << " " << i << " " << j;
                    }
                    const AllHits all = intersect_all(bvh, Ray{below, 0.0f, dir, kInf});
                    EXPECT_EQ(all.hits.size(), from_below.crossings);
                }
}

// Diagonal rays through the icosphere's vertices from far outside: in and out.
TEST(Crossings, RaysThroughVerticesFromOutside) {
    const Mesh sphere = workloads::icosphere(3);
    const Bvh2 bvh = Bvh2::build(sphere);
    for (std::size_t v = 0; v < sphere.positions.size(); ++v) {
        const Vec3 p = sphere.positions[v];
        const Ray r{p * 3.0f, 0.0f, p * -1.0f, kInf};  // through the vertex and the centre
        const CrossingCount n = count_crossings(bvh, r);
        ASSERT_EQ(n.winding, 0) << v;
        ASSERT_EQ(n.crossings, 2u) << v;
    }
}

TEST(Crossings, AllHitsSortedCappedAndEqualToBruteForce) {
    const Mesh soup = workloads::random_soup(2000, 3);
    const Bvh2 bvh = Bvh2::build(soup);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(-1.0f, 2.0f);
    std::size_t many = 0;
    for (int i = 0; i < 500; ++i) {
        const Ray r{{u(rng), u(rng), -1.0f}, 0.0f, {u(rng) * 0.1f, u(rng) * 0.1f, 1.0f}, kInf};
        const AllHits a = intersect_all(bvh, r);
        const AllHits b = brute_force_intersect_all(soup, r);
        ASSERT_EQ(a.hits.size(), b.hits.size()) << i;
        for (std::size_t k = 0; k < a.hits.size(); ++k) {
            ASSERT_EQ(a.hits[k].prim, b.hits[k].prim) << i;
            ASSERT_EQ(a.hits[k].t, b.hits[k].t) << i;
            if (k > 0) {
                ASSERT_TRUE(a.hits[k - 1].t < a.hits[k].t ||
                            (a.hits[k - 1].t == a.hits[k].t && a.hits[k - 1].prim < a.hits[k].prim));
            }
        }
        // The first of all hits is the closest hit, unless a tie at an edge went elsewhere.
        const Hit h = intersect(bvh, r);
        if (!a.hits.empty()) {
            EXPECT_EQ(a.hits[0].t, h.t) << i;
        }
        const AllHits capped = intersect_all(bvh, r, 3);
        ASSERT_EQ(capped.hits.size(), std::min<std::size_t>(3, a.hits.size()));
        ASSERT_EQ(capped.dropped, a.hits.size() - capped.hits.size());
        many += a.hits.size() > 3;
    }
    EXPECT_GT(many, 10u);
    // Batched counts with threads equal the single-ray counts; an invalid ray counts nothing.
    std::vector<Ray> rays(300);
    for (Ray& r : rays) r = Ray{{u(rng), u(rng), -1.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, kInf};
    rays[7].dir = {0, 0, 0};
    std::vector<CrossingCount> out(rays.size());
    count_crossings(bvh, rays, out, 2);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const CrossingCount one = count_crossings(bvh, rays[i]);
        ASSERT_EQ(out[i].crossings, one.crossings);
        ASSERT_EQ(out[i].winding, one.winding);
    }
    EXPECT_EQ(out[7].crossings, 0u);
}

}  // namespace
}  // namespace simdbvh
