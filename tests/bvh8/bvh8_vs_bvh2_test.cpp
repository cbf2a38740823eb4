// BVH8 against the BVH2 scalar traversal: bit-identical closest hits (t, u, v,
// prim) for every ISA and both collapse variants, any-hit agreeing on hit/miss.
// Every case runs once per ISA and is skipped (not passed) when the CPU lacks it.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <tuple>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/kernels/box.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/triangle.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh {
namespace {

using workloads::RayKind;

bool npm_scene(const std::string& s) { return s == "bunny" || s == "teapot" || s.rfind("dragon", 0) == 0; }

// Scene, BVH2, rays and the BVH2 scalar answers, built once per (scene, ray kind).
struct Fixture {
    Mesh mesh;
    Bvh2 bvh2;
    std::vector<Ray> rays;
    std::vector<Hit> want_watertight, want_moller;
};

const Fixture& fixture(const std::string& scene, RayKind kind) {
    static std::map<std::pair<std::string, RayKind>, std::unique_ptr<Fixture>> cache;
    auto& f = cache[{scene, kind}];
    if (!f) {
        f = std::make_unique<Fixture>();
        f->mesh = workloads::load_scene(scene);
        f->bvh2 = Bvh2::build(f->mesh);
        f->rays = workloads::generate_rays(f->mesh, kind, 20000, /*seed=*/11);
        f->want_watertight.resize(f->rays.size());
        f->want_moller.resize(f->rays.size());
        intersect(f->bvh2, f->rays, f->want_watertight);
        intersect(f->bvh2, f->rays, f->want_moller, {TriangleTest::moller});
    }
    return *f;
}

using Param = std::tuple<std::string, RayKind, Collapse, Isa>;

std::string param_name(const testing::TestParamInfo<Param>& info) {
    auto [s, k, c, isa] = info.param;
    std::string n =
        s + "_" + std::string(workloads::name(k)) + "_" + std::string(name(c)) + "_" + std::string(name(isa));
    for (char& ch : n)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    return n;
}

class Bvh8VsBvh2 : public testing::TestWithParam<Param> {};

TEST_P(Bvh8VsBvh2, ClosestBitIdenticalAnyHitAgrees) {
    const auto [scene_name, kind, collapse, isa] = GetParam();
    if (!supported(isa)) GTEST_SKIP() << "CPU lacks " << name(isa);
    if (npm_scene(scene_name) && !workloads::is_cached(scene_name))
        GTEST_SKIP() << "scene '" << scene_name << "' is not cached: run scripts/fetch_scenes.sh";
    const Fixture& f = fixture(scene_name, kind);
    WideOptions o;
    o.collapse = collapse;
    const Bvh8 bvh8 = Bvh8::build(f.bvh2, o);
    ASSERT_EQ(bvh8.stats().triangles, f.bvh2.prim_ids().size());
    if (collapse == Collapse::sah || scene_name != "icosphere-4") {  // greedy icosphere-4: only full 8-triangle leaves
        EXPECT_GT(bvh8.stats().shared_blocks, 0u) << "no shared Tri8 blocks: the sharing is not exercised";
    }
    for (TriangleTest test : {TriangleTest::watertight, TriangleTest::moller}) {
        const auto& want = test == TriangleTest::watertight ? f.want_watertight : f.want_moller;
        std::vector<Hit> got(f.rays.size()), any(f.rays.size());
        intersect(bvh8, f.rays, got, with_isa({test}, isa));
        occluded(bvh8, f.rays, any, with_isa({test}, isa));
        std::size_t hits = 0;
        for (std::size_t i = 0; i < f.rays.size(); ++i) {
            ASSERT_EQ(got[i], want[i]) << "ray " << i << " ("
                                       << (test == TriangleTest::watertight ? "watertight" : "moller")
                                       << "): bvh8 prim " << got[i].prim << " t " << got[i].t << ", bvh2 prim "
                                       << want[i].prim << " t " << want[i].t;
            ASSERT_EQ(any[i].hit(), want[i].hit()) << "any-hit disagrees on ray " << i;
            if (any[i].hit()) {
                EXPECT_LE(f.rays[i].tmin, any[i].t);
                EXPECT_LE(any[i].t, f.rays[i].tmax);
                ASSERT_LT(any[i].prim, f.mesh.size());
                // A genuine hit of that triangle (shared Tri8 blocks: it may be a sibling leaf's triangle).
                const std::uint32_t p = any[i].prim;
                float t, u, v;
                const bool genuine = test == TriangleTest::watertight
                                         ? intersect_triangle<TriangleTest::watertight>(
                                               prepare(f.rays[i]), f.mesh.vertex(p, 0), f.mesh.vertex(p, 1),
                                               f.mesh.vertex(p, 2), f.rays[i].tmax, &t, &u, &v)
                                         : intersect_triangle<TriangleTest::moller>(
                                               prepare(f.rays[i]), f.mesh.vertex(p, 0), f.mesh.vertex(p, 1),
                                               f.mesh.vertex(p, 2), f.rays[i].tmax, &t, &u, &v);
                EXPECT_TRUE(genuine) << "any-hit ray " << i << " reports prim " << p << " it does not hit";
                if (genuine) {
                    EXPECT_EQ(any[i].t, t) << "any-hit ray " << i;
                }
                ++hits;
            }
        }
        if (kind != RayKind::diffuse && scene_name.rfind("soup", 0) != 0) {  // diffuse rays mostly escape convex scenes
            EXPECT_GT(hits, f.rays.size() / 20) << "too few hits to mean anything";
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, Bvh8VsBvh2,
                         testing::Combine(testing::Values("icosphere-4", "soup-3000", "bunny", "teapot", "dragon-res4"),
                                          testing::Values(RayKind::primary, RayKind::incoherent, RayKind::diffuse),
                                          testing::Values(Collapse::sah, Collapse::greedy),
                                          testing::ValuesIn(kAllIsas)),
                         param_name);

// Small and partly filled trees: 0..9 triangles, and BVH2 leaves of 1-2
// triangles so most Node8s and Tri8 blocks are partly filled. Checked against
// the BVH2 and brute force.
class Bvh8Small : public testing::TestWithParam<Isa> {};

std::vector<Ray> rays_around(const Mesh& mesh, std::size_t count, std::uint64_t seed) {
    Aabb b = mesh.bounds();
    if (b.is_empty()) b = Aabb{{-1, -1, -1}, {1, 1, 1}};
    return workloads::incoherent_rays(b, count, seed);
}

void expect_same(const Mesh& mesh, const BuildOptions& bo, const WideOptions& o, Isa isa, const std::string& what) {
    const Bvh2 bvh2 = Bvh2::build(mesh, bo);
    const Bvh8 bvh8 = Bvh8::build(bvh2, o);
    const auto rays = rays_around(mesh, 3000, 5);
    std::vector<Hit> want(rays.size()), got(rays.size()), any(rays.size());
    intersect(bvh2, rays, want);
    intersect(bvh8, rays, got, with_isa({}, isa));
    occluded(bvh8, rays, any, with_isa({}, isa));
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(got[i], want[i]) << what << ": ray " << i;
        ASSERT_EQ(got[i], brute_force_intersect(mesh, rays[i])) << what << ": ray " << i;
        ASSERT_EQ(any[i].hit(), want[i].hit()) << what << ": ray " << i;
    }
}

TEST_P(Bvh8Small, FewTriangles) {
    const Isa isa = GetParam();
    if (!supported(isa)) GTEST_SKIP() << "CPU lacks " << name(isa);
    for (std::size_t n : {0u, 1u, 3u, 7u, 8u, 9u, 17u}) {
        const Mesh mesh = workloads::random_soup(n, 100 + n);
        for (Collapse c : {Collapse::sah, Collapse::greedy}) {
            WideOptions o;
            o.collapse = c;
            expect_same(mesh, {}, o, isa, std::to_string(n) + " triangles, " + std::string(name(c)));
            const Bvh8 b = Bvh8::build(mesh, {}, o);
            if (n == 0) {
                EXPECT_TRUE(b.nodes().empty());
                EXPECT_TRUE(b.blocks().empty());
            } else {
                EXPECT_EQ(b.stats().triangles, n);
            }
        }
    }
}

TEST_P(Bvh8Small, PartlyFilledNodesAndBlocks) {
    const Isa isa = GetParam();
    if (!supported(isa)) GTEST_SKIP() << "CPU lacks " << name(isa);
    for (std::size_t n : {20u, 50u, 300u}) {
        const Mesh mesh = workloads::random_soup(n, 7 * n);
        for (int leaf : {1, 2, 3}) {
            BuildOptions bo;
            bo.max_leaf_size = leaf;
            for (Collapse c : {Collapse::sah, Collapse::greedy}) {
                for (int max_leaf : {1, 3, 8, 16}) {
                    WideOptions o;
                    o.collapse = c;
                    o.max_leaf_size = max_leaf;
                    expect_same(mesh, bo, o, isa,
                                std::to_string(n) + " tris, bvh2 leaf " + std::to_string(leaf) + ", " +
                                    std::string(name(c)) + ", bvh8 leaf " + std::to_string(max_leaf));
                }
            }
        }
    }
}

// Invalid rays and rays that miss the tree's bounds miss without visiting a
// node; stats do not change results.
TEST_P(Bvh8Small, InvalidRaysAndStats) {
    const Isa isa = GetParam();
    if (!supported(isa)) GTEST_SKIP() << "CPU lacks " << name(isa);
    const Mesh mesh = workloads::icosphere(3);
    const Bvh8 bvh8 = Bvh8::build(mesh);
    constexpr float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const std::vector<Ray> bad = {
        {{0, 0, -5}, 0, {0, 0, 0}, inf},    // zero direction
        {{nan, 0, -5}, 0, {0, 0, 1}, inf},  // NaN origin
        {{0, 0, -5}, 0, {0, nan, 1}, inf},  // NaN direction
        {{0, 0, -5}, 0, {inf, 0, 1}, inf},  // infinite direction
        {{0, 0, -5}, 3, {0, 0, 1}, 2},      // tmin > tmax
        {{0, 0, -5}, nan, {0, 0, 1}, inf},  // NaN tmin
    };
    for (const Ray& r : bad) {
        TraceStats st;
        TraceOptions o;
        o.stats = &st;
        const Hit h = intersect(bvh8, r, with_isa(o, isa));
        EXPECT_FALSE(h.hit());
        EXPECT_TRUE(std::isinf(h.t));
        EXPECT_FALSE(occluded(bvh8, r, with_isa(o, isa)).hit());
        EXPECT_EQ(st.nodes_visited, 0u);
        EXPECT_EQ(st.rays, 2u);
    }
    const auto rays = rays_around(mesh, 2000, 3);
    std::vector<Hit> plain(rays.size()), counted(rays.size());
    TraceStats st;
    intersect(bvh8, rays, plain, with_isa({}, isa));
    TraceOptions counting;
    counting.stats = &st;
    intersect(bvh8, rays, counted, with_isa(counting, isa));
    for (std::size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(plain[i], counted[i]) << "ray " << i;
    EXPECT_EQ(st.rays, rays.size());
    // Every ray is valid and aimed into the bounds: one test of the tree's
    // bounds each, then at least the root node.
    for (const Ray& r : rays) {
        const PreparedRay p = prepare(r);
        float e;
        ASSERT_TRUE(p.valid && intersect_box(p, bvh8.bounds(), p.tmax, &e));
    }
    EXPECT_GE(st.nodes_visited, rays.size());
    EXPECT_EQ(st.box_tests, 8 * st.nodes_visited + rays.size());
    // The same rays turned around (they start outside the bounds and leave
    // them): the bounds test ends each one, no node is visited, no hit.
    std::vector<Ray> away = rays;
    for (Ray& r : away) r.dir = r.dir * -1.0f;
    TraceStats st_away;
    counting.stats = &st_away;
    intersect(bvh8, away, counted, with_isa(counting, isa));
    for (std::size_t i = 0; i < away.size(); ++i) ASSERT_FALSE(counted[i].hit()) << "ray " << i;
    EXPECT_EQ(st_away.nodes_visited, 0u);
    EXPECT_EQ(st_away.box_tests, away.size());
    EXPECT_EQ(st.triangle_tests % 8, 0u);
}

INSTANTIATE_TEST_SUITE_P(Isas, Bvh8Small, testing::ValuesIn(kAllIsas),
                         [](const testing::TestParamInfo<Isa>& i) { return std::string(name(i.param)); });

// TraceOptions::threads splits a batch; the answers do not change.
TEST_P(Bvh8Small, ThreadsGiveSameHits) {
    const Isa isa = GetParam();
    if (!supported(isa)) GTEST_SKIP() << "CPU lacks " << name(isa);
    const Mesh mesh = workloads::icosphere(4);
    const Bvh8 bvh8 = Bvh8::build(mesh);
    const auto rays = rays_around(mesh, 10000, 4);
    std::vector<Hit> one(rays.size()), many(rays.size());
    intersect(bvh8, rays, one, with_isa({}, isa));
    TraceOptions o;
    o.threads = 2;
    intersect(bvh8, rays, many, with_isa(o, isa));
    for (std::size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(one[i], many[i]) << "ray " << i;
}

TEST(Bvh8Api, UnsupportedIsaThrowsAndSpanSizeIsChecked) {
    const Bvh8 bvh8 = Bvh8::build(workloads::icosphere(1));
    const std::vector<Ray> rays(4, Ray{{0, 0, -5}, 0, {0, 0, 1}});
    std::vector<Hit> hits(3);
    EXPECT_THROW(intersect(bvh8, rays, hits, with_isa({}, Isa::scalar)), Error);
    for (Isa isa : kAllIsas)
        if (!supported(isa)) {
            EXPECT_THROW(intersect(bvh8, rays[0], with_isa({}, isa)), Error) << name(isa);
        }
    EXPECT_EQ(parse_collapse("sah"), Collapse::sah);
    EXPECT_EQ(parse_collapse("greedy"), Collapse::greedy);
    EXPECT_FALSE(parse_collapse("nope"));
    WideOptions bad;
    bad.max_leaf_size = 0;
    EXPECT_THROW(Bvh8::build(workloads::icosphere(1), {}, bad), Error);
}

}  // namespace
}  // namespace simdbvh
