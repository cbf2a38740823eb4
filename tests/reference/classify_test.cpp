// Classification labels on constructed cases, Tally arithmetic, and
// compare_methods / compare_occluded bookkeeping.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "simdbvh/reference/classify.h"
#include "simdbvh/kernels/error.h"
#include "support/scene.h"

namespace simdbvh::reference {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

Ray ray(Vec3 o, Vec3 d, float tmin = 0.0f, float tmax = kInf) { return Ray{o, tmin, d, tmax}; }

// Triangle 0 at z = 0, triangle 1 the same at z = -1 (behind it), triangle 2 a duplicate of 0.
Mesh layered() {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}, {1, 0, -1}, {0, 1, -1}};
    m.triangles = {{0, 1, 2}, {3, 4, 5}, {0, 1, 2}};
    return m;
}

const Ray kDown = ray({0.25f, 0.25f, 5}, {0, 0, -1});  // hits 0 and 2 at t = 5, 1 at t = 6
const Ray kAway = ray({5, 5, 5}, {0, 0, -1});          // misses everything

TEST(Classify, ConstructedLabels) {
    const Mesh m = layered();
    const Reference ref = reference_intersect(m, kDown);
    ASSERT_EQ(ref.prim, 0u);
    ASSERT_EQ(ref.t, 5.0);
    ASSERT_EQ(ref.tie_set(), (std::vector<std::uint32_t>{0, 2}));

    const auto label = [&](const Hit& h) { return classify(ref, h).label; };
    EXPECT_EQ(label(Hit{5.0f, 0.25f, 0.25f, 0}), Label::agree);
    EXPECT_EQ(label(Hit{std::nextafter(5.0f, 6.0f), 0.25f, 0.25f, 0}), Label::agree);  // within tau
    EXPECT_EQ(label(Hit{5.0f, 0.25f, 0.25f, 2}), Label::tie);
    EXPECT_EQ(label(Hit{}), Label::leak);
    EXPECT_EQ(label(Hit{6.0f, 0.25f, 0.25f, 1}), Label::wrong_triangle);
    EXPECT_EQ(label(Hit{5.0f, 0.25f, 0.25f, 1}), Label::wrong_triangle);  // right t, triangle behind
    EXPECT_EQ(label(Hit{5.0f, 0.25f, 0.25f, 7}), Label::wrong_triangle);  // not a triangle at all
    EXPECT_EQ(label(Hit{5.01f, 0.25f, 0.25f, 0}), Label::t_error);
    EXPECT_EQ(label(Hit{4.99f, 0.25f, 0.25f, 2}), Label::t_error);

    const Reference miss = reference_intersect(m, kAway);
    EXPECT_EQ(classify(miss, Hit{}).label, Label::agree);
    EXPECT_EQ(classify(miss, Hit{5.0f, 0.25f, 0.25f, 0}).label, Label::false_hit);

    // Clear-cut cases are not marginal.
    EXPECT_FALSE(classify(ref, Hit{}).marginal);
    EXPECT_FALSE(classify(ref, Hit{6.0f, 0.25f, 0.25f, 1}).marginal);
    EXPECT_FALSE(classify(ref, Hit{5.01f, 0.25f, 0.25f, 0}).marginal);
    EXPECT_FALSE(classify(miss, Hit{5.0f, 0.25f, 0.25f, 0}).marginal);
}

TEST(Classify, InvalidRayMustMiss) {
    const Mesh m = layered();
    const Reference ref = reference_intersect(m, ray({0.25f, 0.25f, 5}, {0, 0, 0}));
    EXPECT_FALSE(ref.valid);
    EXPECT_EQ(classify(ref, Hit{}).label, Label::agree);
    EXPECT_EQ(classify(ref, Hit{5.0f, 0, 0, 0}).label, Label::false_hit);
    EXPECT_EQ(classify_occluded(ref, false).label, Label::agree);
    EXPECT_EQ(classify_occluded(ref, true).label, Label::false_hit);
}

