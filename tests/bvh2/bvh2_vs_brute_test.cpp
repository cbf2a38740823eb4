// BVH2 against brute force: bit-identical closest hits (ties to the lower id)
// and any-hit agreement on hit/miss, on real and procedural scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <string>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"
#include "support/sanitizer.h"

namespace simdbvh {
namespace {

using workloads::RayKind;

struct Case {
    std::string scene;
    RayKind kind;
    Builder builder;
};

std::string case_name(const testing::TestParamInfo<Case>& info) {
    std::string s = info.param.scene + "_" + std::string(workloads::name(info.param.kind)) + "_" +
                    std::string(name(info.param.builder));
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

class Bvh2VsBrute : public testing::TestWithParam<Case> {};

TEST_P(Bvh2VsBrute, ClosestAndAnyHitMatchBruteForce) {
    const Case& c = GetParam();
    const bool npm_scene = c.scene == "bunny" || c.scene == "teapot" || c.scene.rfind("dragon", 0) == 0;
    if (npm_scene && !workloads::is_cached(c.scene))
        GTEST_SKIP() << "scene '" << c.scene << "' is not cached: run scripts/fetch_scenes.sh";
    const Mesh mesh = workloads::load_scene(c.scene);
    BuildOptions opts;
    opts.builder = c.builder;
    const Bvh2 bvh = Bvh2::build(mesh, opts);
    // Brute force is O(rays x triangles): keep the product near 1e8.
    // (an eighth of the rays under a sanitizer: support/sanitizer.h)
    const std::size_t count =
        test::sampled(std::clamp<std::size_t>(100'000'000 / std::max<std::size_t>(mesh.size(), 1), 500, 20000), 200);
    const auto rays = workloads::generate_rays(mesh, c.kind, count, /*seed=*/7);
    ASSERT_EQ(rays.size(), count);
    std::vector<Hit> got(rays.size()), any(rays.size());
    intersect(bvh, rays, got);
    occluded(bvh, rays, any);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit want = brute_force_intersect(mesh, rays[i]);
        ASSERT_EQ(got[i], want) << "ray " << i << ": bvh2 prim " << got[i].prim << " t " << got[i].t << ", brute prim "
                                << want.prim << " t " << want.t;
        ASSERT_EQ(any[i].hit(), want.hit()) << "any-hit disagrees on ray " << i;
        if (any[i].hit()) {  // the reported triangle really is hit within the ray's interval
            EXPECT_LE(rays[i].tmin, any[i].t);
            EXPECT_LE(any[i].t, rays[i].tmax);
            EXPECT_LT(any[i].prim, mesh.size());
        }
        hits += want.hit();
    }
    // Primary and incoherent rays aim at the scene: a test where nothing is hit
    // proves nothing. Diffuse rays mostly escape (all of them on a convex icosphere).
    if (c.kind != RayKind::diffuse) EXPECT_GT(hits, rays.size() / 20) << "too few hits for a meaningful comparison";
    else if (c.scene.rfind("icosphere", 0) != 0) EXPECT_GT(hits, 0u) << "no diffuse ray hits";
}

std::vector<Case> cases() {
    std::vector<Case> out;
    for (const char* s : {"bunny", "teapot", "dragon-res4", "icosphere-4", "soup-3000"})
        for (RayKind k : {RayKind::primary, RayKind::incoherent, RayKind::diffuse})
            out.push_back({s, k, Builder::sah_binned});
    for (Builder b : {Builder::sah_sweep, Builder::midpoint, Builder::median, Builder::variance})
        for (RayKind k : {RayKind::primary, RayKind::incoherent}) out.push_back({"soup-3000", k, b});
    return out;
}

INSTANTIATE_TEST_SUITE_P(Scenes, Bvh2VsBrute, testing::ValuesIn(cases()), case_name);

}  // namespace
}  // namespace simdbvh
