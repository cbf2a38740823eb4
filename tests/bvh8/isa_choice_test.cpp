// The wide traversal's ISA chosen by speed (bvh8.h, traversal_isa_choice):
// a batch below kIsaCalibrationRays does not calibrate; the first large batch
// calibrates its (width, query) slot only, picks a SIMD ISA the CPU has,
// reports a measured time per ISA, and its hits are bit-identical to every
// explicit path; a forced ISA is obeyed and never calibrated. ctest runs each
// test in its own process, so each starts with no choice made.
#include <gtest/gtest.h>

#include <cstring>

#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/scene/rays.h"
#include "simdbvh/scene/scenes.h"

namespace simdbvh {
namespace {

int simd_isas() {
    int n = 0;
    for (Isa isa : supported_isas()) n += isa != Isa::scalar;
    return n;
}

bool same_bits(const Hit& a, const Hit& b) {
    return a.prim == b.prim && std::memcmp(&a.t, &b.t, 4) == 0 && std::memcmp(&a.u, &b.u, 4) == 0 &&
           std::memcmp(&a.v, &b.v, 4) == 0;
}

struct Sphere5 {
    Mesh mesh = scene::icosphere(5);
    Bvh8 bvh = Bvh8::build(mesh);
    std::vector<Ray> rays = scene::generate_rays(mesh, scene::RayKind::incoherent, 20000, /*seed=*/5);
};

void expect_same_as_every_isa(const Sphere5& s, const std::vector<Hit>& got) {
    for (Isa isa : supported_isas()) {
        std::vector<Hit> want(s.rays.size());
        intersect(s.bvh, s.rays, want, {}, isa);
        std::size_t hits = 0;
        for (std::size_t i = 0; i < want.size(); ++i) {
            ASSERT_TRUE(same_bits(got[i], want[i])) << "ray " << i << " vs " << name(isa);
            hits += want[i].hit();
        }
        EXPECT_GT(hits, want.size() / 10);  // the rays do reach the mesh
    }
}

TEST(IsaChoice, FirstLargeBatchCalibratesItsSlotOnly) {
    if (forced_isa()) GTEST_SKIP() << "SIMDBVH_ISA forces an ISA";
    if (simd_isas() < 2) GTEST_SKIP() << "this CPU has fewer than two SIMD ISAs: nothing to choose";
    const Sphere5 s;
    EXPECT_FALSE(traversal_isa_choice(8, false).calibrated);
    EXPECT_EQ(traversal_isa_choice(8, false).isa, detected_isa());

    std::vector<Hit> small(kIsaCalibrationRays - 1);
    intersect(s.bvh, std::span<const Ray>(s.rays).first(small.size()), small);
    EXPECT_FALSE(traversal_isa_choice(8, false).calibrated) << "a small batch must not calibrate";

    std::vector<Hit> hits(s.rays.size());
    intersect(s.bvh, s.rays, hits);
    const TraversalIsaChoice c = traversal_isa_choice(8, false);
    EXPECT_TRUE(c.calibrated);
    EXPECT_FALSE(c.forced);
    EXPECT_NE(c.isa, Isa::scalar);
    EXPECT_TRUE(supported(c.isa));
    EXPECT_GT(c.rays_timed, 0u);
    for (Isa isa : supported_isas()) {
        if (isa != Isa::scalar) {
            EXPECT_GT(c.ns_per_ray[int(isa)], 0.0) << name(isa);
        }
    }
    EXPECT_EQ(c.ns_per_ray[int(Isa::scalar)], 0.0);
    EXPECT_FALSE(traversal_isa_choice(8, true).calibrated) << "any hit has its own slot";
    EXPECT_FALSE(traversal_isa_choice(4, false).calibrated) << "each width has its own slot";
    expect_same_as_every_isa(s, hits);

    std::vector<Hit> again(s.rays.size());  // after the choice: the chosen path, same hits
    TraceOptions two;
    two.threads = 2;
    intersect(s.bvh, s.rays, again, two);
    expect_same_as_every_isa(s, again);
}

// A batch traced sorted (TraceOptions::reorder) that calibrates is traced whole
// after the calibration's chunks, the calibration's rays again: every ray's
// hit is every explicit path's.
TEST(IsaChoice, FirstLargeSortedBatchCalibratesAndTracesEveryRay) {
    if (forced_isa()) GTEST_SKIP() << "SIMDBVH_ISA forces an ISA";
    if (simd_isas() < 2) GTEST_SKIP() << "this CPU has fewer than two SIMD ISAs: nothing to choose";
    const Sphere5 s;
    TraceOptions sorted;
    sorted.reorder = Reorder::on;
    std::vector<Hit> hits(s.rays.size(), Hit{.t = -1.0f, .u = -1.0f, .v = -1.0f, .prim = 7});  // not a result
    intersect(s.bvh, s.rays, hits, sorted);
    EXPECT_TRUE(traversal_isa_choice(8, false).calibrated);
    expect_same_as_every_isa(s, hits);
}

TEST(IsaChoice, ForcedIsaIsObeyedAndNeverCalibrated) {
    set_active_isa(Isa::scalar);
    const Sphere5 s;
    std::vector<Hit> hits(s.rays.size());
    occluded(s.bvh, s.rays, hits);
    const TraversalIsaChoice c = traversal_isa_choice(8, true);
    EXPECT_TRUE(c.forced);
    EXPECT_FALSE(c.calibrated);
    EXPECT_EQ(c.isa, Isa::scalar);
    std::vector<Hit> want(s.rays.size());
    occluded(s.bvh, s.rays, want, {}, Isa::scalar);
    for (std::size_t i = 0; i < want.size(); ++i) ASSERT_TRUE(same_bits(hits[i], want[i])) << "ray " << i;
}

TEST(IsaChoice, OnlyTheBuiltWidthsAreReported) {
    EXPECT_THROW(traversal_isa_choice(2, false), Error);
    EXPECT_THROW(traversal_isa_choice(32, true), Error);
    EXPECT_NO_THROW(traversal_isa_choice(16, true));
}

}  // namespace
}  // namespace simdbvh
