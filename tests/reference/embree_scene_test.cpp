// EmbreeScene: result conversion (t, u, v, prim in our convention), rays that
// must not reach Embree, options, stats, errors, RAII.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "simdbvh/reference/classify.h"
#include "simdbvh/reference/embree.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/workloads/deform.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"
#include "support/scene.h"

namespace simdbvh::reference {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

Ray ray(Vec3 o, Vec3 d, float tmin = 0.0f, float tmax = kInf) { return Ray{o, tmin, d, tmax}; }

TEST(EmbreeScene, HitUsesOurConventions) {
    Mesh m;  // triangle 0 far away, triangle 1 the one we aim at: prim ids must map through
    m.positions = {{10, 10, 10}, {11, 10, 10}, {10, 11, 10}, {0, 0, 0}, {2, 0, 0}, {0, 4, 0}};
    m.triangles = {{0, 1, 2}, {3, 4, 5}};
    const EmbreeScene s(m);
    // P = (1-u-v) v0 + u v1 + v v2 with u = 0.25, v = 0.5: (0.5, 2, 0).
    const Hit h = s.intersect(ray({0.5f, 2.0f, 3.0f}, {0, 0, -1}));
    ASSERT_TRUE(h.hit());
    EXPECT_EQ(h.prim, 1u);
    EXPECT_FLOAT_EQ(h.t, 3.0f);
    EXPECT_NEAR(h.u, 0.25f, 1e-6f);
    EXPECT_NEAR(h.v, 0.5f, 1e-6f);
    EXPECT_TRUE(s.occluded(ray({0.5f, 2.0f, 3.0f}, {0, 0, -1})));
    // Miss, and a hit beyond tmax.
    EXPECT_EQ(s.intersect(ray({5, 5, 3}, {0, 0, -1})), Hit{});
    EXPECT_EQ(s.intersect(ray({0.5f, 2.0f, 3.0f}, {0, 0, -1}, 0.0f, 2.0f)), Hit{});
    EXPECT_FALSE(s.occluded(ray({0.5f, 2.0f, 3.0f}, {0, 0, -1}, 0.0f, 2.0f)));
    // Back face (no culling).
    EXPECT_EQ(s.intersect(ray({0.5f, 2.0f, -3.0f}, {0, 0, 1})).prim, 1u);
    EXPECT_EQ(s.invalid_rays(), 0u);
}

TEST(EmbreeScene, InvalidRaysAreMissesAndCounted) {
    const EmbreeScene s(test::one_triangle());
    const std::vector<Ray> bad = {
        ray({kNaN, 0.2f, 1}, {0, 0, -1}),       ray({0.2f, 0.2f, 1}, {0, 0, 0}),
        ray({0.2f, 0.2f, kInf}, {0, 0, -1}),    ray({0.2f, 0.2f, 1}, {kNaN, 0, -1}),
        ray({0.2f, 0.2f, 1}, {0, -kInf, -1}),   ray({0.2f, 0.2f, 1}, {0, 0, -1}, 2.0f, 1.0f),
        ray({0.2f, 0.2f, 1}, {0, 0, -1}, kNaN), ray({0.2f, 0.2f, 1}, {0, 0, -1}, 0.0f, kNaN),
    };
    for (const Ray& r : bad) EXPECT_EQ(check_embree_ray(r), EmbreeRayCheck::invalid);
    std::vector<Hit> hits(bad.size(), Hit{1, 1, 1, 1});
    s.intersect(bad, hits);
    for (const Hit& h : hits) EXPECT_EQ(h, Hit{});
    std::vector<std::uint8_t> occ(bad.size(), 1);
    s.occluded(bad, occ);
    for (std::uint8_t o : occ) EXPECT_EQ(o, 0);
    EXPECT_EQ(s.invalid_rays(), 2 * bad.size());

    // Valid for us, outside Embree's domain: answered as misses, counted apart.
    const Ray negative_tmin = ray({0.2f, 0.2f, 1}, {0, 0, -1}, -1.0f);
    const Ray huge = ray({0.2f, 0.2f, 1e19f}, {0, 0, -1});
    EXPECT_EQ(check_embree_ray(negative_tmin), EmbreeRayCheck::unsupported);
    EXPECT_EQ(check_embree_ray(huge), EmbreeRayCheck::unsupported);
    EXPECT_EQ(s.intersect(negative_tmin), Hit{});
    EXPECT_FALSE(s.occluded(huge));
    EXPECT_EQ(s.unsupported_rays(), 2u);
    s.intersect(ray({0.2f, 0.2f, 1}, {0, 0, -1}, -0.0f));  // -0 is a valid tnear
    EXPECT_EQ(s.unsupported_rays(), 2u);
    const_cast<EmbreeScene&>(s).reset_counters();
    EXPECT_EQ(s.invalid_rays(), 0u);
    EXPECT_EQ(s.unsupported_rays(), 0u);
}

TEST(EmbreeScene, OptionsStatsAndNames) {
    const Mesh m = workloads::icosphere(4);  // 5120 triangles
    for (EmbreeQuality q : {EmbreeQuality::medium, EmbreeQuality::high}) {
        for (bool robust : {false, true}) {
            const EmbreeOptions o{q, robust, 1};
            const EmbreeScene s(m, o);
            EXPECT_EQ(s.options().threads, 1);
            EXPECT_EQ(s.stats().threads, 1);
            EXPECT_EQ(s.stats().triangles, m.size());
            EXPECT_GE(s.stats().build_ms, 0.0);
            if (s.stats().memory_tracked) {
                EXPECT_GE(s.stats().buffer_bytes, std::int64_t(m.size() * 12));
                EXPECT_GT(s.stats().bvh_bytes, 0);
                EXPECT_GT(s.stats().bytes_per_triangle, 0.0);
                EXPECT_GE(s.stats().peak_bytes, s.stats().bvh_bytes + s.stats().buffer_bytes);
            }
            std::cout << method_name(o) << ": build " << s.stats().build_ms << " ms, " << s.stats().bytes_per_triangle
                      << " B/tri (bvh " << s.stats().bvh_bytes << " B, buffers " << s.stats().buffer_bytes
                      << " B, peak " << s.stats().peak_bytes << " B), tasking " << s.tasking_system() << ", Embree "
                      << EmbreeScene::version() << "\n";
        }
    }
    EXPECT_EQ(method_name({EmbreeQuality::high, true, 0}), "embree-high-robust");
    EXPECT_EQ(method_name({}), "embree-medium");
    EXPECT_EQ(parse_embree_quality("high"), EmbreeQuality::high);
    EXPECT_FALSE(parse_embree_quality("low").has_value());
    EXPECT_EQ(EmbreeScene::version().substr(0, 2), "3.");
    EXPECT_GE(EmbreeScene(m).stats().threads, 1);  // 0 = default: resolved to the hardware threads
}

TEST(EmbreeScene, EmptyMeshMissesEverything) {
    const EmbreeScene s(Mesh{});
    EXPECT_EQ(s.intersect(ray({0, 0, 1}, {0, 0, -1})), Hit{});
    EXPECT_FALSE(s.occluded(ray({0, 0, 1}, {0, 0, -1})));
    EXPECT_EQ(s.stats().bytes_per_triangle, 0.0);
}

TEST(EmbreeScene, BadInputThrowsOurError) {
    Mesh bad = test::one_triangle();
    bad.triangles[0][2] = 3;  // out of range
    EXPECT_THROW(EmbreeScene{bad}, Error);
    Mesh nan = test::one_triangle();
    nan.positions[1].x = kNaN;
    EXPECT_THROW(EmbreeScene{nan}, Error);
    EXPECT_THROW((EmbreeScene{test::one_triangle(), EmbreeOptions{EmbreeQuality::medium, false, -1}}), Error);
    const EmbreeScene s(test::one_triangle());
    std::vector<Hit> hits(1);
    EXPECT_THROW(s.intersect(std::vector<Ray>(2), hits), Error);
}

TEST(EmbreeScene, MovesKeepTheScene) {
    EmbreeScene a(test::one_triangle());
    EmbreeScene b(std::move(a));
    EXPECT_EQ(b.intersect(ray({0.2f, 0.2f, 1}, {0, 0, -1})).prim, 0u);
    EmbreeScene c(Mesh{});
    c = std::move(b);
    EXPECT_EQ(c.intersect(ray({0.2f, 0.2f, 1}, {0, 0, -1})).prim, 0u);
}

// Embree against the double reference on a closed mesh: report its own errors.
TEST(EmbreeScene, AgainstReferenceOnIcosphere) {
    const Mesh m = workloads::icosphere(3);
    std::vector<Ray> rays = workloads::incoherent_rays(m.bounds(), 400, 5);
    for (const Vec3& p : m.positions) rays.push_back(ray({0.01f, -0.02f, 0.03f}, p));  // through every vertex
    for (bool robust : {false, true}) {
        const EmbreeScene s(m, {EmbreeQuality::medium, robust, 1});
        std::vector<Hit> hits(rays.size());
        s.intersect(rays, hits);
        Tally t;
        for (std::size_t i = 0; i < rays.size(); ++i) t.add(classify(reference_intersect(m, rays[i]), hits[i]));
        std::cout << method_name(s.options()) << " vs reference (" << rays.size() << " rays): " << to_string(t) << "\n";
        RecordProperty(method_name(s.options()) + "_disagreements", std::to_string(t.disagreements()));
        EXPECT_GT(t.agreement_rate(), 0.95) << to_string(t);
    }
}

// update_vertices: a refit scene (and a medium one, which rebuilds) answers
// for the moved mesh: the same prims as a scene built on the moved mesh for
// almost every ray, and far from the answers before the move.
TEST(EmbreeScene, StreamCallsGiveTheSingleRayAnswers) {
    const Mesh mesh = workloads::load_scene("icosphere-4");
    const EmbreeScene embree(mesh);
    for (workloads::RayKind kind : {workloads::RayKind::primary, workloads::RayKind::incoherent}) {
        std::vector<Ray> rays = workloads::generate_rays(mesh, kind, 1000, 5);
        rays[3].dir = {0, 0, 0};                                 // invalid: a miss either way
        rays[4].tmax = std::numeric_limits<float>::quiet_NaN();  // invalid too
        std::vector<Hit> one(rays.size()), stream(rays.size());
        std::vector<std::uint8_t> occ_one(rays.size()), occ_stream(rays.size());
        embree.intersect(rays, one);
        embree.intersect_stream(rays, stream);
        embree.occluded(rays, occ_one);
        embree.occluded_stream(rays, occ_stream);
        std::size_t hits = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(stream[i].prim, one[i].prim) << "ray " << i;
            ASSERT_EQ(stream[i].t, one[i].t) << "ray " << i;
            ASSERT_EQ(occ_stream[i], occ_one[i]) << "ray " << i;
            hits += one[i].hit();
        }
        EXPECT_GT(hits, 100u);
        EXPECT_FALSE(stream[3].hit());
        EXPECT_FALSE(stream[4].hit());
        // Flagged coherent, Embree may trace the stream as packets; and packets of 8 (rtcIntersect8 /
        // rtcOccluded8). Either way: the same hits and misses as one ray at a time, and the same triangle for
        // almost every ray (its packet kernels need not round as its single-ray ones).
        auto same_as_one = [&](const char* what, const std::vector<Hit>& h, const std::vector<std::uint8_t>& occ) {
            std::size_t same = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) {
                ASSERT_EQ(h[i].hit(), one[i].hit()) << what << " ray " << i;
                ASSERT_EQ(occ[i], occ_one[i]) << what << " ray " << i;
                same += h[i].prim == one[i].prim;
            }
            EXPECT_GE(same, rays.size() * 99 / 100) << what;
            EXPECT_FALSE(h[3].hit()) << what;
            EXPECT_FALSE(h[4].hit()) << what;
        };
        std::vector<Hit> coherent(rays.size()), packets(rays.size());
        std::vector<std::uint8_t> occ_coherent(rays.size()), occ_packets(rays.size());
        embree.intersect_stream(rays, coherent, true);
        embree.occluded_stream(rays, occ_coherent, true);
        same_as_one("coherent stream", coherent, occ_coherent);
        embree.intersect_packets8(rays, packets);
        embree.occluded_packets8(rays, occ_packets);
        same_as_one("packets8", packets, occ_packets);
    }
}

