// The double scene reference: known answers on a hand-made scene (an
// instanced sphere, a box, a plane, a rotated triangle mesh), agreement with
// our scene traversal on random rays (every disagreement of ours would be a
// bug or marginal), and every classification label from constructed answers.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "simdbvh/reference/scene_reference.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh {
namespace {

using reference::SceneLabel;
using reference::SceneReferencer;

// Instance 0: unit sphere scaled 2, at z = 5 (front at z = 3). Instance 1: box [-1,1]^2 x [7,8].
// Instance 2: an icosphere at x = 100 (off the z axis). Plane 0: z = 10.
SceneDesc hand_made() {
    SceneDesc d;
    d.geometries.push_back(SphereSet{{Sphere{{0, 0, 0}, 1.0f}}});
    d.geometries.push_back(BoxSet{{Aabb{{-1, -1, 7}, {1, 1, 8}}}});
    d.geometries.push_back(workloads::icosphere(2));
    d.instances.push_back({0, Affine3::translation({0, 0, 5}) * Affine3::scaling(2)});
    d.instances.push_back({1, Affine3{}});
    d.instances.push_back({2, Affine3::translation({100, 0, 0}) * Affine3::rotation({0, 1, 0}, 0.3)});
    d.planes.push_back({{0, 0, 10}, {0, 0, -1}});
    return d;
}

TEST(SceneReference, KnownAnswers) {
    const SceneDesc d = hand_made();
    const SceneReferencer ref(d);
    const Ray down_z{{0, 0, 0}, 0.0f, {0, 0, 1}, INFINITY};
    const reference::SceneReference r = ref.closest(down_z);
    ASSERT_TRUE(r.hit());
    EXPECT_EQ(r.inst, 0u);
    EXPECT_EQ(r.prim, 0u);
    EXPECT_NEAR(r.t, 3.0, 1e-12);
    EXPECT_TRUE(r.robust);
    // Past the sphere (tmin 7.5, inside the box): the box's exit at 8, then the plane at 10.
    const Ray inside_box{{0, 0, 0}, 7.5f, {0, 0, 1}, INFINITY};
    const reference::SceneReference rb = ref.closest(inside_box);
    EXPECT_EQ(rb.inst, 1u);
    EXPECT_NEAR(rb.t, 8.0, 1e-12);
    const Ray past{{0, 0, 0}, 4.25f, {0, 0, 2}, INFINITY};  // unnormalised (z = 2t, from z = 8.5): the plane at t = 5
    const reference::SceneReference rp = ref.closest(past);
    EXPECT_EQ(rp.inst, 3u);  // plane 0 follows the 3 instances
    EXPECT_EQ(rp.prim, 0u);
    EXPECT_NEAR(rp.t, 5.0, 1e-12);
    const Ray away{{0, 0, 0}, 0.0f, {0, 0, -1}, INFINITY};
    EXPECT_FALSE(ref.closest(away).hit());
    EXPECT_FALSE(ref.closest(Ray{{0, 0, 0}, 0.0f, {0, 0, 0}, INFINITY}).valid);
    // tmin a hair past the sphere's near root (t = 3, within the tolerance): the strict hit is the far root, t = 7.
    const Ray past_front{{0, 0, 0}, std::nextafter(3.0f, 4.0f), {0, 0, 1}, 3.5f};
    const Ray through{{0, 0, 0}, std::nextafter(3.0f, 4.0f), {0, 0, 1}, INFINITY};
    EXPECT_FALSE(ref.closest(past_front).hit());
    const reference::SceneReference rf = ref.closest(through);
    EXPECT_EQ(rf.inst, 0u);
    EXPECT_NEAR(rf.t, 7.0, 1e-12);
}

TEST(SceneReference, EveryLabel) {
    const SceneDesc d = hand_made();
    const SceneReferencer ref(d);
    const Ray ray{{0, 0, 0}, 0.0f, {0, 0, 1}, INFINITY};
    const reference::SceneReference r = ref.closest(ray);
    auto label = [&](const SceneHit& h) { return ref.classify(ray, r, h).label; };
    EXPECT_EQ(label(SceneHit{3.0f, 0, 0, 0, 0, 0}), SceneLabel::agree);
    EXPECT_EQ(label(SceneHit{3.5f, 0, 0, 0, 0, 0}), SceneLabel::t_error);
    EXPECT_EQ(label(SceneHit{}), SceneLabel::false_miss);
    EXPECT_EQ(label(SceneHit{7.0f, 0, 0, 0, 1, 1}), SceneLabel::farther_hit);             // the box, behind the sphere
    EXPECT_EQ(label(SceneHit{10.0f, 0, 0, 0, kNoGeometry, 3}), SceneLabel::farther_hit);  // the plane
    EXPECT_EQ(label(SceneHit{3.0f, 0, 0, 5, 2, 2}), SceneLabel::false_hit);               // the icosphere off the axis
    const Ray away{{0, 0, 0}, 0.0f, {0, 0, -1}, INFINITY};
    EXPECT_EQ(ref.classify(away, ref.closest(away), SceneHit{1.0f, 0, 0, 0, 0, 0}).label, SceneLabel::false_hit);
    EXPECT_EQ(ref.classify(away, ref.closest(away), SceneHit{}).label, SceneLabel::agree);
    // Two coincident spheres (instances 0 and 1 of one set): the other one is a tie.
    SceneDesc twins;
    twins.geometries.push_back(SphereSet{{Sphere{{0, 0, 5}, 1.0f}}});
    twins.instances.push_back({0, Affine3{}});
    twins.instances.push_back({0, Affine3{}});
    const SceneReferencer tr(twins);
    const reference::SceneReference rt = tr.closest(ray);
    EXPECT_EQ(rt.inst, 0u);
    EXPECT_EQ(tr.classify(ray, rt, SceneHit{4.0f, 0, 0, 0, 0, 1}).label, SceneLabel::tie);
}

// Our traversal against the reference on random rays through a mixed scene: no hard disagreement.
TEST(SceneReference, OursAgreesOnRandomRays) {
    SceneDesc d = hand_made();
    d.instances.push_back(
        {2, Affine3::translation({0, 3, 4}) * Affine3::rotation({1, 1, 0}, 0.7) * Affine3::scaling(1.5f)});
    const SceneReferencer ref(d);
    const SceneBvhN<8> s = SceneBvhN<8>::build(d);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Ray> rays;
    for (int i = 0; i < 1500; ++i) {
        const Vec3 o{6 * u(rng), 6 * u(rng), -4 + 2 * u(rng)};
        const Vec3 aim{3 * u(rng), 4 * u(rng), 4 + 4 * u(rng)};
        rays.push_back(Ray{o, 0.0f, aim - o, INFINITY});
    }
    std::vector<SceneHit> hits(rays.size());
    intersect(s, std::span<const Ray>(rays), std::span<SceneHit>(hits), {.isa = Isa::scalar});
    reference::SceneTally tally;
    std::size_t ref_hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const reference::SceneReference r = ref.closest(rays[i]);
        ref_hits += r.hit();
        const auto v = ref.classify(rays[i], r, hits[i]);
        tally.add(v);
        if (!v.marginal) {
            EXPECT_LT(int(v.label), int(SceneLabel::false_miss)) << "ray " << i << " " << name(v.label);
        }
    }
    EXPECT_GT(ref_hits, 400u);
    EXPECT_GE(tally.count[0], 1490u) << to_string(tally);
}

}  // namespace
}  // namespace simdbvh
