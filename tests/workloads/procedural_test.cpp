// Procedural scenes: icosphere closed and consistently wound, triangle counts,
// terrain size, determinism, named procedural scenes.
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <utility>

#include "simdbvh/kernels/error.h"
#include "simdbvh/workloads/scenes.h"

using simdbvh::Mesh;
using simdbvh::Vec3;
namespace wl = simdbvh::workloads;

namespace {

bool same_mesh(const Mesh& a, const Mesh& b) {
    return a.positions.size() == b.positions.size() && a.triangles == b.triangles &&
           std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * sizeof(Vec3)) == 0;
}

}  // namespace

TEST(Icosphere, ClosedWatertightOutwardCcw) {
    for (int level : {0, 1, 2, 4}) {
        SCOPED_TRACE(level);
        const Vec3 c{1.0f, -2.0f, 3.0f};
        const Mesh m = wl::icosphere(level, 2.0f, c);
        ASSERT_EQ(m.triangles.size(), 20u << (2 * level));
        EXPECT_EQ(m.positions.size(), 10u * (1u << (2 * level)) + 2);  // shared vertices: V = E - F + 2
        // Every undirected edge is used by exactly two triangles, once in each direction
        // (consistent winding).
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
        for (const auto& t : m.triangles)
            for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
        for (const auto& [e, n] : directed) {
            ASSERT_EQ(n, 1) << "directed edge used twice";
            ASSERT_EQ(directed.count({e.second, e.first}), 1u) << "edge " << e.first << "-" << e.second << " is open";
        }
        // Counter-clockwise seen from outside: the normal points away from the centre.
        for (std::size_t i = 0; i < m.size(); ++i) {
            const Vec3 v0 = m.vertex(i, 0), v1 = m.vertex(i, 1), v2 = m.vertex(i, 2);
            const Vec3 n = simdbvh::cross(v1 - v0, v2 - v0);
            ASSERT_GT(simdbvh::dot(n, (v0 + v1 + v2) * (1.0f / 3.0f) - c), 0.0f) << "triangle " << i;
        }
        for (const Vec3& p : m.positions) EXPECT_NEAR(simdbvh::length(p - c), 2.0f, 1e-5f);
    }
    EXPECT_THROW(wl::icosphere(-1), simdbvh::Error);
}

TEST(RandomSoup, CountUnitCubeDeterministic) {
    const Mesh a = wl::random_soup(5000, 42), b = wl::random_soup(5000, 42), c = wl::random_soup(5000, 43);
    EXPECT_EQ(a.triangles.size(), 5000u);
    EXPECT_TRUE(same_mesh(a, b));
    EXPECT_FALSE(same_mesh(a, c));
    const auto box = a.bounds();
    for (int k = 0; k < 3; ++k) {
        EXPECT_GE(box.lo[k], 0.0f);
        EXPECT_LE(box.hi[k], 1.0f);
        EXPECT_LT(box.lo[k], 0.1f);
        EXPECT_GT(box.hi[k], 0.9f);
    }
    EXPECT_EQ(wl::random_soup(0, 1).triangles.size(), 0u);
    // The exact numbers are fixed (own PRNG): a change here changes every benchmark.
    const Mesh one = wl::random_soup(1, 7);
    EXPECT_EQ(one.positions.size(), 3u);
}

// No time is asserted: speed is the benches' to show, and a timed assertion fails on a loaded or instrumented
// machine.
TEST(Terrain, AtLeastOneMillionAndDeterministic) {
    const Mesh m = wl::terrain();
    EXPECT_GE(m.triangles.size(), 1'000'000u);
    EXPECT_LT(m.triangles.size(), 1'200'000u);
    EXPECT_NO_THROW(simdbvh::validate(m));
    // Uneven density: the objects make some areas much denser than the heightfield.
    const Mesh small = wl::terrain(20'000, 3);
    EXPECT_GE(small.triangles.size(), 20'000u);
    EXPECT_TRUE(same_mesh(small, wl::terrain(20'000, 3)));
    EXPECT_FALSE(same_mesh(small, wl::terrain(20'000, 4)));
}

TEST(NamedScenes, Procedural) {
    EXPECT_EQ(wl::load_scene("icosphere").triangles.size(), 20u * 256u);
    EXPECT_EQ(wl::load_scene("icosphere-2").triangles.size(), 320u);
    EXPECT_EQ(wl::load_scene("soup").triangles.size(), 10000u);
    EXPECT_EQ(wl::load_scene("soup-123").triangles.size(), 123u);
    EXPECT_THROW(wl::load_scene("icosphere-99"), simdbvh::Error);
    EXPECT_THROW(wl::load_scene("no-such-scene"), simdbvh::Error);  // treated as a path
    const auto names = wl::scene_names();
    for (const char* n :
         {"dragon", "dragon-res2", "dragon-res3", "dragon-res4", "bunny", "teapot", "icosphere", "soup", "terrain"})
        EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
    EXPECT_FALSE(wl::cached_scene_file("icosphere").has_value());
}
