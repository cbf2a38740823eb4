// Invalid rays (zero, NaN or Inf direction, NaN or Inf origin, NaN interval,
// tmin > tmax) miss without traversal on every path and variant; degenerate
// scenes build under the depth cap.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/workloads/families.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh {
namespace {

constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

std::vector<Ray> invalid_rays() {
    std::vector<Ray> rays;
    auto add = [&](Vec3 o, Vec3 d, float tmin = 0.0f, float tmax = kInf) { rays.push_back(Ray{o, tmin, d, tmax}); };
    const Vec3 o{0.1f, 0.2f, 3.0f}, d{0.0f, 0.0f, -1.0f};
    add(o, {0, 0, 0});
    add(o, {-0.0f, 0.0f, -0.0f});
    add({0, 0, 0}, {0, 0, 0});
    for (float bad : {kNan, kInf, -kInf}) {
        for (int k = 0; k < 3; ++k) {
            Vec3 dd = d, oo = o;
            dd[k] = bad;
            oo[k] = bad;
            add(o, dd);
            add(oo, d);
        }
        add(o, {bad, bad, bad});
    }
    add(o, d, 2.0f, 1.0f);  // tmin > tmax
    add(o, d, kNan, kInf);  // NaN interval
    add(o, d, 0.0f, kNan);
    add(o, d, kInf, kInf);  // [inf, inf]: tmin <= tmax, but nothing lies there
    add(o, d, 5.0f, -5.0f);
    return rays;
}

void expect_miss(const Hit& h, const std::string& what) {
    EXPECT_FALSE(h.hit()) << what;
    EXPECT_EQ(h, Hit{}) << what << ": a miss is Hit{} (t = +inf, no NaN)";
    EXPECT_FALSE(std::isnan(h.t) || std::isnan(h.u) || std::isnan(h.v)) << what;
}

TEST(InvalidRays, MissWithoutTraversalOnEveryPath) {
    const Mesh mesh = workloads::icosphere(3, 4.0f);  // the valid rays start inside it
    const Bvh2 bvh = Bvh2::build(mesh);
    const Bvh8 b8 = Bvh8::build(bvh);
    const auto rays = invalid_rays();
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Ray& r = rays[i];
        const bool valid = prepare(r).valid;
        const std::string id = "ray " + std::to_string(i);
        if (valid) {  // [inf, inf]: valid, but no hit can lie there
            EXPECT_EQ(r.tmin, kInf) << id;
        }
        for (TriangleTest t : {TriangleTest::watertight, TriangleTest::moller})
            for (BoxTest b : {BoxTest::conservative, BoxTest::plain}) {
                TraceStats st;
                TraceOptions o;
                o.test = t;
                o.box = b;
                o.stats = &st;
                expect_miss(intersect(bvh, r, o), id + " bvh2 closest");
                expect_miss(occluded(bvh, r, o), id + " bvh2 any");
                std::vector<Hit> h(1);
                intersect(bvh, std::span(&r, 1), h, o);
                expect_miss(h[0], id + " bvh2 batch");
                if (!valid) EXPECT_EQ(st.nodes_visited, 0u) << id;
            }
        for (Isa isa : supported_isas()) {
            TraceStats st;
            TraceOptions o;
            o.stats = &st;
            expect_miss(intersect(b8, r, with_isa(o, isa)), id + " bvh8/" + std::string(name(isa)));
            expect_miss(occluded(b8, r, with_isa(o, isa)), id + " bvh8 any/" + std::string(name(isa)));
            std::vector<Hit> h(1);
            intersect(b8, std::span(&r, 1), h, with_isa(o, isa));
            expect_miss(h[0], id + " bvh8 batch/" + std::string(name(isa)));
            if (!valid) EXPECT_EQ(st.nodes_visited, 0u) << id << " bvh8/" << name(isa);
        }
        expect_miss(brute_force_intersect(mesh, r), id + " brute");
    }
}

TEST(InvalidRays, NodesVisitedIsZeroForInvalidRaysOnly) {
    // Control: the stats do count for a valid ray, so 0 above means "not traversed".
    const Bvh2 bvh = Bvh2::build(workloads::icosphere(3));
    TraceStats st;
    TraceOptions o;
    o.stats = &st;
    EXPECT_TRUE(intersect(bvh, Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, kInf}, o).hit());
    EXPECT_GT(st.nodes_visited, 0u);
}

// Every degenerate case builds under the cap; the node count of a binary tree
// over n primitives is at most 2n - 1, and the BVH8's depth is at most the BVH2's.
TEST(DegenerateBuild, DepthAndNodeCountUnderTheCap) {
    const auto cases = workloads::make_family(workloads::Family::degenerate, {.quick = false});
    for (const auto& c : cases) {
        SCOPED_TRACE(c.name);
        for (int cap : {64, 16, 6}) {
            BuildOptions bo;
            bo.max_depth = cap;
            const Bvh2 bvh = Bvh2::build(c.mesh, bo);
            const BuildStats& s = bvh.stats();
            EXPECT_LE(s.depth, cap);
            EXPECT_GE(s.nodes, 1u);
            EXPECT_LE(s.nodes, 2 * c.mesh.size() - 1);
            EXPECT_LE(s.triangles, c.mesh.size());  // zero-area triangles may be left out
            const Bvh8 b8 = Bvh8::build(bvh);
            EXPECT_LE(b8.stats().depth, s.depth);
            EXPECT_LE(b8.stats().nodes, s.nodes);
        }
    }
}

TEST(DegenerateBuild, HundredThousandDuplicates) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.triangles.assign(100000, Triangle{0, 1, 2});
    const Bvh2 bvh = Bvh2::build(m);
    EXPECT_LE(bvh.stats().depth, kMaxDepth);
    EXPECT_LE(bvh.stats().nodes, 2 * m.size() - 1);
    // Every duplicate is hit at the same t: the tie goes to triangle 0.
    const Hit h = intersect(bvh, Ray{{0.25f, 0.25f, 1.0f}, 0.0f, {0, 0, -1}, kInf});
    EXPECT_EQ(h.prim, 0u);
    EXPECT_EQ(h.t, 1.0f);
}

}  // namespace
}  // namespace simdbvh
