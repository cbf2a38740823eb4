// The validated path (watertight triangle test + conservative box test) on every
// ray family (docs/accuracy.md): no leak, false hit or wrong triangle against the
// double reference, every case of every family (each offset is a case), and
// BVH2, BVH2 with stats and BVH8 on every supported ISA bit-identical.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <algorithm>
#include <map>

#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/reference/classify.h"
#include "simdbvh/reference/reference.h"
#include "simdbvh/platform/parallel.h"
#include "simdbvh/workloads/families.h"

namespace simdbvh {
namespace {

using workloads::Expect;
using workloads::Family;

std::vector<reference::Reference> references(const workloads::FamilyCase& c) {
    std::vector<reference::Reference> refs(c.rays.size());
    parallel_for(c.rays.size(), 2, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) refs[i] = reference::reference_intersect(c.mesh, c.rays[i]);
    });
    return refs;
}

std::vector<Hit> trace2(const Bvh2& bvh, const std::vector<Ray>& rays, TraceOptions o = {}) {
    std::vector<Hit> hits(rays.size());
    intersect(bvh, rays, hits, o);
    return hits;
}

class Families : public testing::TestWithParam<Family> {};

TEST_P(Families, DefaultPathAgreesWithReferenceAndPathsAreBitIdentical) {
    workloads::FamilyOptions fo;
    fo.quick = true;
    fo.random_scene = "icosphere-4";  // offline and deterministic (the CLI uses dragon-res4 when cached)
    const auto cases = workloads::make_family(GetParam(), fo);
    ASSERT_FALSE(cases.empty());
    for (const workloads::FamilyCase& c : cases) {
        SCOPED_TRACE(c.name);
        ASSERT_EQ(c.rays.size(), c.expect.size());
        ASSERT_GT(c.rays.size(), 50u);
        const Bvh2 bvh = Bvh2::build(c.mesh);
        EXPECT_LE(bvh.stats().depth, BuildOptions{}.max_depth);
        const auto hits = trace2(bvh, c.rays);
        TraceStats st;
        TraceOptions so;
        so.stats = &st;
        const auto with_stats = trace2(bvh, c.rays, so);
        const auto refs = references(c);
        reference::Tally tally;
        std::size_t n_hit = 0;
        for (std::size_t i = 0; i < c.rays.size(); ++i) {
            const Hit& h = hits[i];
            ASSERT_EQ(h, with_stats[i]) << "ray " << i << ": the stats path differs";
            ASSERT_FALSE(std::isnan(h.t) || std::isnan(h.u) || std::isnan(h.v)) << "ray " << i;
            const reference::Verdict v = reference::classify(refs[i], h);
            tally.add(v);
            EXPECT_TRUE(v.label != reference::Label::leak && v.label != reference::Label::false_hit &&
                        v.label != reference::Label::wrong_triangle)
                << "ray " << i << ": " << reference::name(v.label) << (v.marginal ? " (marginal)" : "") << " t=" << h.t
                << " prim=" << h.prim << " t_ref=" << refs[i].t << " ref_prim=" << refs[i].prim;
            const workloads::RayExpect& e = c.expect[i];
            if (e.kind == Expect::hit) EXPECT_TRUE(h.hit()) << "ray " << i << " must hit";
            if (e.kind == Expect::miss) EXPECT_FALSE(h.hit()) << "ray " << i << " must miss";
            if (e.kind == Expect::no_self_hit) EXPECT_NE(h.prim, e.source) << "ray " << i << " hit its own triangle";
            if (!std::isnan(e.t) && h.hit()) EXPECT_NEAR(h.t, e.t, 1e-5 * e.t) << "ray " << i;
            n_hit += h.hit();
        }
        // t errors (ill-conditioned t on near-degenerate triangles) are allowed
        // only within the float error bound of the reference.
        EXPECT_EQ(tally.hard_disagreements(), 0u) << reference::to_string(tally);
        // (At offsets >= 1e6 the float spacing is 0.06..1, the meshes' size: they
        // collapse and may legitimately be missed by every ray.)
        if (GetParam() != Family::degenerate && c.offset < 1e6) EXPECT_GT(n_hit, 0u);
        for (Isa isa : supported_isas()) {
            const Bvh8 b8 = Bvh8::build(bvh);
            EXPECT_LE(b8.stats().depth, BuildOptions{}.max_depth);
            std::vector<Hit> h8(c.rays.size());
            intersect(b8, c.rays, h8, with_isa({}, isa));
            for (std::size_t i = 0; i < c.rays.size(); ++i)
                ASSERT_EQ(h8[i], hits[i]) << "bvh8/" << name(isa) << " ray " << i << " differs from bvh2";
        }
    }
}