TEST(EmbreeScene, UpdateVerticesFollowsTheMovedMesh) {
    const Mesh m = workloads::random_soup(4000, 2);
    const Mesh moved = workloads::twist(m, 2.0);
    const auto rays = workloads::incoherent_rays(moved.bounds(), 2000, 3);
    const EmbreeScene fresh(moved, {EmbreeQuality::medium, false, 1});
    std::vector<Hit> want(rays.size());
    fresh.intersect(rays, want);
    for (EmbreeQuality q : {EmbreeQuality::refit, EmbreeQuality::medium}) {
        EmbreeScene s(m, {q, false, 1});
        std::vector<Hit> before(rays.size()), after(rays.size());
        s.intersect(rays, before);
        EXPECT_GE(s.update_vertices(moved), 0.0);
        s.intersect(rays, after);
        std::size_t same_before = 0, same_after = 0, hits = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            same_before += before[i].prim == want[i].prim;
            same_after += after[i].prim == want[i].prim;
            hits += want[i].hit();
        }
        EXPECT_GT(hits, rays.size() / 4);
        EXPECT_GE(same_after, rays.size() * 99 / 100) << name(q);
        EXPECT_LT(same_before, rays.size() * 80 / 100) << name(q);
        Mesh fewer = moved;
        fewer.triangles.pop_back();
        EXPECT_THROW(s.update_vertices(fewer), Error);
        Mesh other = moved;
        std::swap(other.triangles[0][0], other.triangles[0][1]);
        EXPECT_THROW(s.update_vertices(other), Error);
    }
    EXPECT_EQ(parse_embree_quality("refit"), EmbreeQuality::refit);
}

