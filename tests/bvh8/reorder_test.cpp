// The sorted batches of the wide trees (TraceOptions::reorder,
// bvh8/internal/simdbvh/bvh8/internal/ray_order.h): traced sorted, unsorted or as chosen, every width,
// ISA and thread count gives the BVH2's closest hits bit for bit at the
// caller's positions, any hits without streams are the caller's-order ones,
// and with streams a hit where the ray hits something; the sort is a stable
// permutation by key; the automatic choice sorts surface bounces and keeps a
// camera's rays and rays from outside or filling the bounds, and
// traces_sorted (batch_order.h) tells a caller that choice.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "simdbvh/bvh8/internal/ray_order.h"
#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/batch_order.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"
#include "wide_trace_checks.h"

namespace simdbvh {
namespace {

using bvh8::detail::kReorderSegment;

// Diffuse bounces off the mesh, then rays no traversal takes (a NaN origin, a
// zero direction, outside the bounds) and rays with a negative tmin or a
// finite tmax, spread through the batch.
std::vector<Ray> bounce_rays(const Mesh& mesh, std::size_t count) {
    std::vector<Ray> rays = workloads::generate_rays(mesh, workloads::RayKind::diffuse, count, 7);
    const Aabb b = mesh.bounds();
    const float e = b.extent().x;
    for (std::size_t i = 0; i < rays.size(); i += 97) {
        switch (i / 97 % 5) {
        case 0: rays[i].org.y = std::numeric_limits<float>::quiet_NaN(); break;
        case 1: rays[i].dir = Vec3{0, 0, 0}; break;
        case 2: rays[i].org.x = b.hi.x + 3 * e; break;
        case 3: rays[i].tmin = -0.25f * e; break;
        case 4: rays[i].tmax = 0.1f * e; break;
        }
    }
    return rays;
}

// Eight spheres on the corners of a cube: bounces off one hit the others, and
// the origins lie on surfaces (the automatic choice sorts them).
Mesh spheres() {
    Mesh m;
    for (int c = 0; c < 8; ++c) {
        const Mesh s = workloads::icosphere(3, 0.8f, Vec3{float(c & 1) * 2, float(c >> 1 & 1) * 2, float(c >> 2) * 2});
        const auto base = std::uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), s.positions.begin(), s.positions.end());
        for (const Triangle& t : s.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    return m;
}

template <int N>
void check_width(const Bvh2& bvh2, const std::vector<Ray>& rays, const std::vector<Hit>& want, Isa isa,
                 const std::string& what) {
    const BvhN<N> bvh = BvhN<N>::build(bvh2);
    TraceOptions base;
    base.packets = Packets::off;
    base.reorder = Reorder::off;
    std::vector<Hit> any_caller(rays.size());
    occluded(bvh, rays, any_caller, with_isa(base, isa));
    for (Reorder r : {Reorder::on, Reorder::automatic, Reorder::off})
        for (Packets p : {Packets::off, Packets::automatic})
            for (int threads : {1, 2}) {
                const std::string how = what + " bvh" + std::to_string(N) + " " + std::string(name(isa)) + " reorder " +
                                        std::to_string(int(r)) + " packets " + std::to_string(int(p)) + " threads " +
                                        std::to_string(threads);
                TraceOptions o;
                o.reorder = r;
                o.packets = p;
                o.threads = threads;
                std::vector<Hit> any;
                test::wide::expect_hits(bvh, rays, want, o, isa, how, any);
                if (testing::Test::HasFatalFailure()) return;
                if (p != Packets::off) continue;
                for (std::size_t i = 0; i < rays.size(); ++i)
                    ASSERT_EQ(any[i], any_caller[i]) << how << " any, ray " << i;
            }
}

class ReorderHits : public testing::TestWithParam<Isa> {};

TEST_P(ReorderHits, SameHitsInEveryOrder) {
    const Isa isa = GetParam();
    if (!supported(isa)) GTEST_SKIP() << "CPU lacks " << name(isa);
    // Surfaces (the automatic choice sorts their bounces) and a soup.
    for (const Mesh& mesh : {spheres(), workloads::random_soup(30000, 3)}) {
        const Bvh2 bvh2 = Bvh2::build(mesh);
        // Past kReorderMinRays and kReorderBlock: a full sorted block and a part.
        const std::vector<Ray> rays = bounce_rays(mesh, 20000);
        std::vector<Hit> want(rays.size());
        intersect(bvh2, rays, want, {});
        std::size_t hits = 0;
        for (const Hit& h : want) hits += h.hit();
        ASSERT_GT(hits, rays.size() / 20);
        const std::string what = std::to_string(mesh.triangles.size()) + " triangles";
        check_width<4>(bvh2, rays, want, isa, what);
        check_width<8>(bvh2, rays, want, isa, what);
        check_width<16>(bvh2, rays, want, isa, what);
    }
}

INSTANTIATE_TEST_SUITE_P(Isas, ReorderHits, testing::ValuesIn(kAllIsas),
                         [](const testing::TestParamInfo<Isa>& i) { return std::string(name(i.param)); });

// A batch of more than one segment: each sorted on its own, the hits at the caller's positions.
TEST(ReorderHits, BatchOfSeveralSegments) {
    const Mesh mesh = workloads::icosphere(2);
    const Bvh8 bvh = Bvh8::build(mesh);
    const std::vector<Ray> rays = workloads::incoherent_rays(mesh.bounds(), kReorderSegment + 5003, 11);
    TraceOptions off, on;
    off.reorder = Reorder::off;
    on.reorder = Reorder::on;
    std::vector<Hit> want(rays.size()), got(rays.size());
    intersect(bvh, rays, want, off);
    intersect(bvh, rays, got, on);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(got[i], want[i]) << "ray " << i;
        hits += want[i].hit();
    }
    EXPECT_GT(hits, rays.size() / 10);
}

TEST(RayOrder, KeysOfTheCorners) {
    const Aabb b{{-1, -2, -3}, {1, 2, 3}};
    Ray r;
    r.org = b.lo;
    r.dir = Vec3{1, 1, 1};
    EXPECT_EQ(bvh8::detail::ray_key(r, b), 0u);
    r.org = b.hi;  // the last cell, every sign negative: every bit of the 21
    r.dir = Vec3{-1, -0.0f, -1};
    EXPECT_EQ(bvh8::detail::ray_key(r, b), (1u << 21) - 1);
    r.org = Vec3{10, 20, 30};  // outside: clamped to the last cell
    EXPECT_EQ(bvh8::detail::ray_key(r, b) >> 12, 511u);
    r.org = Vec3{std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::infinity(), -100};
    r.dir = Vec3{1, 1, 1};
    EXPECT_EQ(bvh8::detail::ray_key(r, b), 0u);
    // The 8^3 cell leads: x in the upper half sets the cell code's bit 6 (x, y, z interleaved from bit 0).
    r.org = Vec3{0.01f, -2, -3};
    EXPECT_EQ(bvh8::detail::ray_key(r, b), 1u << (12 + 6));
    // then the octant, then the fine cell.
    r.org = b.lo;
    r.dir = Vec3{1, -1, 1};
    EXPECT_EQ(bvh8::detail::ray_key(r, b), 2u << 9);
}

TEST(RayOrder, StablePermutationByKey) {
    const Mesh mesh = workloads::icosphere(3);
    std::vector<Ray> rays = workloads::generate_rays(mesh, workloads::RayKind::diffuse, 30000, 5);
    const std::vector<Ray> far = workloads::incoherent_rays(mesh.bounds(), 3000, 6);  // from outside the bounds
    rays.insert(rays.begin() + 1000, far.begin(), far.end());
    for (std::size_t i = 0; i < rays.size(); i += 5) rays[i] = rays[i / 5];  // equal keys far apart
    rays[3].org.x = std::numeric_limits<float>::quiet_NaN();
    std::vector<std::uint64_t> order, work;
    bvh8::detail::sort_rays(rays, mesh.bounds(), order, work);
    ASSERT_EQ(order.size(), rays.size());
    std::vector<bool> seen(rays.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        const std::uint32_t at = bvh8::detail::order_index(order[i]);
        ASSERT_LT(at, rays.size());
        ASSERT_FALSE(seen[at]) << "position " << at << " twice";
        seen[at] = true;
        if (i == 0) continue;
        const std::uint32_t prev = bvh8::detail::order_index(order[i - 1]);
        const std::uint32_t k0 = bvh8::detail::ray_key(rays[prev], mesh.bounds());
        const std::uint32_t k1 = bvh8::detail::ray_key(rays[at], mesh.bounds());
        ASSERT_LE(k0, k1) << "at " << i;
        if (k0 == k1) {
            ASSERT_LT(prev, at) << "equal keys out of the caller's order at " << i;
        }
    }
}

TEST(RayOrder, AutomaticSortsSurfaceBouncesOnly) {
    const Mesh mesh = spheres();
    const Aabb b = mesh.bounds();
    const std::vector<Ray> bounces = workloads::generate_rays(mesh, workloads::RayKind::diffuse, 150000, 1);
    EXPECT_TRUE(bvh8::detail::scattered(bounces, b));
    // Every 8th of them (18,750: the same cells, fewer rays): too few per cell their origins occupy.
    std::vector<Ray> sparse;
    for (std::size_t i = 0; i < bounces.size(); i += 8) sparse.push_back(bounces[i]);
    EXPECT_FALSE(bvh8::detail::scattered(sparse, b));
    EXPECT_FALSE(bvh8::detail::scattered(workloads::generate_rays(mesh, workloads::RayKind::primary, 40000, 1), b));
    EXPECT_FALSE(bvh8::detail::scattered(workloads::incoherent_rays(b, 40000, 1), b));  // from outside
    EXPECT_FALSE(bvh8::detail::scattered(workloads::interior_rays(b, 40000, 1), b));    // filling the bounds
}

// Rays in an order that keeps neighbours together are sorted all the same when their origins spread over many
// cells (shadow rays from the primary hits in pixel order), and kept when they share an origin (a LiDAR inside
// the bounds).
TEST(RayOrder, AutomaticSortsShadowRaysAndKeepsASharedOrigin) {
    const Mesh mesh = spheres();
    const Aabb b = mesh.bounds();
    for (auto kind : {workloads::RayKind::shadow, workloads::RayKind::area_shadow}) {
        const std::vector<Ray> shadow = workloads::generate_rays(mesh, kind, 150000, 1);
        // In pixel order, most neighbours share cell and octant: the first test alone would keep them.
        std::size_t same = 0;
        for (std::size_t i = 0; i + 1 < shadow.size(); i += 97)
            same += (bvh8::detail::ray_key(shadow[i], b) >> bvh8::detail::kFineBits) ==
                    (bvh8::detail::ray_key(shadow[i + 1], b) >> bvh8::detail::kFineBits);
        if (kind == workloads::RayKind::shadow)  // (toward an area light the octant changes more often)
            EXPECT_GT(4 * same, 3 * ((shadow.size() - 1 + 96) / 97));
        EXPECT_TRUE(bvh8::detail::scattered(shadow, b)) << workloads::name(kind);
    }
    EXPECT_FALSE(bvh8::detail::scattered(workloads::lidar_rays(b, 150000), b));
}

// The public question (batch_order.h), on Ray records and on a function of
// the position, answers as the traversal decides: the rule for automatic,
// yes for on (more than one ray), no for off.
TEST(RayOrder, TracesSortedTellsTheTraversalsChoice) {
    const Mesh mesh = spheres();
    const Bvh16 bvh = Bvh16::build(mesh);
    const std::vector<Ray> bounces = workloads::generate_rays(mesh, workloads::RayKind::diffuse, 150000, 1);
    const std::vector<Ray> camera = workloads::generate_rays(mesh, workloads::RayKind::primary, 40000, 1);
    auto asked = [&](const std::vector<Ray>& rays, Reorder r) {
        TraceOptions o;
        o.reorder = r;
        const bool records = traces_sorted(bvh, rays, o);
        const bool by_position = traces_sorted(
            bvh, rays.size(), [&](std::size_t i) { return rays[i]; }, o);
        EXPECT_EQ(records, by_position);
        return records;
    };
    EXPECT_TRUE(asked(bounces, Reorder::automatic));
    EXPECT_FALSE(asked(camera, Reorder::automatic));
    EXPECT_FALSE(asked(bounces, Reorder::off));
    EXPECT_TRUE(asked(camera, Reorder::on));
    EXPECT_FALSE(asked(std::vector<Ray>(camera.begin(), camera.begin() + 1), Reorder::on));
    // Below the automatic rule's ray count, even surface bounces are not sorted.
    EXPECT_FALSE(asked(std::vector<Ray>(bounces.begin(), bounces.begin() + 8000), Reorder::automatic));
}

}  // namespace
}  // namespace simdbvh
