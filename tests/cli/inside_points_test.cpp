// SPDX-License-Identifier: MIT
// The inside/outside panel's "diagonal rays through vertices" family
// (lab/inside_points.h), on the quick panel's meshes and caps: every point p
// has a vertex v with v - p = s(1, 1, 1) exactly (checked with an exact
// difference, not a rounded one), so that the ray from p along (1, 1, 1),
// Open3D's compute_occupancy ray, meets v when s > 0.
#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

#include "inside_points.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh::lab {
namespace {

// a - b in double, and whether that is exact (Knuth's TwoSum error term is 0).
bool exact_difference(float a, float b, double& s) {
    const double x = a, y = -double(b);
    s = x + y;
    const double yy = s - x, err = (x - (s - yy)) + (y - yy);
    return err == 0;
}

// s with v - p = s(1, 1, 1) exactly and s != 0, or 0 when there is none.
double diagonal_step(Vec3 v, Vec3 p) {
    double sx, sy, sz;
    if (!exact_difference(v.x, p.x, sx) || !exact_difference(v.y, p.y, sy) || !exact_difference(v.z, p.z, sz)) return 0;
    return sx == sy && sy == sz ? sx : 0;
}

// The number of points whose diagonal ray meets a vertex (s > 0); fails the test for a point on no
// vertex's diagonal.
std::size_t check_family(const Mesh& m, const std::vector<Vec3>& points) {
    std::size_t toward = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        bool on = false, ahead = false;
        for (Vec3 v : m.positions) {
            const double s = diagonal_step(v, points[i]);
            on = on || s != 0;
            ahead = ahead || s > 0;
        }
        EXPECT_TRUE(on) << "point " << i << " (" << points[i].x << ", " << points[i].y << ", " << points[i].z
                        << ") is on no vertex's diagonal";
        toward += ahead;
    }
    return toward;
}

TEST(InsidePoints, DiagonalFamilyRunsExactlyThroughIcosphereVertices) {
    const Mesh sphere = workloads::icosphere(3);
    const std::vector<Vec3> p = diagonal_through_vertices(sphere, 4000);  // the quick panel's call
    ASSERT_GE(p.size(), 1000u) << "most of the 642 vertices should give exact points";
    EXPECT_GE(check_family(sphere, p), 500u);
}

TEST(InsidePoints, DiagonalFamilyRunsExactlyThroughCubeGridVertices) {
    const Mesh cubes = cube_grid(6);
    const std::vector<Vec3> p = diagonal_through_vertices(cubes, 4000);
    EXPECT_EQ(p.size(), 2 * cubes.positions.size());  // integer vertices: every point is exact
    // v - d(1, 1, 1) for every vertex v, and some v + d(1, 1, 1) whose rays meet another vertex farther on.
    EXPECT_GE(check_family(cubes, p), cubes.positions.size());
}

TEST(InsidePoints, DiagonalFamilyKeepsToItsCapAndDropsInexactPoints) {
    const Mesh sphere = workloads::icosphere(3);
    EXPECT_LE(diagonal_through_vertices(sphere, 100).size(), 101u);
    // A vertex far below the step in magnitude: v.x - d is not a float, so its points go.
    Mesh m;
    m.positions = {{1e-20f, 0.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}, {0.0f, 0.0f, 2.0f}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
    const std::vector<Vec3> p = diagonal_through_vertices(m, 100);
    EXPECT_EQ(p.size(), 6u);
    check_family(m, p);
    for (Vec3 q : p) EXPECT_EQ(diagonal_step(m.positions[0], q), 0) << "a point for the tiny vertex";
}

}  // namespace
}  // namespace simdbvh::lab