TEST_P(Families, Deterministic) {
    workloads::FamilyOptions fo;
    fo.quick = true;
    fo.random_scene = "icosphere-3";
    const auto a = workloads::make_family(GetParam(), fo), b = workloads::make_family(GetParam(), fo);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
        EXPECT_EQ(a[k].name, b[k].name);
        ASSERT_EQ(a[k].rays.size(), b[k].rays.size());
        EXPECT_EQ(0, std::memcmp(a[k].rays.data(), b[k].rays.data(), a[k].rays.size() * sizeof(Ray))) << a[k].name;
        ASSERT_EQ(a[k].mesh.positions.size(), b[k].mesh.positions.size());
        EXPECT_EQ(0, std::memcmp(a[k].mesh.positions.data(), b[k].mesh.positions.data(),
                                 a[k].mesh.positions.size() * sizeof(Vec3)))
            << a[k].name;
        EXPECT_EQ(a[k].mesh.triangles, b[k].mesh.triangles) << a[k].name;
    }
}

INSTANTIATE_TEST_SUITE_P(All, Families, testing::ValuesIn(workloads::kAllFamilies),
                         [](const testing::TestParamInfo<Family>& i) {
                             std::string n(workloads::name(i.param));
                             for (char& ch : n)
                                 if (ch == '-') ch = '_';
                             return n;
                         });

TEST(FamilyNames, RoundTrip) {
    for (Family f : workloads::kAllFamilies) EXPECT_EQ(workloads::parse_family(workloads::name(f)), f);
    EXPECT_FALSE(workloads::parse_family("primary"));
}

TEST(FamilyShapes, OffsetsCoverEveryDecadeAndGrazingHasCoplanarRays) {
    workloads::FamilyOptions fo;
    fo.quick = true;
    const auto off = workloads::make_family(Family::offsets, fo);
    std::vector<double> seen;
    for (const auto& c : off) seen.push_back(c.offset);
    for (double o = 1.0; o <= 1e7; o *= 10.0) EXPECT_NE(std::find(seen.begin(), seen.end(), o), seen.end()) << o;
    const auto g = workloads::make_family(Family::grazing, fo);
    std::size_t coplanar = 0;
    for (std::size_t i = 0; i < g[0].rays.size(); ++i)
        coplanar += g[0].expect[i].kind == Expect::miss && g[0].rays[i].org.y == 0.0f && g[0].rays[i].dir.y == 0.0f;
    EXPECT_GT(coplanar, 10u);
    // The torus is closed: every edge is shared by exactly two triangles.
    const Mesh t = workloads::torus(12, 8);
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    for (const Triangle& tr : t.triangles)
        for (int k = 0; k < 3; ++k) edges[{std::min(tr[k], tr[(k + 1) % 3]), std::max(tr[k], tr[(k + 1) % 3])}]++;
    for (const auto& [e, n] : edges) EXPECT_EQ(n, 2);
    EXPECT_EQ(t.size(), 2u * 12 * 8);
}

// The comparison variants are wired and do what docs/accuracy.md measured: the
// plain box test and Moller-Trumbore leak on the watertight family.
TEST(Variants, PlainBoxAndMollerLeakWhereTheDefaultDoesNot) {
    workloads::FamilyOptions fo;
    fo.quick = true;
    const auto cases = workloads::make_family(Family::watertight, fo);
    std::size_t leaks[2][2] = {};
    for (const auto& c : cases) {
        const Bvh2 bvh = Bvh2::build(c.mesh);
        for (int t = 0; t < 2; ++t)
            for (int b = 0; b < 2; ++b) {
                TraceOptions o;
                o.test = t ? TriangleTest::moller : TriangleTest::watertight;
                o.box = b ? BoxTest::plain : BoxTest::conservative;
                for (const Hit& h : trace2(bvh, c.rays, o)) leaks[t][b] += !h.hit();  // every ray must hit
            }
    }
    EXPECT_EQ(leaks[0][0], 0u);
    EXPECT_GT(leaks[0][1], 0u) << "plain box: no leak on the watertight family (the variant is not wired?)";
    EXPECT_GT(leaks[1][0], 0u);
    EXPECT_GE(leaks[1][1], leaks[1][0]);
}

TEST(Variants, BoxTestOptionDoesNotChangeBvh8) {
    const auto cases = workloads::make_family(Family::watertight, {.quick = true});
    const auto& c = cases[0];
    const Bvh8 b8 = Bvh8::build(c.mesh);
    TraceOptions plain;
    plain.box = BoxTest::plain;
    std::vector<Hit> a(c.rays.size()), b(c.rays.size());
    intersect(b8, c.rays, a);
    intersect(b8, c.rays, b, plain);
    for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], b[i]) << "ray " << i;
}

}  // namespace
}  // namespace simdbvh