// count_hits: every hit along the ray, through a closed sphere: one from
// inside, two from outside, none when the ray points away; a scene without
// count_filter refuses.
TEST(EmbreeScene, CountHitsCountsEveryCrossing) {
    const Mesh m = workloads::icosphere(3);
    const EmbreeScene s(m, {EmbreeQuality::medium, false, 1, true});
    const Vec3 d{0.0123f, 0.0456f, 1.0f};  // through face interiors, not along the mesh's symmetry planes
    EXPECT_EQ(s.count_hits(ray({0.01f, 0.02f, 0.0f}, d)), 1u);
    EXPECT_EQ(s.count_hits(ray({0.01f, 0.02f, -3.0f}, d)), 2u);
    EXPECT_EQ(s.count_hits(ray({0.01f, 0.02f, 3.0f}, d)), 0u);
    EXPECT_EQ(s.count_hits(ray({0.01f, 0.02f, -3.0f}, d, 0.0f, 1.0f)), 0u);  // stops before the sphere
    EXPECT_EQ(s.count_hits(ray({kNaN, 0, 0}, d)), 0u);
    const EmbreeScene plain(m, {EmbreeQuality::medium, false, 1});
    EXPECT_THROW(plain.count_hits(ray({0, 0, -3}, d)), Error);
    EXPECT_EQ(plain.intersect(ray({0.01f, 0.02f, -3.0f}, d)).prim, s.intersect(ray({0.01f, 0.02f, -3.0f}, d)).prim);
}

}  // namespace
}  // namespace simdbvh::reference
