// Finite meshes whose boxes overflow float areas (a triangle
// spanning 2e19, coordinates up to +-3e38) build with every builder, keep a
// finite SAH cost, let the SAH separate the huge triangle from the small ones,
// and trace bit for bit like brute force.
#include <gtest/gtest.h>

#include <cmath>

#include "simdbvh/bvh2/bvh2.h"
#include "support/huge_meshes.h"

namespace simdbvh {
namespace {

struct Case {
    const char* mesh;
    Builder builder;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.mesh << " " << name(c.builder); }

Mesh mesh_of(const Case& c) {
    return std::string_view(c.mesh) == "huge_triangle" ? test::huge_triangle_mesh() : test::extreme_mesh();
}

class HugeCoordinates : public testing::TestWithParam<Case> {};

TEST_P(HugeCoordinates, FiniteCostAndBitIdenticalToBruteForce) {
    const Mesh mesh = mesh_of(GetParam());
    BuildOptions bo;
    bo.builder = GetParam().builder;
    const Bvh2 bvh = Bvh2::build(mesh, bo);
    EXPECT_TRUE(std::isfinite(bvh.stats().sah_cost)) << bvh.stats().sah_cost;
    EXPECT_TRUE(std::isfinite(sah_cost(build_topology(mesh, bo)))) << "topology SAH cost";

    const auto rays = test::huge_mesh_rays(mesh);
    std::vector<Hit> want(rays.size()), got(rays.size()), any(rays.size());
    brute_force_intersect(mesh, rays, want);
    std::size_t hits = 0;
    for (const Hit& h : want) hits += h.hit();
    ASSERT_GT(hits, rays.size() / 10) << "the rays must hit something";
    intersect(bvh, rays, got);
    occluded(bvh, rays, any);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(got[i], want[i]) << "ray " << i;
        ASSERT_EQ(intersect(bvh, rays[i]), want[i]) << "single ray " << i;
        ASSERT_EQ(any[i].hit(), want[i].hit()) << "ray " << i;
    }
}

// The SAH isolates the 2e19 triangle (prim 0) from the 8 small ones: with
// float areas every cost was +inf and the builders fell back to the object
// median, which leaves it in a leaf with small triangles.
TEST(HugeCoordinatesSah, HugeTriangleGetsItsOwnLeaf) {
    const Mesh mesh = test::huge_triangle_mesh();
    for (Builder b : {Builder::sah_binned, Builder::sah_sweep}) {
        BuildOptions bo;
        bo.builder = b;
        const Bvh2 bvh = Bvh2::build(mesh, bo);
        bool alone = false;
        for (const Node2& n : bvh.nodes())
            if (n.is_leaf())
                for (std::uint32_t k = n.first; k < n.first + n.count; ++k)
                    if (bvh.prim_ids()[k] == 0) alone = n.count == 1;
        EXPECT_TRUE(alone) << name(b);
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

INSTANTIATE_TEST_SUITE_P(AllBuilders, HugeCoordinates, testing::ValuesIn(all_cases()), [](const auto& info) {
    std::string s = std::string(info.param.mesh) + "_" + std::string(name(info.param.builder));
    for (char& ch : s)
        if (ch == '-') ch = '_';
    return s;
});

}  // namespace
}  // namespace simdbvh
