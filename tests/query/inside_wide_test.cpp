// Exact inside/outside on the wide trees (query/src/inside_wide.cpp): every field
// (side, ray, winding, crossings) equal to the brute-force count with the same
// predicates (tests/query/inside_test.cpp checks those against answers derived
// by hand) at widths 4, 8, 16, one and two threads, both rules, four ray
// choices (on the soup, an open mesh, the rays disagree: the same ray must be
// picked on every path); on 64
// separated cubes with points on a quarter grid (their +z rays run through
// vertices and along edges and faces of cubes in different leaves, and the
// side is known by hand), on a sphere with points at its vertices and edge
// midpoints, and on a soup of overlapping triangles (windings above 1, many
// leaves sharing a Tri8 block: a leaf must count its own lanes only).
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "simdbvh/query/inside_wide.h"
#include "simdbvh/workloads/points.h"
#include "simdbvh/workloads/scenes.h"
#include "support/scene.h"

namespace simdbvh {
namespace {

template <int N>
std::size_t shared_leaves(const BvhN<N>& t) {
    std::size_t n = 0;
    for (const NodeN<N>& node : t.nodes())
        for (const ChildN<N>& c : node.children) n += c.is_leaf() && c.sharing_slots() != 0;
    return n;
}

// Checks every width against brute force, for the shortest ray and three
// fixed ones (each axis, both signs) and both rules; returns the BVH8's answers
// (default options: winding rule, shortest ray).
std::vector<PointSide> check(const Mesh& mesh, const std::vector<Vec3>& pts, const char* what,
                             bool expect_shared = false) {
    std::vector<PointSide> result;
    const Bvh4 b4 = Bvh4::build(mesh);
    const Bvh8 b8 = Bvh8::build(mesh);
    const Bvh16 b16 = Bvh16::build(mesh);
    for (const CountRay r : {CountRay::shortest, CountRay::plus_z, CountRay::minus_x, CountRay::minus_y}) {
        const int ray = int(r);
        InsideOptions winding;
        winding.ray = r;
        std::vector<PointSide> brute(pts.size());
        for (std::size_t i = 0; i < pts.size(); ++i) brute[i] = brute_force_classify_point(mesh, pts[i], winding);
        for (const bool par : {false, true}) {
            InsideOptions o = winding;
            o.rule = par ? InsideOptions::Rule::parity : InsideOptions::Rule::winding;
            std::vector<PointSide> want = brute;  // the parity rule: the same count, odd = inside
            if (par)
                for (PointSide& w : want)
                    if (w.side != Side::surface) w.side = w.crossings % 2 ? Side::inside : Side::outside;
            auto run = [&]<int N>(const BvhN<N>& wide) {
                if (expect_shared) {
                    EXPECT_GT(shared_leaves(wide), 0u) << what << " N=" << N << ": no shared block tested";
                }
                // Both thread counts on the default ray, one thread on the fixed ones.
                for (int threads = 1; threads <= (o.ray == CountRay::shortest ? 2 : 1); ++threads) {
                    InsideOptions ot = o;
                    ot.threads = threads;
                    std::vector<PointSide> got(pts.size());
                    classify_points(wide, pts, got, ot);
                    for (std::size_t i = 0; i < pts.size(); ++i) {
                        const auto at = ::testing::Message()
                                        << what << " N=" << N << " ray " << ray << " parity " << par << " point " << i;
                        ASSERT_EQ(int(got[i].side), int(want[i].side)) << at;
                        ASSERT_EQ(int(got[i].ray), int(want[i].ray)) << at;
                        ASSERT_EQ(got[i].winding, want[i].winding) << at;
                        ASSERT_EQ(got[i].crossings, want[i].crossings) << at;
                    }
                    if (N == 8 && threads == 1 && !par && o.ray == CountRay::shortest) result = got;
                }
                for (std::size_t i = 0; i < pts.size(); i += 53)
                    ASSERT_EQ(classify_point(wide, pts[i], o).crossings, want[i].crossings) << what << " single " << i;
            };
            run(b4);
            run(b8);
            run(b16);
        }
    }
    return result;
}

TEST(WideInside, SeparatedCubesOnAQuarterGrid) {
    // Unit cubes at (2i, 2j, 2k), i, j, k in 0..3.
    const Mesh unit = test::unit_cube();
    Mesh cubes;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 4; ++k) {
                const auto base = std::uint32_t(cubes.positions.size());
                for (const Vec3& v : unit.positions) cubes.positions.push_back(v + Vec3{2.0f * i, 2.0f * j, 2.0f * k});
                for (const Triangle& t : unit.triangles)
                    cubes.triangles.push_back({base + t[0], base + t[1], base + t[2]});
            }
    std::vector<Vec3> pts;
    std::vector<Side> hand;
    // Quarter steps over [-0.5, 8]: a point is on the surface when it is on a
    // cube's closed boundary, inside when strictly inside one.
    for (int i = -2; i <= 32; ++i)
        for (int j = -2; j <= 32; j += 3)
            for (int k = -2; k <= 32; ++k) {
                pts.push_back({0.25f * float(i), 0.25f * float(j), 0.25f * float(k)});
                auto cell = [](int q, bool& strict) {  // in [2c, 2c + 1] for some c in 0..3?
                    const int c = q >= 0 ? q / 8 : -1, r = q - 8 * c;
                    strict = r > 0 && r < 4;
                    return c >= 0 && c <= 3 && r >= 0 && r <= 4;
                };
                bool si, sj, sk;
                const bool in = cell(i, si) && cell(j, sj) && cell(k, sk);
                hand.push_back(!in ? Side::outside : (si && sj && sk) ? Side::inside : Side::surface);
            }
    const std::vector<PointSide> got = check(cubes, pts, "cubes");
    ASSERT_EQ(got.size(), pts.size());
    std::size_t inside = 0, surface = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        ASSERT_EQ(int(got[i].side), int(hand[i])) << "point " << i;
        inside += hand[i] == Side::inside;
        surface += hand[i] == Side::surface;
    }
    EXPECT_GT(inside, 500u);
    EXPECT_GT(surface, 500u);
}

