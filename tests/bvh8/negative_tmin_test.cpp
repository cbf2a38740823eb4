// Rays whose interval reaches behind the origin (tmin < 0): the closest hit is
// the smallest t in [tmin, tmax], a negative one here, and every path must
// still give ties at equal t to the lower triangle id, as brute force does.
//
// The mesh is a flat grid of triangles in the plane x = 1, so every leaf box
// is flat and its entry distance equals, up to a few roundings, the t of each
// triangle in it. Every ray passes exactly (in real arithmetic) through a grid
// vertex, where up to six triangles (in different leaves) tie. The traversals
// cull a box when its entry lies beyond the closest hit "widened" by a margin;
// for a negative t the margin must still point away from the origin of the
// t axis' ordering (t + |t| eps, not t * (1 + eps)), or every tie across
// leaves is culled and the higher id wins.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/query/crossings.h"
#include "simdbvh/bvh2/spheres.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/kernels/isa.h"

namespace simdbvh {
namespace {

constexpr int kGrid = 48;

Mesh plane_grid() {
    Mesh m;
    for (int j = 0; j <= kGrid; ++j)
        for (int i = 0; i <= kGrid; ++i) m.positions.push_back({1.0f, float(i), float(j)});
    auto at = [](int i, int j) { return std::uint32_t(j * (kGrid + 1) + i); };
    for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) {
            m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    return m;
}

// Rays through grid vertex (1, y, z) at t = +-4 (sign = +1: in front of the
// origin; -1: behind it, found with tmin = -16, tmax = 0). Dyadic directions
// keep the origins exact.
std::vector<Ray> vertex_rays(int sign, std::size_t count) {
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> cell(1, kGrid - 1), slope(-64, 64);
    std::vector<Ray> rays;
    for (std::size_t k = 0; k < count; ++k) {
        const Vec3 p{1.0f, float(cell(rng)), float(cell(rng))};
        const Vec3 d{sign > 0 ? -1.0f : 1.0f, slope(rng) / 64.0f, slope(rng) / 64.0f};
        Ray r;
        // sign > 0: o = p - 4 d, hit at t = 4; sign < 0: o = p + 4 d, hit at t = -4.
        const float s = 4.0f;
        r.org = {p.x + (sign > 0 ? -s : s) * d.x, p.y + (sign > 0 ? -s : s) * d.y, p.z + (sign > 0 ? -s : s) * d.z};
        r.dir = d;
        r.tmin = sign > 0 ? 0.0f : -16.0f;
        r.tmax = sign > 0 ? 16.0f : 0.0f;
        rays.push_back(r);
    }
    return rays;
}

struct Case {
    Mesh mesh = plane_grid();
    std::vector<Ray> rays;
    std::vector<Hit> want, want_reversed;
    explicit Case(int sign) : rays(vertex_rays(sign, 4000)) {
        Mesh reversed = mesh;
        std::reverse(reversed.triangles.begin(), reversed.triangles.end());
        for (const Ray& r : rays) {
            want.push_back(brute_force_intersect(mesh, r));
            Hit h = brute_force_intersect(reversed, r);
            if (h.hit()) h.prim = std::uint32_t(mesh.size() - 1 - h.prim);
            want_reversed.push_back(h);
        }
    }
};

void expect_same(const Case& c, const std::vector<Hit>& got, const char* what) {
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < c.rays.size(); ++i) {
        ASSERT_NE(c.want[i].prim, kInvalidPrim) << "ray " << i << " misses the grid: the test is broken";
        if (got[i].prim != c.want[i].prim || got[i].t != c.want[i].t || got[i].u != c.want[i].u ||
            got[i].v != c.want[i].v)
            ++wrong;
    }
    EXPECT_EQ(wrong, 0u) << what << ": " << wrong << " of " << c.rays.size() << " rays differ from brute force";
}

class NegativeTmin : public testing::TestWithParam<int> {};

TEST_P(NegativeTmin, VertexTiesGoToTheLowerIdOnEveryPath) {
    const Case c(GetParam());
    // The hits are at t = +-4 (to rounding), and most rays tie: two or more
    // triangles report exactly the brute force's t, so the brute force over
    // the triangles in reverse order names another one.
    std::size_t tied = 0;
    for (std::size_t i = 0; i < c.rays.size(); ++i) {
        ASSERT_NEAR(c.want[i].t, 4.0f * GetParam(), 1e-4f) << "ray " << i;
        tied += c.want_reversed[i].prim != c.want[i].prim;
    }
    EXPECT_GT(tied, c.rays.size() / 2) << "too few ties: the test does not exercise the tie rule";

    BuildOptions small;
    small.max_leaf_size = 2;  // many leaves: ties across leaves
    const Bvh2 bvh2 = Bvh2::build(c.mesh, small);
    std::vector<Hit> got(c.rays.size());
    intersect(bvh2, c.rays, got);
    expect_same(c, got, "BVH2");

    // Any hit: some hit (every ray has one); all hits and crossing counts as the brute force's.
    occluded(bvh2, c.rays, got);
    for (std::size_t i = 0; i < c.rays.size(); ++i) ASSERT_NE(got[i].prim, kInvalidPrim) << "BVH2 any hit, ray " << i;
    for (std::size_t i = 0; i < c.rays.size(); i += 7) {
        const AllHits a = intersect_all(bvh2, c.rays[i]), b = brute_force_intersect_all(c.mesh, c.rays[i]);
        ASSERT_EQ(a.hits.size(), b.hits.size()) << "intersect_all, ray " << i;
        for (std::size_t k = 0; k < a.hits.size(); ++k) {
            EXPECT_EQ(a.hits[k].prim, b.hits[k].prim) << "intersect_all, ray " << i;
            EXPECT_EQ(a.hits[k].t, b.hits[k].t) << "intersect_all, ray " << i;
        }
        EXPECT_EQ(count_crossings(bvh2, c.rays[i]).winding, brute_force_count_crossings(c.mesh, c.rays[i]).winding);
    }

    const SphereBvh spheres = SphereBvh::build(c.mesh, small);
    intersect(spheres, c.rays, got);
    expect_same(c, got, "sphere BVH");

    for (Isa isa : {Isa::scalar, Isa::avx2, Isa::avx512}) {
        if (!supported(isa)) continue;
        intersect(Bvh4::build(bvh2), c.rays, got, with_isa({}, isa));
        expect_same(c, got, "BVH4");
        intersect(Bvh8::build(bvh2), c.rays, got, with_isa({}, isa));
        expect_same(c, got, "BVH8");
        const Bvh16 b16 = Bvh16::build(bvh2);
        intersect(b16, c.rays, got, with_isa({}, isa));
        expect_same(c, got, "BVH16");
        occluded(b16, c.rays, got, with_isa({}, isa));
        for (std::size_t i = 0; i < c.rays.size(); ++i)
            ASSERT_NE(got[i].prim, kInvalidPrim) << "BVH16 any hit, ray " << i;
    }
}

INSTANTIATE_TEST_SUITE_P(Sign, NegativeTmin, testing::Values(1, -1),
                         [](const testing::TestParamInfo<int>& i) { return i.param > 0 ? "InFront" : "Behind"; });

}  // namespace
}  // namespace simdbvh