TEST(Classify, GrazingAnEdgeIsMarginal) {
    const Mesh m = test::one_triangle();  // edge x = 0 from (0,0,0) to (0,1,0)
    // Just outside the edge (by far less than float rounding of the test): the
    // reference misses, yet a float method hitting it is within rounding.
    const Ray outside = ray({-1e-12f, 0.5f, 1}, {0, 0, -1});
    const Reference out = reference_intersect(m, outside);
    ASSERT_FALSE(out.hit());
    ASSERT_TRUE(out.near_hit());
    const Verdict fh = classify(out, Hit{1.0f, 0.5f, 0.0f, 0});
    EXPECT_EQ(fh.label, Label::false_hit);
    EXPECT_TRUE(fh.marginal);
    EXPECT_TRUE(classify_occluded(out, true).marginal);
    // Just inside: the reference hits, but not robustly; a miss is a marginal leak.
    const Ray inside = ray({1e-12f, 0.5f, 1}, {0, 0, -1});
    const Reference in = reference_intersect(m, inside);
    ASSERT_TRUE(in.hit());
    ASSERT_FALSE(in.robust_hit());
    const Verdict lk = classify(in, Hit{});
    EXPECT_EQ(lk.label, Label::leak);
    EXPECT_TRUE(lk.marginal);
    EXPECT_TRUE(classify_occluded(in, false).marginal);
    // A hit far from t is not made plausible by the edge.
    EXPECT_FALSE(classify(out, Hit{2.0f, 0.5f, 0.0f, 0}).marginal);
}

TEST(Classify, OccludedLabels) {
    const Mesh m = layered();
    const Reference hit = reference_intersect(m, kDown);
    const Reference miss = reference_intersect(m, kAway);
    EXPECT_EQ(classify_occluded(hit, true).label, Label::agree);
    EXPECT_EQ(classify_occluded(hit, false).label, Label::leak);
    EXPECT_FALSE(classify_occluded(hit, false).marginal);
    EXPECT_EQ(classify_occluded(miss, false).label, Label::agree);
    EXPECT_EQ(classify_occluded(miss, true).label, Label::false_hit);
    EXPECT_FALSE(classify_occluded(miss, true).marginal);
}

TEST(Tally, CountsAndRates) {
    Tally t;
    t.add({Label::agree, false});
    t.add({Label::agree, false});
    t.add({Label::tie, false});
    t.add({Label::leak, true});
    t.add({Label::false_hit, false});
    t.add({Label::wrong_triangle, false});
    t.add({Label::t_error, true});
    EXPECT_EQ(t.agreements(), 3u);
    EXPECT_EQ(t.disagreements(), 4u);
    EXPECT_EQ(t.marginal, 2u);
    EXPECT_EQ(t.hard_disagreements(), 2u);
    EXPECT_EQ(t.total(), 7u);
    EXPECT_DOUBLE_EQ(t.agreement_rate(), 3.0 / 7.0);
    Tally u = t;
    u.invalid_rays = 5;
    u += t;
    EXPECT_EQ(u.total(), 14u);
    EXPECT_EQ(u.leak, 2u);
    EXPECT_EQ(u.invalid_rays, 5u);
    EXPECT_EQ((t + t).tie, 2u);
    EXPECT_DOUBLE_EQ(Tally{}.agreement_rate(), 1.0);
    EXPECT_NE(to_string(t).find("wrong_triangle=1"), std::string::npos);
    EXPECT_EQ(name(Label::t_error), "t_error");
}

