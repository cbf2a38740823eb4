// validate(mesh): the fast path (linear scans of the indices and positions)
// accepts exactly the meshes the per-triangle pass accepts, and every error
// names the first offending triangle as before.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh {
namespace {

Mesh quad() {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    m.triangles = {{0, 1, 2}, {1, 3, 2}};
    return m;
}

std::string error_of(const Mesh& m) {
    try {
        validate(m);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(MeshValidate, ValidMeshesPass) {
    EXPECT_EQ(error_of(quad()), "");
    Mesh empty;
    EXPECT_EQ(error_of(empty), "");
    Mesh points_only = quad();
    points_only.triangles.clear();
    EXPECT_EQ(error_of(points_only), "");
}

TEST(MeshValidate, IndexOutOfRangeNamesTheTriangle) {
    Mesh m = quad();
    m.triangles[1][1] = 4;
    const std::string e = error_of(m);
    EXPECT_NE(e.find("triangle 1 has vertex index 4 out of range (4 vertices)"), std::string::npos) << e;
    Mesh none;
    none.triangles = {{0, 0, 0}};
    EXPECT_NE(error_of(none).find("triangle 0 has vertex index 0 out of range (0 vertices)"), std::string::npos);
}

TEST(MeshValidate, NonFiniteVerticesCountTheTrianglesThatUseThem) {
    const float inf = std::numeric_limits<float>::infinity();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (float bad : {nan, inf, -inf}) {
        Mesh m = quad();
        m.positions[3].y = bad;  // used by triangle 1 only
        EXPECT_NE(error_of(m).find("1 triangles have a NaN or infinite vertex (first: triangle 1)"), std::string::npos)
            << error_of(m);
        m.positions[2].z = bad;  // used by both
        EXPECT_NE(error_of(m).find("2 triangles have a NaN or infinite vertex (first: triangle 0)"), std::string::npos)
            << error_of(m);
    }
}

TEST(MeshValidate, UnusedNonFiniteVertexIsNoError) {
    Mesh m = quad();
    m.positions.push_back({std::numeric_limits<float>::quiet_NaN(), 0, 0});
    EXPECT_EQ(error_of(m), "");
    m.positions.back() = {0, std::numeric_limits<float>::max(), -std::numeric_limits<float>::max()};
    EXPECT_EQ(error_of(m), "");  // finite extremes are valid
}

}  // namespace
}  // namespace simdbvh
