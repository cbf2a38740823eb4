// The BVH8 of a finite mesh whose boxes overflow float areas
// (a triangle spanning 2e19, coordinates up to +-3e38) builds with every
// builder and collapse (the SAH collapse used to read from[n][-1] and recurse
// until the stack overflowed), keeps a finite cost, and traces bit for bit
// like brute force on every ISA.
#include <gtest/gtest.h>

#include <cmath>

#include "simdbvh/bvh8/internal/collapse.h"
#include "simdbvh/bvh8/bvh8.h"
#include "support/huge_meshes.h"

namespace simdbvh {
namespace {

struct Case {
    const char* mesh;
    Builder builder;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.mesh << " " << name(c.builder); }

class Bvh8HugeCoordinates : public testing::TestWithParam<Case> {};

TEST_P(Bvh8HugeCoordinates, EveryCollapseMatchesBruteForceOnEveryIsa) {
    const Mesh mesh =
        std::string_view(GetParam().mesh) == "huge_triangle" ? test::huge_triangle_mesh() : test::extreme_mesh();
    BuildOptions bo;
    bo.builder = GetParam().builder;
    const Bvh2 bvh2 = Bvh2::build(mesh, bo);
    const auto rays = test::huge_mesh_rays(mesh);
    std::vector<Hit> want(rays.size());
    brute_force_intersect(mesh, rays, want);
    std::size_t hits = 0;
    for (const Hit& h : want) hits += h.hit();
    ASSERT_GT(hits, rays.size() / 10) << "the rays must hit something";
    for (Collapse c : {Collapse::sah, Collapse::greedy})
        for (int leaf : {1, 4, 8, 32}) {
            WideOptions o8;
            o8.collapse = c;
            o8.max_leaf_size = leaf;
            const std::string what = std::string(name(c)) + " max_leaf_size " + std::to_string(leaf);
            const bvh8::WideTopology<8> topo = bvh8::collapse<8>(bvh2, o8);
            EXPECT_TRUE(std::isfinite(bvh8::sah_cost<8>(topo, o8))) << what;
            const Bvh8 bvh8 = Bvh8::build(bvh2, o8);
            EXPECT_TRUE(std::isfinite(bvh8.stats().sah_cost)) << what;
            for (Isa isa : kAllIsas) {
                if (!supported(isa)) continue;
                std::vector<Hit> got(rays.size()), any(rays.size());
                intersect(bvh8, rays, got, with_isa({}, isa));
                occluded(bvh8, rays, any, with_isa({}, isa));
                for (std::size_t i = 0; i < rays.size(); ++i) {
                    ASSERT_EQ(got[i], want[i]) << what << " " << name(isa) << " ray " << i;
                    ASSERT_EQ(any[i].hit(), want[i].hit()) << what << " " << name(isa) << " ray " << i;
                }
            }
        }
}

std::vector<Case> all_cases() {
    std::vector<Case> v;
    for (const char* m : {"huge_triangle", "extreme"})
        for (Builder b :
             {Builder::sah_binned, Builder::sah_sweep, Builder::midpoint, Builder::median, Builder::variance})
            v.push_back({m, b});
    return v;
}

INSTANTIATE_TEST_SUITE_P(AllBuilders, Bvh8HugeCoordinates, testing::ValuesIn(all_cases()), [](const auto& info) {
    std::string s = std::string(info.param.mesh) + "_" + std::string(name(info.param.builder));
    for (char& ch : s)
        if (ch == '-') ch = '_';
    return s;
});

}  // namespace
}  // namespace simdbvh