TEST(WideInside, SphereVerticesAndEdgeMidpoints) {
    const Mesh sphere = workloads::icosphere(4);
    std::vector<Vec3> pts = workloads::random_points(sphere.bounds(), 3000, 5, 0.3f);
    for (std::size_t t = 0; t < sphere.size(); t += 7) {
        const Vec3 a = sphere.vertex(t, 0), b = sphere.vertex(t, 1);
        pts.push_back(a);
        pts.push_back({0.5f * (a.x + b.x), 0.5f * (a.y + b.y), 0.5f * (a.z + b.z)});
    }
    pts.push_back({std::numeric_limits<float>::quiet_NaN(), 0, 0});
    pts.push_back({0, 0, std::numeric_limits<float>::infinity()});
    const std::vector<PointSide> got = check(sphere, pts, "sphere");
    std::size_t inside = 0;
    for (const PointSide& s : got) inside += s.side == Side::inside;
    EXPECT_GT(inside, 500u);
    EXPECT_EQ(got[got.size() - 2].crossings, 0u);  // NaN: outside, no crossings
}

TEST(WideInside, SoupOfOverlappingTrianglesWithSharedBlocks) {
    const Mesh soup = workloads::random_soup(3000, 17);
    std::vector<Vec3> pts = workloads::random_points(soup.bounds(), 3000, 6, 0.1f);
    for (std::size_t t = 0; t < soup.size(); t += 5) pts.push_back(soup.vertex(t, 2));
    const std::vector<PointSide> got = check(soup, pts, "soup", /*expect_shared=*/true);
    std::uint32_t most = 0;
    for (const PointSide& s : got) most = std::max(most, s.crossings);
    EXPECT_GE(most, 3u) << "rays through several overlapping triangles";
    // An open mesh: the rays give different answers, so check() above shows
    // that every path picks the same ray.
    const Bvh8 bvh = Bvh8::build(soup);
    InsideOptions up, left;
    up.ray = CountRay::plus_z;
    left.ray = CountRay::minus_x;
    std::vector<PointSide> a(pts.size()), b(pts.size());
    classify_points(bvh, pts, a, up);
    classify_points(bvh, pts, b, left);
    std::size_t differ = 0, shortest_not_z = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        differ += a[i].side != b[i].side;
        shortest_not_z += got[i].ray != CountRay::plus_z;
    }
    EXPECT_GT(differ, 100u);
    EXPECT_GT(shortest_not_z, 1000u);
}

}  // namespace
}  // namespace simdbvh
