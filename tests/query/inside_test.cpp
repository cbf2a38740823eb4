// Exact inside/outside: the predicates against 128-bit integer
// arithmetic, mesh closure, and points whose +z rays run exactly through
// vertices, along edges and along the diagonals of a cube and an octahedron,
// against answers derived by hand (docs/exact_crossings.md).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "simdbvh/query/internal/exact_predicates.h"
#include "simdbvh/query/inside.h"
#include "simdbvh/workloads/scenes.h"
#include "support/scene.h"

namespace simdbvh {
namespace {

using i128 = __int128;

// Coordinates k / 1024 with |k| < 2^20: integers after scaling by 1024.
i128 fixed(float v) { return i128(std::llround(double(v) * 1024.0)); }
int sign128(i128 v) { return (v > 0) - (v < 0); }

int ref_orient2d(const Vec3& a, const Vec3& b, const Vec3& p) {
    return sign128((fixed(b.x) - fixed(a.x)) * (fixed(p.y) - fixed(a.y)) -
                   (fixed(b.y) - fixed(a.y)) * (fixed(p.x) - fixed(a.x)));
}
int ref_plane_side(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
    const i128 bx = fixed(b.x) - fixed(a.x), by = fixed(b.y) - fixed(a.y), bz = fixed(b.z) - fixed(a.z);
    const i128 cx = fixed(c.x) - fixed(a.x), cy = fixed(c.y) - fixed(a.y), cz = fixed(c.z) - fixed(a.z);
    const i128 px = fixed(p.x) - fixed(a.x), py = fixed(p.y) - fixed(a.y), pz = fixed(p.z) - fixed(a.z);
    return sign128((by * cz - bz * cy) * px + (bz * cx - bx * cz) * py + (bx * cy - by * cx) * pz);
}

TEST(ExactPredicates, AgreeWithIntegerArithmeticOnNearDegenerateInputs) {
    std::mt19937 rng(1);
    std::uniform_int_distribution<int> coord(-(1 << 19), (1 << 19) - 1), small(-3, 3), nudge(-1, 1);
    auto f = [](int k) { return float(k) / 1024.0f; };
    std::size_t zero2 = 0, zero3 = 0;
    for (int i = 0; i < 200000; ++i) {
        // a, b, c random; p on the line a b (or the plane a b c) up to a nudge of one unit.
        const int ax = coord(rng) >> 4, ay = coord(rng) >> 4, az = coord(rng) >> 4;
        const int dx = coord(rng) >> 8, dy = coord(rng) >> 8, dz = coord(rng) >> 8;
        const int ex = coord(rng) >> 8, ey = coord(rng) >> 8, ez = coord(rng) >> 8;
        const int s = small(rng), t = small(rng);
        const Vec3 a{f(ax), f(ay), f(az)}, b{f(ax + dx), f(ay + dy), f(az + dz)}, c{f(ax + ex), f(ay + ey), f(az + ez)};
        const Vec3 p2{f(ax + s * dx + nudge(rng)), f(ay + s * dy + nudge(rng)), 0.0f};
        const Vec3 p3{f(ax + s * dx + t * ex + nudge(rng)), f(ay + s * dy + t * ey + nudge(rng)),
                      f(az + s * dz + t * ez + nudge(rng))};
        const int want2 = ref_orient2d(a, b, p2), want3 = ref_plane_side(a, b, c, p3);
        ASSERT_EQ(query::exact::orient2d(a, b, p2), want2) << i;
        ASSERT_EQ(query::exact::plane_side(a, b, c, p3), want3) << i;
        zero2 += want2 == 0;
        zero3 += want3 == 0;
        if (want2 == 0 && (a.x != b.x || a.y != b.y)) {
            ASSERT_NE(query::exact::orient2d_perturbed(a, b, p2), 0);
        }
        EXPECT_EQ(query::exact::orient2d_perturbed(a, b, p2), -query::exact::orient2d_perturbed(b, a, p2)) << i;
    }
    EXPECT_GT(zero2, 10000u) << "the exact path must be exercised";
    EXPECT_GT(zero3, 5000u);
}

TEST(ExactPredicates, LargeAndTinyMagnitudes) {
    // Collinear along y = x at wildly different magnitudes.
    const float big = 1e30f, tiny = 1e-30f;
    EXPECT_EQ(query::exact::orient2d({tiny, tiny, 0}, {big, big, 0}, {2 * big, 2 * big, 0}), 0);
    EXPECT_EQ(query::exact::orient2d({tiny, tiny, 0}, {big, big, 0}, {2 * big, std::nextafter(2 * big, 3 * big), 0}),
              1);
    EXPECT_EQ(query::exact::orient2d({tiny, tiny, 0}, {big, big, 0}, {std::nextafter(2 * big, 3 * big), 2 * big, 0}),
              -1);
    // A point one ulp above the plane z = 2^20 + 0.25.
    const float z = 1048576.25f;
    const Vec3 a{0, 0, z}, b{1, 0, z}, c{0, 1, z};
    EXPECT_EQ(query::exact::plane_side(a, b, c, {0.3f, 0.3f, z}), 0);
    EXPECT_EQ(query::exact::plane_side(a, b, c, {0.3f, 0.3f, std::nextafter(z, 2 * z)}), 1);
    EXPECT_EQ(query::exact::plane_side(a, b, c, {0.3f, 0.3f, std::nextafter(z, 0.0f)}), -1);
}

TEST(MeshClosure, ClosedOpenFlippedAndUnwelded) {
    const Mesh cube = test::unit_cube();
    const MeshClosure c = mesh_closure(cube);
    EXPECT_EQ(c.edges, 18u);
    EXPECT_TRUE(c.closed());
    EXPECT_TRUE(c.consistently_oriented());
    Mesh open = cube;
    open.triangles.pop_back();
    EXPECT_EQ(mesh_closure(open).boundary_edges, 3u);
    EXPECT_FALSE(mesh_closure(open).closed());
    Mesh flipped = cube;
    std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
    EXPECT_TRUE(mesh_closure(flipped).closed());
    EXPECT_EQ(mesh_closure(flipped).misoriented_edges, 3u);
    Mesh soup;  // every triangle with its own three vertices: closed after welding
    for (const Triangle& t : cube.triangles) {
        const auto i = std::uint32_t(soup.positions.size());
        for (int k = 0; k < 3; ++k) soup.positions.push_back(cube.positions[t[k]]);
        soup.triangles.push_back({i, i + 1, i + 2});
    }
    EXPECT_TRUE(mesh_closure(soup).consistently_oriented());
    EXPECT_TRUE(mesh_closure(workloads::icosphere(3)).consistently_oriented());
}

// The cube [o, o+1]^3 on a grid of quarter steps: the axis rays from these
// points pass exactly through the cube's vertices, along its edges and faces
// and along the diagonals that split its faces. Points on the closed box's
// boundary are on the surface; strictly inside, one crossing; before the cube
// along the ray, two crossings when the perturbed point p + (eps, eps^2) of the
// ray's frame projects into the square: with (u', v') the frame's first two
// coordinates ((u, v) up, (v, u) down, never negated), when 0 <= u' - o < 1 and
// 0 <= v' - o < 1. `ray` fixed: that ray for every point; shortest: the ray
// toward the nearest face of the cube, the first of +z, -z, +x, -x, +y, -y.
void check_cube_grid(float o, CountRay ray) {
    Mesh cube = test::unit_cube();
    for (Vec3& v : cube.positions) v = v + Vec3{o, o, o};
    const Bvh2 bvh = Bvh2::build(cube);
    InsideOptions opts;
    opts.ray = ray;
    std::size_t n = 0, on_surface = 0, inside = 0;
    auto in = [](int v, int lo, int hi) { return v >= lo && v <= hi; };
    for (int i = -2; i <= 6; ++i)
        for (int j = -2; j <= 6; ++j)
            for (int k = -2; k <= 6; ++k) {
                const int idx[3] = {i, j, k};
                const Vec3 p{o + 0.25f * float(i), o + 0.25f * float(j), o + 0.25f * float(k)};
                CountRay r = ray;
                if (ray == CountRay::shortest) {  // nearest face; distances in quarter steps
                    const CountRay order[6] = {CountRay::plus_z,  CountRay::minus_z, CountRay::plus_x,
                                               CountRay::minus_x, CountRay::plus_y,  CountRay::minus_y};
                    int best = 1 << 30;
                    for (CountRay c : order) {
                        const int a = int(c) / 2, d = int(c) % 2 == 0 ? 4 - idx[a] : idx[a];
                        if (d < best) best = d, r = c;
                    }
                }
                const int w = int(r) / 2, u = (w + 1) % 3, v = (w + 2) % 3;
                const bool up = int(r) % 2 == 0;
                const int pu = up ? idx[u] : idx[v], pv = up ? idx[v] : idx[u];
                const bool in_proj = in(pu, 0, 3) && in(pv, 0, 3);
                const bool before = up ? idx[w] < 0 : idx[w] > 4;
                Side want = Side::outside;
                std::uint32_t crossings = 0;
                std::int32_t winding = 0;
                if (in(i, 0, 4) && in(j, 0, 4) && in(k, 0, 4) && !(in(i, 1, 3) && in(j, 1, 3) && in(k, 1, 3))) {
                    want = Side::surface;
                } else if (in(i, 1, 3) && in(j, 1, 3) && in(k, 1, 3)) {
                    want = Side::inside;
                    crossings = 1;
                    winding = 1;
                } else if (in_proj && before) {
                    crossings = 2;
                }
                const PointSide got = classify_point(bvh, p, opts);
                const PointSide brute = brute_force_classify_point(cube, p, opts);
                const auto at = ::testing::Message()
                                << o << " ray " << int(ray) << " grid " << i << " " << j << " " << k;
                ASSERT_EQ(int(got.side), int(want)) << at;
                ASSERT_EQ(int(brute.side), int(want)) << at;
                ASSERT_EQ(int(got.ray), int(r)) << at;
                ASSERT_EQ(int(brute.ray), int(r)) << at;
                if (want != Side::surface) {
                    ASSERT_EQ(got.crossings, crossings) << at;
                    ASSERT_EQ(got.winding, winding) << at;
                    ASSERT_EQ(brute.crossings, crossings) << at;
                    ASSERT_EQ(brute.winding, winding) << at;
                }
                ++n;
                on_surface += want == Side::surface;
                inside += want == Side::inside;
            }
    EXPECT_EQ(n, 729u);
    EXPECT_EQ(on_surface, 98u);
    EXPECT_EQ(inside, 27u);
}

TEST(Inside, CubeGridThroughVerticesEdgesAndDiagonals) {
    for (int r = 0; r <= int(CountRay::shortest); ++r) {
        check_cube_grid(0.0f, CountRay(r));
        check_cube_grid(1048576.0f, CountRay(r));  // 2^20: quarter steps still exact in float
        check_cube_grid(-3.0f, CountRay(r));
    }
}

// The octahedron |x| + |y| + |z| <= 1: every vertical ray through x = 0 or
// y = 0 runs along its edges, and those through (0, 0) through two vertices
// where four faces meet.
TEST(Inside, OctahedronGridOffTheSurface) {
    Mesh oct;
    oct.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    oct.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    ASSERT_TRUE(mesh_closure(oct).consistently_oriented());
    const Bvh2 bvh = Bvh2::build(oct);
    std::size_t n = 0;
    for (int i = -6; i <= 6; ++i)
        for (int j = -6; j <= 6; ++j)
            for (int k = -6; k <= 6; ++k) {
                const int l1 = std::abs(i) + std::abs(j) + std::abs(k);
                if (l1 == 4) continue;  // on the surface
                const Vec3 p{0.25f * float(i), 0.25f * float(j), 0.25f * float(k)};
                const PointSide got = classify_point(bvh, p);
                ASSERT_EQ(int(got.side), int(l1 < 4 ? Side::inside : Side::outside)) << i << " " << j << " " << k;
                ASSERT_EQ(got.winding, l1 < 4 ? 1 : 0) << i << " " << j << " " << k;
                ASSERT_EQ(got.crossings % 2u, l1 < 4 ? 1u : 0u) << i << " " << j << " " << k;
                ++n;
            }
    EXPECT_GT(n, 1500u);
    // Along the axis through both apexes, from below: in at one vertex, out at
    // the other. The shortest ray from there points away (-z): no crossing.
    InsideOptions plus_z;
    plus_z.ray = CountRay::plus_z;
    const PointSide below = classify_point(bvh, {0, 0, -2}, plus_z);
    EXPECT_EQ(below.crossings, 2u);
    EXPECT_EQ(below.winding, 0);
    EXPECT_EQ(below.ray, CountRay::plus_z);
    const PointSide away = classify_point(bvh, {0, 0, -2});
    EXPECT_EQ(away.crossings, 0u);
    EXPECT_EQ(away.ray, CountRay::minus_z);
    EXPECT_EQ(classify_point(bvh, {0, 0, 1}).side, Side::surface);
}

TEST(Inside, SphereBvhEqualsBruteForceAndTheGeometry) {
    const Mesh sphere = workloads::icosphere(3);
    const Bvh2 bvh = Bvh2::build(sphere);
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(-1.3f, 1.3f);
    std::vector<Vec3> pts(4000);
    for (Vec3& p : pts) p = {u(rng), u(rng), u(rng)};
    // Vertices of the mesh itself: on the surface.
    for (std::size_t v = 0; v < sphere.positions.size(); v += 10) pts.push_back(sphere.positions[v]);
    std::vector<PointSide> out(pts.size());
    InsideOptions two;
    two.threads = 2;
    classify_points(bvh, pts, out, two);
    std::size_t inside = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const PointSide b = brute_force_classify_point(sphere, pts[i]);
        ASSERT_EQ(int(out[i].side), int(b.side)) << i;
        ASSERT_EQ(out[i].winding, b.winding) << i;
        ASSERT_EQ(out[i].crossings, b.crossings) << i;
        ASSERT_TRUE(out[i].winding == 0 || out[i].winding == 1) << i;
        if (i >= 4000) {
            EXPECT_EQ(out[i].side, Side::surface) << "vertex " << i;
            continue;
        }
        const double r =
            std::sqrt(double(pts[i].x) * pts[i].x + double(pts[i].y) * pts[i].y + double(pts[i].z) * pts[i].z);
        if (r < 0.95) {
            EXPECT_EQ(out[i].side, Side::inside) << i;
        }
        if (r > 1.0001) {
            EXPECT_EQ(out[i].side, Side::outside) << i;
        }
        inside += out[i].side == Side::inside;
    }
    EXPECT_GT(inside, 500u);
    constexpr float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(classify_point(bvh, {nan, 0, 0}).side, Side::outside);
    EXPECT_EQ(classify_point(bvh, {nan, 0, 0}).crossings, 0u);
}

TEST(Inside, ParityRuleAndOverlappingParts) {
    // Two overlapping cubes: the overlap has winding 2 (inside by the winding
    // rule) and two crossings (outside by parity).
    Mesh two = test::unit_cube();
    const Mesh second = test::unit_cube();
    const auto base = std::uint32_t(two.positions.size());
    for (const Vec3& v : second.positions) two.positions.push_back(v + Vec3{0.5f, 0.5f, 0.5f});
    for (const Triangle& t : second.triangles) two.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    const Bvh2 bvh = Bvh2::build(two);
    const Vec3 overlap{0.75f, 0.7f, 0.8f};
    EXPECT_EQ(classify_point(bvh, overlap).winding, 2);
    EXPECT_EQ(classify_point(bvh, overlap).side, Side::inside);
    InsideOptions parity;
    parity.rule = InsideOptions::Rule::parity;
    EXPECT_EQ(classify_point(bvh, overlap, parity).side, Side::outside);
    EXPECT_EQ(classify_point(bvh, {0.25f, 0.3f, 0.2f}, parity).side, Side::inside);
}

}  // namespace
}  // namespace simdbvh
