// The double-precision brute-force reference: hand-built triangles with known
// t, u, v; the tolerance formula; tie-sets; agreement with simdbvh's float
// brute force on a closed mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/reference/classify.h"
#include "simdbvh/reference/reference.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"
#include "support/scene.h"

namespace simdbvh::reference {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

Ray ray(Vec3 o, Vec3 d, float tmin = 0.0f, float tmax = kInf) { return Ray{o, tmin, d, tmax}; }

TEST(Reference, HandBuiltTriangleGivesExactTAndBarycentrics) {
    const Mesh m = test::one_triangle();  // (0,0,0) (1,0,0) (0,1,0)
    const Reference r = reference_intersect(m, ray({0.25f, 0.5f, 4.0f}, {0, 0, -1}));
    ASSERT_TRUE(r.valid);
    ASSERT_TRUE(r.hit());
    EXPECT_EQ(r.prim, 0u);
    EXPECT_EQ(r.t, 4.0);
    const RefHit* h = r.find(0);
    ASSERT_NE(h, nullptr);
    EXPECT_TRUE(h->hit);
    EXPECT_TRUE(h->robust);
    EXPECT_DOUBLE_EQ(h->u, 0.25);  // P = (1-u-v) v0 + u v1 + v v2
    EXPECT_DOUBLE_EQ(h->v, 0.5);

    // t is in units of d: doubling d halves t; from below (negative kz) too.
    EXPECT_EQ(reference_intersect(m, ray({0.25f, 0.5f, 4.0f}, {0, 0, -2})).t, 2.0);
    EXPECT_EQ(reference_intersect(m, ray({0.25f, 0.5f, -3.0f}, {0, 0, 1})).t, 3.0);
}

TEST(Reference, ObliqueRayHitsAtTheKnownPoint) {
    Mesh m;  // a big triangle in the plane x + y + z = 1
    m.positions = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    m.triangles = {{0, 1, 2}};
    // From the origin along (1, 2, 1): hits at t = 1/4, point (0.25, 0.5, 0.25).
    const Reference r = reference_intersect(m, ray({0, 0, 0}, {1, 2, 1}));
    ASSERT_TRUE(r.hit());
    EXPECT_NEAR(r.t, 0.25, 1e-15);
    const RefHit* h = r.find(0);
    EXPECT_NEAR(h->u, 0.5, 1e-15);   // weight of v1 = y
    EXPECT_NEAR(h->v, 0.25, 1e-15);  // weight of v2 = z
    // The float kernel lands within tau of it.
    const Hit f = brute_force_intersect(m, ray({0, 0, 0}, {1, 2, 1}));
    EXPECT_LE(std::fabs(double(f.t) - r.t), r.tau);
}

TEST(Reference, IntervalIsInclusiveAndBothFacesHit) {
    const Mesh m = test::one_triangle();
    EXPECT_TRUE(reference_intersect(m, ray({0.2f, 0.2f, 1}, {0, 0, -1}, 0.0f, 1.0f)).hit());  // t == tmax
    EXPECT_TRUE(reference_intersect(m, ray({0.2f, 0.2f, 1}, {0, 0, -1}, 1.0f, 2.0f)).hit());  // t == tmin
    EXPECT_FALSE(reference_intersect(m, ray({0.2f, 0.2f, 1}, {0, 0, -1}, 0.0f, 0.5f)).hit());
    EXPECT_FALSE(reference_intersect(m, ray({0.2f, 0.2f, 1}, {0, 0, 1})).hit());  // behind
    EXPECT_TRUE(reference_intersect(m, ray({0.2f, 0.2f, -1}, {0, 0, 1})).hit());  // back face
    EXPECT_FALSE(reference_intersect(m, ray({0.2f, 0.2f, 0}, {1, 0, 0})).hit());  // coplanar
    EXPECT_TRUE(reference_occluded(m, ray({0.2f, 0.2f, 1}, {0, 0, -1})));
    EXPECT_FALSE(reference_occluded(m, ray({2, 2, 1}, {0, 0, -1})));
}

TEST(Reference, InvalidRaysMiss) {
    const Mesh m = test::one_triangle();
    for (const Ray& r :
         {ray({kNaN, 0.2f, 1}, {0, 0, -1}), ray({0.2f, 0.2f, 1}, {0, 0, 0}), ray({0.2f, 0.2f, 1}, {0, kInf, -1}),
          ray({0.2f, 0.2f, 1}, {0, 0, -1}, 2.0f, 1.0f), ray({0.2f, 0.2f, 1}, {0, 0, -1}, kNaN, 1.0f)}) {
        const Reference ref = reference_intersect(m, r);
        EXPECT_FALSE(ref.valid);
        EXPECT_FALSE(ref.hit());
        EXPECT_TRUE(ref.candidates.empty());
        EXPECT_FALSE(reference_occluded(m, r));
        EXPECT_EQ(to_hit(ref), Hit{});
    }
}

TEST(Reference, ToleranceFollowsTheFormula) {
    // tau = 16 * 2^-24 * (|o|inf + t |d|inf) / |d|
    const Ray r = ray({3, -7, 1}, {0, 3, -4});  // |d| = 5, |d|inf = 4, |o|inf = 7
    EXPECT_DOUBLE_EQ(tolerance(r, 2.0), 16.0 * 0x1p-24 * (7.0 + 2.0 * 4.0) / 5.0);
    EXPECT_EQ(tolerance(r, std::numeric_limits<double>::infinity()), 0.0);
    EXPECT_EQ(tolerance(ray({0, 0, 0}, {0, 0, 0}), 1.0), 0.0);
}

TEST(Reference, SharedEdgeAndDuplicatesFormTheTieSet) {
    Mesh m;  // unit square split along the diagonal (0,0)-(1,1), plus a duplicate of the first half
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 1, 2}};
    // Exactly on the diagonal: all three triangles are hit at the same t.
    const Reference on = reference_intersect(m, ray({0.5f, 0.5f, 2}, {0, 0, -1}));
    ASSERT_TRUE(on.hit());
    EXPECT_EQ(on.prim, 0u);  // ties to the lower id
    EXPECT_EQ(on.tie_set(), (std::vector<std::uint32_t>{0, 1, 2}));
    EXPECT_FALSE(on.find(0)->robust);  // on an edge: within rounding of missing
    // Inside the second half only.
    const Reference in = reference_intersect(m, ray({0.25f, 0.75f, 2}, {0, 0, -1}));
    EXPECT_EQ(in.prim, 1u);
    EXPECT_EQ(in.tie_set(), (std::vector<std::uint32_t>{1}));
    EXPECT_TRUE(in.in_tie_set(1));
    EXPECT_FALSE(in.in_tie_set(0));
    EXPECT_TRUE(in.robust_hit());
}