TEST(Compare, OnlyDifferingRaysGoToTheReference) {
    const Mesh m = layered();
    const std::vector<Ray> rays = {kDown, kDown, kDown, kAway, kDown, ray({0, 0, 0}, {0, 0, 0})};
    const Hit good{5.0f, 0.25f, 0.25f, 0};
    const std::vector<Hit> a = {good, good, good, Hit{}, Hit{5.0f, 0.25f, 0.25f, 2}, Hit{}};
    const std::vector<Hit> b = {good, Hit{}, Hit{6.0f, 0.25f, 0.25f, 1}, Hit{3.0f, 0, 0, 1}, good, Hit{}};
    const Comparison c = compare_methods(m, rays, a, b);
    EXPECT_EQ(c.reference_rays, 4u);  // rays 1, 2, 3, 4 (4: another triangle, a tie)
    ASSERT_EQ(c.disagreements.size(), 4u);
    EXPECT_EQ(c.disagreements[0].ray, 1u);
    EXPECT_EQ(c.disagreements[0].a.label, Label::agree);
    EXPECT_EQ(c.disagreements[0].b.label, Label::leak);
    EXPECT_EQ(c.disagreements[1].b.label, Label::wrong_triangle);
    EXPECT_EQ(c.disagreements[2].ray, 3u);
    EXPECT_EQ(c.disagreements[2].b.label, Label::false_hit);
    EXPECT_EQ(c.disagreements[2].t_ref, std::numeric_limits<double>::infinity());
    EXPECT_EQ(c.disagreements[3].a.label, Label::tie);
    EXPECT_EQ(c.disagreements[3].ref_prim, 0u);
    EXPECT_EQ(c.a.disagreements(), 0u);
    EXPECT_EQ(c.a.tie, 1u);
    EXPECT_EQ(c.b.leak, 1u);
    EXPECT_EQ(c.b.wrong_triangle, 1u);
    EXPECT_EQ(c.b.false_hit, 1u);
    EXPECT_EQ(c.a.total(), rays.size());
    EXPECT_EQ(c.a.invalid_rays, 1u);

    // reference_all also checks the rays on which both agree.
    const std::vector<Hit> wrong_both = {Hit{6.0f, 0, 0, 1}};
    const Comparison all =
        compare_methods(m, std::span(rays).first(1), wrong_both, wrong_both, {.reference_all = true});
    EXPECT_EQ(all.reference_rays, 1u);
    EXPECT_EQ(all.a.wrong_triangle, 1u);
    EXPECT_EQ(all.disagreements.size(), 1u);
    EXPECT_EQ(compare_methods(m, std::span(rays).first(1), wrong_both, wrong_both).a.agree, 1u);

    EXPECT_THROW(compare_methods(m, rays, a, std::span(b).first(2)), Error);
}

TEST(Compare, Differ) {
    const Ray r = kDown;
    EXPECT_FALSE(differ(r, Hit{}, Hit{}));
    EXPECT_TRUE(differ(r, Hit{}, Hit{5, 0, 0, 0}));
    EXPECT_TRUE(differ(r, Hit{5, 0, 0, 2}, Hit{5, 0, 0, 0}));
    EXPECT_FALSE(differ(r, Hit{5, 0, 0, 0}, Hit{std::nextafter(5.0f, 6.0f), 0.1f, 0, 0}));
    EXPECT_TRUE(differ(r, Hit{5, 0, 0, 0}, Hit{5.01f, 0, 0, 0}));
}

TEST(Compare, Occluded) {
    const Mesh m = layered();
    const std::vector<Ray> rays = {kDown, kDown, kAway, kAway};
    const std::vector<std::uint8_t> a = {1, 1, 0, 0};
    const std::vector<std::uint8_t> b = {1, 0, 0, 1};
    const Comparison c = compare_occluded(m, rays, a, b);
    EXPECT_EQ(c.reference_rays, 2u);
    EXPECT_EQ(c.a.disagreements(), 0u);
    EXPECT_EQ(c.b.leak, 1u);
    EXPECT_EQ(c.b.false_hit, 1u);
    EXPECT_EQ(occluded_flags(std::vector<Hit>{Hit{}, Hit{1, 0, 0, 3}}), (std::vector<std::uint8_t>{0, 1}));
}

}  // namespace
}  // namespace simdbvh::reference
