// Degenerate meshes and rays never crash; degenerate triangles and rays miss.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/error.h"

namespace simdbvh {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

Ray down_at(float x, float y) { return Ray{{x, y, 5.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, kInf}; }

void expect_miss(const Hit& h) {
    EXPECT_FALSE(h.hit());
    EXPECT_EQ(h.t, kInf);
    EXPECT_FALSE(std::isnan(h.u) || std::isnan(h.v));
}

TEST(Degenerate, EmptyMeshMissesEverything) {
    const Bvh2 bvh = Bvh2::build(Mesh{});
    EXPECT_TRUE(bvh.nodes().empty());
    expect_miss(intersect(bvh, down_at(0, 0)));
    expect_miss(occluded(bvh, down_at(0, 0)));
}

TEST(Degenerate, OneTriangle) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}};
    const Bvh2 bvh = Bvh2::build(m);
    ASSERT_EQ(bvh.nodes().size(), 1u);
    const Hit h = intersect(bvh, down_at(0.25f, 0.5f));
    EXPECT_EQ(h.prim, 0u);
    EXPECT_EQ(h.t, 5.0f);
    EXPECT_EQ(h.u, 0.25f);  // P = (1-u-v) v0 + u v1 + v v2
    EXPECT_EQ(h.v, 0.5f);
    expect_miss(intersect(bvh, down_at(0.75f, 0.5f)));
}

TEST(Degenerate, IdenticalTrianglesTieToLowestId) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.triangles.assign(1000, Triangle{0, 1, 2});
    const Bvh2 bvh = Bvh2::build(m);
    for (float x : {0.1f, 0.3f, 0.45f}) {
        const Hit h = intersect(bvh, down_at(x, 0.2f));
        EXPECT_EQ(h.prim, 0u);
        EXPECT_EQ(h, brute_force_intersect(m, down_at(x, 0.2f)));
    }
}

TEST(Degenerate, ZeroAreaTrianglesNeverHit) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0.5f, 0.5f, 0}};
    m.triangles = {{0, 1, 2}, {0, 0, 0}, {3, 3, 3}, {0, 1, 1}};  // collinear, points, a segment
    const Bvh2 bvh = Bvh2::build(m);
    for (float x : {0.0f, 0.5f, 1.0f, 1.5f})
        for (float y : {0.0f, 0.5f}) {
            expect_miss(intersect(bvh, down_at(x, y)));
            expect_miss(occluded(bvh, down_at(x, y)));
            // Grazing along the segment's line.
            expect_miss(intersect(bvh, Ray{{-1, y, 0}, 0, {1, 0, 0}, kInf}));
        }
}

TEST(Degenerate, AllCentroidsEqualTerminates) {
    // Triangles of different sizes around one centre: zero centroid extent.
    Mesh m;
    for (int i = 0; i < 500; ++i) {
        const float s = 1.0f + float(i);
        const auto base = std::uint32_t(m.positions.size());
        m.positions.push_back({-s, -s, 0});
        m.positions.push_back({2 * s, -s, 0});
        m.positions.push_back({-s, 2 * s, 0});
        m.triangles.push_back({base, base + 1, base + 2});
    }
    const Bvh2 bvh = Bvh2::build(m);
    EXPECT_LE(bvh.stats().depth, kMaxDepth);
    const Hit h = intersect(bvh, down_at(0.1f, 0.1f));
    EXPECT_EQ(h, brute_force_intersect(m, down_at(0.1f, 0.1f)));
    // All coplanar at t = 5; each triangle's t rounds on its own, so the
    // winner is whichever computes the smallest t (ties to the lower id).
    EXPECT_TRUE(h.hit());
    EXPECT_NEAR(h.t, 5.0f, 1e-5f);
}

TEST(Degenerate, BadRaysMissWithoutTraversal) {
    Mesh m;
    m.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}};
    const Bvh2 bvh = Bvh2::build(m);
    const Ray bad[] = {
        {{0, 0, 5}, 0, {0, 0, 0}, kInf},      // zero direction
        {{0, 0, 5}, 0, {0, 0, kNaN}, kInf},   // NaN direction
        {{0, 0, 5}, 0, {0, kInf, -1}, kInf},  // Inf direction
        {{kNaN, 0, 5}, 0, {0, 0, -1}, kInf},  // NaN origin
        {{0, 0, 5}, 3, {0, 0, -1}, 2},        // tmin > tmax
        {{0, 0, 5}, kNaN, {0, 0, -1}, kInf},  // NaN tmin
    };
    for (const Ray& r : bad) {
        TraceStats st;
        TraceOptions o;
        o.stats = &st;
        expect_miss(intersect(bvh, r, o));
        expect_miss(occluded(bvh, r, o));
        EXPECT_EQ(st.nodes_visited, 0u);
        expect_miss(brute_force_intersect(m, r));
    }
}

TEST(Degenerate, IntervalIsInclusive) {
    Mesh m;
    m.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}};
    const Bvh2 bvh = Bvh2::build(m);
    EXPECT_EQ(intersect(bvh, Ray{{0, 0, 5}, 0, {0, 0, -1}, 5.0f}).prim, 0u);
    EXPECT_EQ(intersect(bvh, Ray{{0, 0, 5}, 5.0f, {0, 0, -1}, 5.0f}).prim, 0u);
    EXPECT_FALSE(intersect(bvh, Ray{{0, 0, 5}, 0, {0, 0, -1}, std::nextafter(5.0f, 0.0f)}).hit());
}

TEST(Degenerate, InvalidMeshIsRejectedWithAClearError) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 1, 7}};
    try {
        (void)Bvh2::build(m);
        FAIL() << "out-of-range index accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("triangle 1"), std::string::npos) << e.what();
    }
    m.triangles = {{0, 1, 2}};
    m.positions[1].y = kNaN;
    EXPECT_THROW((void)Bvh2::build(m), Error);
}

}  // namespace
}  // namespace simdbvh
