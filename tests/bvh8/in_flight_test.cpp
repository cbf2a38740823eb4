// Rays in flight (TraceOptions::in_flight, bvh8/internal/simdbvh/bvh8/internal/traverse.h): one ray at a
// time or eight interleaved, chosen by the tree's size or forced, give the
// same hits at every width and ISA; anything but 0, 1 or 8 is an error.
#include <gtest/gtest.h>

#include <string>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"
#include "simdbvh/bvh8/internal/traverse.h"

namespace simdbvh {
namespace {

using workloads::RayKind;

TEST(InFlight, ChosenByTreeSize) {
    using bvh8::detail::kInCacheBytes;
    using bvh8::detail::one_in_flight;
    EXPECT_TRUE(one_in_flight(0, 0));
    EXPECT_TRUE(one_in_flight(kInCacheBytes, 0));
    EXPECT_FALSE(one_in_flight(kInCacheBytes + 1, 0));
    EXPECT_TRUE(one_in_flight(kInCacheBytes + 1, 1));
    EXPECT_FALSE(one_in_flight(0, bvh8::detail::kInFlight));
}

template <int N>
void check_width(const Bvh2& bvh2, const std::vector<Ray>& rays, const std::vector<Hit>& want, Isa isa,
                 const std::string& what) {
    const BvhN<N> bvh = BvhN<N>::build(bvh2);
    for (int flight : {0, 1, 8}) {
        TraceOptions o;
        o.in_flight = flight;
        std::vector<Hit> got(rays.size()), any(rays.size());
        intersect(bvh, rays, got, with_isa(o, isa));
        occluded(bvh, rays, any, with_isa(o, isa));
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(got[i], want[i]) << what << " bvh" << N << " " << name(isa) << " in_flight " << flight << " ray "
                                       << i;
            ASSERT_EQ(any[i].hit(), want[i].hit()) << what << " bvh" << N << " any, in_flight " << flight;
        }
    }
    for (int bad : {-1, 2, 16}) {
        TraceOptions o;
        o.in_flight = bad;
        std::vector<Hit> got(rays.size());
        EXPECT_THROW(intersect(bvh, rays, got, with_isa(o, isa)), Error) << bad;
    }
}

class InFlightHits : public testing::TestWithParam<Isa> {};

// A small soup (its trees are traced one ray at a time unless forced) and one
// whose trees pass 4 MiB (eight in flight unless forced): the BVH2's hits
// (bit-identical to brute force, bvh8_vs_bvh2_test) every way.
TEST_P(InFlightHits, SameHitsEveryWay) {
    const Isa isa = GetParam();
    if (!supported(isa)) GTEST_SKIP() << "CPU lacks " << name(isa);
    for (std::size_t tris : {2000u, 100000u}) {
        const Mesh mesh = workloads::random_soup(tris, 9);
        const Bvh2 bvh2 = Bvh2::build(mesh);
        for (RayKind kind : {RayKind::primary, RayKind::incoherent}) {
            const auto rays = workloads::generate_rays(mesh, kind, 1500, 3);
            std::vector<Hit> want(rays.size());
            intersect(bvh2, rays, want, {});
            const std::string what = "soup-" + std::to_string(tris);
            check_width<4>(bvh2, rays, want, isa, what);
            check_width<8>(bvh2, rays, want, isa, what);
            check_width<16>(bvh2, rays, want, isa, what);
        }
        if (tris == 100000u) {
            const BvhN<8> b8 = BvhN<8>::build(bvh2);
            EXPECT_GT(b8.nodes().size() * sizeof(NodeN<8>) + b8.blocks().size() * sizeof(Tri8),
                      bvh8::detail::kInCacheBytes);
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Isas, InFlightHits, testing::ValuesIn(kAllIsas),
                         [](const testing::TestParamInfo<Isa>& i) { return std::string(name(i.param)); });

}  // namespace
}  // namespace simdbvh
