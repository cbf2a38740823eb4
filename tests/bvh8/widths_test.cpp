// Every node width (BVH4, BVH8, BVH16, all collapsed from the same BVH2) at
// every ISA: closest hits bit-identical (prim, t, u, v) to brute force and to
// the BVH2, any hit agreeing on hit/miss with a genuine hit, on several scenes
// and ray kinds, both triangle tests; ties at equal t go to the lower id.
// Cases the CPU cannot run are skipped, not passed.
#include <gtest/gtest.h>

#include <cctype>
#include <map>
#include <memory>
#include <string>
#include <tuple>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/kernels/triangle.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh {
namespace {

using workloads::RayKind;

bool npm_scene(const std::string& s) { return s == "bunny" || s == "teapot" || s.rfind("dragon", 0) == 0; }

constexpr std::size_t kRays = 6000;
constexpr std::size_t kBruteEvery = 7;  // brute force on every 7th ray (the BVH2 on all of them)

struct Fixture {
    Mesh mesh;
    Bvh2 bvh2;
    std::vector<Ray> rays;
    std::vector<Hit> want[2];   // BVH2 scalar closest hits, by TriangleTest (watertight, moller)
    std::vector<Hit> brute[2];  // brute force on every kBruteEvery-th ray
};

int test_index(TriangleTest t) { return t == TriangleTest::watertight ? 0 : 1; }

const Fixture& fixture(const std::string& scene, RayKind kind) {
    static std::map<std::pair<std::string, RayKind>, std::unique_ptr<Fixture>> cache;
    auto& f = cache[{scene, kind}];
    if (!f) {
        f = std::make_unique<Fixture>();
        f->mesh = workloads::load_scene(scene);
        f->bvh2 = Bvh2::build(f->mesh);
        f->rays = workloads::generate_rays(f->mesh, kind, kRays, /*seed=*/23);
        for (TriangleTest test : {TriangleTest::watertight, TriangleTest::moller}) {
            const int t = test_index(test);
            f->want[t].resize(f->rays.size());
            intersect(f->bvh2, f->rays, f->want[t], {test});
            for (std::size_t i = 0; i < f->rays.size(); i += kBruteEvery)
                f->brute[t].push_back(brute_force_intersect(f->mesh, f->rays[i], test));
        }
    }
    return *f;
}

bool genuine(const Mesh& mesh, const Ray& ray, const Hit& h, TriangleTest test) {
    float t, u, v;
    const PreparedRay r = prepare(ray);
    const Vec3 a = mesh.vertex(h.prim, 0), b = mesh.vertex(h.prim, 1), c = mesh.vertex(h.prim, 2);
    const bool hit = test == TriangleTest::watertight
                         ? intersect_triangle<TriangleTest::watertight>(r, a, b, c, ray.tmax, &t, &u, &v)
                         : intersect_triangle<TriangleTest::moller>(r, a, b, c, ray.tmax, &t, &u, &v);
    return hit && t == h.t;
}

template <int N>
void check_width(const Fixture& f, Isa isa) {
    const BvhN<N> bvh = BvhN<N>::build(f.bvh2);
    ASSERT_EQ(bvh.stats().triangles, f.bvh2.prim_ids().size());
    ASSERT_EQ(bvh.stats().width, N);
    for (TriangleTest test : {TriangleTest::watertight, TriangleTest::moller}) {
        const int ti = test_index(test);
        const char* tname = test == TriangleTest::watertight ? "watertight" : "moller";
        std::vector<Hit> got(f.rays.size()), any(f.rays.size());
        intersect(bvh, f.rays, got, with_isa({test}, isa));
        occluded(bvh, f.rays, any, with_isa({test}, isa));
        for (std::size_t i = 0; i < f.rays.size(); ++i) {
            ASSERT_EQ(got[i], f.want[ti][i])
                << "bvh" << N << " ray " << i << " (" << tname << "): prim " << got[i].prim << " t " << got[i].t
                << ", bvh2 prim " << f.want[ti][i].prim << " t " << f.want[ti][i].t;
            if (i % kBruteEvery == 0) {
                ASSERT_EQ(got[i], f.brute[ti][i / kBruteEvery]) << "bvh" << N << " vs brute force, ray " << i;
            }
            ASSERT_EQ(any[i].hit(), got[i].hit()) << "bvh" << N << " any hit disagrees on ray " << i;
            if (any[i].hit()) {
                ASSERT_LT(any[i].prim, f.mesh.size());
                EXPECT_TRUE(genuine(f.mesh, f.rays[i], any[i], test))
                    << "bvh" << N << " any hit ray " << i << " reports prim " << any[i].prim;
            }
        }
    }
}

using Param = std::tuple<std::string, RayKind, int, Isa>;

std::string param_name(const testing::TestParamInfo<Param>& info) {
    const auto& [s, k, w, isa] = info.param;
    std::string n =
        s + "_" + std::string(workloads::name(k)) + "_bvh" + std::to_string(w) + "_" + std::string(name(isa));
    for (char& ch : n)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    return n;
}

class WidthsVsBrute : public testing::TestWithParam<Param> {};

TEST_P(WidthsVsBrute, ClosestBitIdenticalAnyHitGenuine) {
    const auto [scene_name, kind, width, isa] = GetParam();
    if (!supported(isa)) GTEST_SKIP() << "CPU lacks " << name(isa);
    if (npm_scene(scene_name) && !workloads::is_cached(scene_name))
        GTEST_SKIP() << "scene '" << scene_name << "' is not cached: run scripts/fetch_scenes.sh";
    const Fixture& f = fixture(scene_name, kind);
    switch (width) {
    case 4: return check_width<4>(f, isa);
    case 8: return check_width<8>(f, isa);
    case 16: return check_width<16>(f, isa);
    }
    FAIL() << "width " << width;
}

INSTANTIATE_TEST_SUITE_P(Scenes, WidthsVsBrute,
                         testing::Combine(testing::Values("icosphere-4", "soup-3000", "bunny", "dragon-res4"),
                                          testing::Values(RayKind::primary, RayKind::incoherent, RayKind::diffuse),
                                          testing::Values(4, 8, 16), testing::ValuesIn(kAllIsas)),
                         param_name);
// The distributions renderers and simulators send beyond the bench's three (workloads/rays.h): shuffled
// bounces, shadow rays with a finite tmax, short AO rays, a LiDAR spin from inside the bounds.
INSTANTIATE_TEST_SUITE_P(Distributions, WidthsVsBrute,
                         testing::Combine(testing::Values("soup-3000", "dragon-res4"),
                                          testing::Values(RayKind::diffuse_shuffled, RayKind::shadow,
                                                          RayKind::area_shadow, RayKind::ao, RayKind::lidar),
                                          testing::Values(4, 8, 16), testing::ValuesIn(kAllIsas)),
                         param_name);

// The SIMD node tests (4 lanes in xmm, 8 in ymm, 16 in zmm or two ymm halves)
// are bit for bit the scalar box test: every ISA visits exactly the same nodes
// and blocks (same hit masks, same entry distances, so the same order), also
// for axis-aligned rays with +-0 components and origins on box planes.
template <int N>
void expect_same_visits(const Mesh& mesh, const std::vector<Ray>& rays, const std::string& what) {
    const BvhN<N> bvh = BvhN<N>::build(mesh);
    TraceStats want, want_any;
    TraceOptions o;
    o.stats = &want;
    std::vector<Hit> ref(rays.size()), got(rays.size());
    intersect(bvh, rays, ref, with_isa(o, Isa::scalar));
    o.stats = &want_any;
    occluded(bvh, rays, ref, with_isa(o, Isa::scalar));
    std::uint64_t valid = 0;  // each valid ray tests the tree's bounds once
    for (const Ray& r : rays) valid += prepare(r).valid;
    EXPECT_EQ(want.box_tests, N * want.nodes_visited + valid);
    for (Isa isa : kAllIsas) {
        if (isa == Isa::scalar || !supported(isa)) continue;
        TraceStats st, st_any;
        o.stats = &st;
        intersect(bvh, rays, got, with_isa(o, isa));
        o.stats = &st_any;
        occluded(bvh, rays, got, with_isa(o, isa));
        EXPECT_EQ(st.nodes_visited, want.nodes_visited) << what << " bvh" << N << " " << name(isa);
        EXPECT_EQ(st.triangle_tests, want.triangle_tests) << what << " bvh" << N << " " << name(isa);
        EXPECT_EQ(st_any.nodes_visited, want_any.nodes_visited) << what << " bvh" << N << " any " << name(isa);
        EXPECT_EQ(st_any.triangle_tests, want_any.triangle_tests) << what << " bvh" << N << " any " << name(isa);
    }
}

TEST(WidthsNodeTest, EveryIsaVisitsTheSameNodes) {
    std::vector<std::pair<std::string, Mesh>> meshes;
    meshes.emplace_back("icosphere-4", workloads::icosphere(4));
    meshes.emplace_back("soup-3000", workloads::random_soup(3000, 5));
    if (workloads::is_cached("dragon-res4")) meshes.emplace_back("dragon-res4", workloads::load_scene("dragon-res4"));
    for (const auto& [what, mesh] : meshes) {
        std::vector<Ray> rays = workloads::generate_rays(mesh, RayKind::incoherent, 3000, 17);
        const Aabb b = mesh.bounds();
        // Axis-aligned rays with +-0 components, from the box's planes and corners.
        for (float sx : {0.0f, -0.0f, 1.0f, -1.0f})
            for (float sy : {0.0f, -0.0f, 1.0f, -1.0f})
                for (float sz : {0.0f, -0.0f, 1.0f, -1.0f})
                    for (const Vec3& o : {b.lo, b.hi, Vec3{0, 0, 0}, Vec3{b.lo.x, 0, b.hi.z}})
                        rays.push_back({o, 0, {sx, sy, sz}});
        expect_same_visits<4>(mesh, rays, what);
        expect_same_visits<8>(mesh, rays, what);
        expect_same_visits<16>(mesh, rays, what);
    }
}

// Every triangle twice (same vertices, ids i and i + n): every hit is a tie at
// equal t, won by the lower id, at every width and ISA; small trees (0..40
// triangles, BVH2 leaves of 1) fill nodes and blocks partly.
class WidthsSmall : public testing::TestWithParam<Isa> {};

template <int N>
void check_small(const Mesh& mesh, Isa isa, const std::string& what) {
    BuildOptions bo;
    bo.max_leaf_size = 1;
    const Bvh2 bvh2 = Bvh2::build(mesh, bo);
    for (Collapse c : {Collapse::sah, Collapse::greedy}) {
        WideOptions o;
        o.collapse = c;
        const BvhN<N> bvh = BvhN<N>::build(bvh2, o);
        Aabb b = mesh.bounds();
        if (b.is_empty()) b = Aabb{{-1, -1, -1}, {1, 1, 1}};
        const auto rays = workloads::incoherent_rays(b, 1500, 5);
        std::vector<Hit> got(rays.size()), any(rays.size());
        intersect(bvh, rays, got, with_isa({}, isa));
        occluded(bvh, rays, any, with_isa({}, isa));
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const Hit want = brute_force_intersect(mesh, rays[i]);
            ASSERT_EQ(got[i], want) << what << " bvh" << N << " " << name(c) << " ray " << i;
            ASSERT_EQ(any[i].hit(), want.hit()) << what << " bvh" << N << " ray " << i;
            if (want.hit()) {
                ASSERT_LT(want.prim, mesh.size() / 2) << "the tie goes to the lower id";
            }
        }
    }
}

TEST_P(WidthsSmall, DuplicatedTrianglesTieToLowerId) {
    const Isa isa = GetParam();
    if (!supported(isa)) GTEST_SKIP() << "CPU lacks " << name(isa);
    for (std::size_t n : {0u, 1u, 3u, 9u, 17u, 40u}) {
        Mesh mesh = workloads::random_soup(n, 31 + n);
        const std::size_t tris = mesh.triangles.size();
        for (std::size_t k = 0; k < tris; ++k) mesh.triangles.push_back(mesh.triangles[k]);
        const std::string what = std::to_string(n) + " triangles twice";
        check_small<4>(mesh, isa, what);
        check_small<8>(mesh, isa, what);
        check_small<16>(mesh, isa, what);
    }
}

INSTANTIATE_TEST_SUITE_P(Isas, WidthsSmall, testing::ValuesIn(kAllIsas),
                         [](const testing::TestParamInfo<Isa>& i) { return std::string(name(i.param)); });

}  // namespace
}  // namespace simdbvh