TEST(Reference, StackedTrianglesOnlyTheClosestIsInTheTieSet) {
    Mesh m;  // the same triangle at z = 0 (id 0) and z = 1e-3 (id 1)
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1e-3f}, {1, 0, 1e-3f}, {0, 1, 1e-3f}};
    m.triangles = {{0, 1, 2}, {3, 4, 5}};
    const Reference r = reference_intersect(m, ray({0.2f, 0.2f, 1}, {0, 0, -1}));
    EXPECT_EQ(r.prim, 1u);
    EXPECT_EQ(r.tie_set(), (std::vector<std::uint32_t>{1}));
    EXPECT_EQ(r.candidates.size(), 2u);
}

// The float brute force (the watertight kernel every path reproduces) agrees
// with the double reference on every ray of a closed mesh.
TEST(Reference, AgreesWithFloatBruteForceOnIcosphere) {
    const Mesh m = workloads::icosphere(3);
    auto rays = workloads::incoherent_rays(m.bounds(), 1500, 11);
    // Plus rays from inside towards every 7th vertex (watertight family).
    for (std::size_t i = 0; i < m.positions.size(); i += 7) rays.push_back(ray({0.01f, -0.02f, 0.03f}, m.positions[i]));
    std::size_t hits = 0;
    Tally closest, any;
    for (const Ray& r : rays) {
        const Reference ref = reference_intersect(m, r);
        const Hit f = brute_force_intersect(m, r);
        closest.add(classify(ref, f));
        any.add(classify_occluded(ref, brute_force_occluded(m, r).hit()));
        EXPECT_EQ(reference_occluded(m, r), ref.hit());
        hits += ref.hit();
    }
    EXPECT_GT(hits, rays.size() / 2);
    EXPECT_EQ(closest.disagreements(), 0u) << to_string(closest);
    EXPECT_EQ(any.disagreements(), 0u) << to_string(any);
    std::cout << "float brute force vs double reference: closest " << to_string(closest) << "\n";
}

}  // namespace
}  // namespace simdbvh::reference
