// The BVH8 collapses every builder's BVH2 (the seed split rules included) and
// stays bit-identical to brute force on every ISA.
#include <gtest/gtest.h>

#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh {
namespace {

class Bvh8Builders : public testing::TestWithParam<Builder> {};

TEST_P(Bvh8Builders, CollapsedTreeMatchesBruteForceOnEveryIsa) {
    const Mesh mesh = workloads::random_soup(3000, 21);
    BuildOptions bo;
    bo.builder = GetParam();
    const Bvh2 bvh2 = Bvh2::build(mesh, bo);
    const auto rays = workloads::generate_rays(mesh, workloads::RayKind::incoherent, 2000, 4);
    std::vector<Hit> want(rays.size());
    brute_force_intersect(mesh, rays, want);
    std::size_t hits = 0;
    for (const Hit& h : want) hits += h.hit();
    ASSERT_GT(hits, rays.size() / 20);
    for (Collapse c : {Collapse::sah, Collapse::greedy}) {
        WideOptions o8;
        o8.collapse = c;
        const Bvh8 bvh8 = Bvh8::build(bvh2, o8);
        for (Isa isa : kAllIsas) {
            if (!supported(isa)) continue;  // every supported ISA; the others are covered where they run
            std::vector<Hit> got(rays.size()), any(rays.size());
            intersect(bvh8, rays, got, with_isa({}, isa));
            occluded(bvh8, rays, any, with_isa({}, isa));
            for (std::size_t i = 0; i < rays.size(); ++i) {
                ASSERT_EQ(got[i], want[i]) << name(GetParam()) << " " << name(c) << " " << name(isa) << " ray " << i;
                ASSERT_EQ(any[i].hit(), want[i].hit()) << name(GetParam()) << " " << name(isa) << " ray " << i;
            }
        }
    }
}

INSTANTIATE_TEST_SUITE_P(AllBuilders, Bvh8Builders,
                         testing::Values(Builder::sah_binned, Builder::sah_sweep, Builder::midpoint, Builder::median,
                                         Builder::variance),
                         [](const auto& info) {
                             std::string s(name(info.param));
                             for (char& ch : s)
                                 if (ch == '-') ch = '_';
                             return s;
                         });

}  // namespace
}  // namespace simdbvh
