// Rays with tiny or huge (finite, non-zero) directions. 1/d
// overflowed for |d| < 2^-128 while the slab distances stayed finite, so the
// BVHs culled boxes the brute force's triangles lay in; huge directions picked
// other triangles. Every path must agree with the brute force bit for bit at
// every scale, and an exact power-of-two rescaling must give the same triangle,
// u and v with t scaled exactly (see PreparedRay in kernels/ray.h).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/workloads/scenes.h"
#include "support/rays.h"

namespace simdbvh {
namespace {

constexpr std::size_t kRays = 6000;  // about 5,000 hits on icosphere-3

struct Fixture {
    Mesh mesh = workloads::icosphere(3);
    Bvh2 bvh2 = Bvh2::build(mesh);
    Bvh8 bvh8 = Bvh8::build(bvh2);
    std::vector<Ray> unit = [this] {
        std::vector<Ray> r = test::rays(mesh, workloads::RayKind::incoherent, kRays, 7);
        for (Ray& x : r) {
            x.tmin = 0.0f;
            x.tmax = std::numeric_limits<float>::infinity();
        }
        return r;
    }();
};
const Fixture& fixture() {
    static const Fixture f;
    return f;
}

std::vector<Ray> scaled(const std::vector<Ray>& rays, float factor) {
    std::vector<Ray> out = rays;
    for (Ray& r : out) r.dir = {r.dir.x * factor, r.dir.y * factor, r.dir.z * factor};
    return out;
}

std::string describe(const Hit& h) {
    return "prim " + std::to_string(h.prim) + " t " + std::to_string(h.t) + " (" +
           std::to_string(std::bit_cast<std::uint32_t>(h.t)) + ") u " + std::to_string(h.u) + " v " +
           std::to_string(h.v);
}

// Every path (BVH2, BVH8 on each ISA, brute force) gives the same bits; the
// any-hit queries agree on hit or miss. Returns the brute-force hits.
std::vector<Hit> expect_paths_agree(const std::vector<Ray>& rays, const std::string& what) {
    const Fixture& f = fixture();
    std::vector<Hit> brute(rays.size()), b2(rays.size()), b8(rays.size());
    brute_force_intersect(f.mesh, rays, brute);
    intersect(f.bvh2, rays, b2);
    std::size_t bad2 = 0, bad8 = 0, bad_any = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!(b2[i] == brute[i]) && bad2++ < 3)
            ADD_FAILURE() << what << " ray " << i << ": BVH2 " << describe(b2[i]) << ", brute " << describe(brute[i]);
        const bool occluded_brute = brute_force_occluded(f.mesh, rays[i]).hit();
        if (occluded(f.bvh2, rays[i]).hit() != occluded_brute && bad_any++ < 3)
            ADD_FAILURE() << what << " ray " << i << ": BVH2 any hit disagrees with brute force";
    }
    for (Isa isa : kAllIsas) {
        if (!supported(isa)) continue;
        intersect(f.bvh8, rays, b8, with_isa({}, isa));
        std::vector<Hit> any8(rays.size());
        occluded(f.bvh8, rays, any8, with_isa({}, isa));
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (!(b8[i] == brute[i]) && bad8++ < 3)
                ADD_FAILURE() << what << " ray " << i << ": BVH8 " << name(isa) << " " << describe(b8[i]) << ", brute "
                              << describe(brute[i]);
            if (any8[i].hit() != brute[i].hit() && bad_any++ < 3)
                ADD_FAILURE() << what << " ray " << i << ": BVH8 " << name(isa)
                              << " any hit disagrees with brute force";
        }
    }
    EXPECT_EQ(bad2, 0u) << what << ": BVH2 rays differing from brute force";
    EXPECT_EQ(bad8, 0u) << what << ": BVH8 rays differing from brute force";
    EXPECT_EQ(bad_any, 0u) << what << ": any-hit answers differing from brute force";
    return brute;
}

std::size_t count_hits(const std::vector<Hit>& hits) {
    std::size_t n = 0;
    for (const Hit& h : hits) n += h.hit();
    return n;
}

// The scales that failed: 1e-37 and 1e-38 lost hits in the BVHs, 3.4e38 changed
// the BVH2's triangle, and everything in between must hold too.
TEST(DirectionScale, EveryPathAgreesWithBruteForceAtEveryScale) {
    const Fixture& f = fixture();
    const std::size_t unit_hits = count_hits(expect_paths_agree(f.unit, "unit"));
    ASSERT_GT(unit_hits, kRays / 2);
    for (float factor : {1e-38f, 1e-37f, 1e-30f, 1e-10f, 1e10f, 1e30f, 3.4e38f / 2.0f}) {
        char what[64];
        std::snprintf(what, sizeof what, "|dir| x %g", double(factor));
        const std::vector<Hit> hits = expect_paths_agree(scaled(f.unit, factor), what);
        // A scaled direction is the same ray: apart from the few rays whose
        // small components became subnormal, the same triangles are hit.
        EXPECT_GE(count_hits(hits), unit_hits - unit_hits / 100) << what;
    }
}

// Tiny directions down to the smallest subnormal and huge ones up to 2^127:
// the scaled ray's components are computed in float (subnormal ones rounded),
// and whatever that ray is, every path answers it the same way.
TEST(DirectionScale, DenormalAndExtremeDirectionsAgreeOnEveryPath) {
    const Fixture& f = fixture();
    for (int e : {-149, -145, -140, -130, -127, -126, -120, 100, 120, 127}) {
        std::vector<Ray> rays = f.unit;
        for (Ray& r : rays) r.dir = {std::ldexp(r.dir.x, e), std::ldexp(r.dir.y, e), std::ldexp(r.dir.z, e)};
        std::size_t valid = 0;
        for (const Ray& r : rays) valid += prepare(r).valid;
        const std::vector<Hit> hits = expect_paths_agree(rays, "|dir| x 2^" + std::to_string(e));
        if (e >= -140) {
            EXPECT_GT(count_hits(hits), valid / 4) << "2^" << e << ": the rays must still hit";
        }
    }
}

// Origins with subnormal components, in the planes of the icosphere's
// vertices and edges (x, y or z = 0), directions along those planes (a zero,
// subnormal or tiny component on the same axis). The triangle test's
// products underflow at that scale, so it finds edge hits a box test with the
// exact origin puts outside the box: the BVHs lost the lower-id triangle of
// a tie on a shared edge (`simdbvh trace --scene icosphere-3` on rays with
// an origin component of 1.4e-45). prepare() flushes them to zero, as the
// direction's.
TEST(DirectionScale, SubnormalOriginComponentsAgreeOnEveryPath) {
    const float tiny[] = {1.4e-45f, -1.4e-45f, 1e-40f, -1e-40f, 1.1e-38f, -1.1e-38f};
    const float along[] = {0.0f, -0.0f, 1.4e-45f, -1e-40f, 1e-30f, -1e-20f};
    std::vector<Ray> rays;
    for (int i = 0; i < 3000; ++i) {
        const int a = i % 3, b = (a + 1) % 3, c = (a + 2) % 3;
        const float phi = 0.0021f * float(i), aim = 0.9f * std::sin(0.37f * float(i));
        Ray r{{0, 0, 0}, 0.0f, {0, 0, 0}, std::numeric_limits<float>::infinity()};
        r.org[a] = tiny[i % 6];
        r.org[b] = 1.7f * std::cos(phi);
        r.org[c] = 1.7f * std::sin(phi);
        r.dir[a] = along[(i / 6) % 6];
        r.dir[b] = -std::cos(phi) + aim * std::sin(phi);
        r.dir[c] = -std::sin(phi) - aim * std::cos(phi);
        rays.push_back(r);
    }
    const std::vector<Hit> hits = expect_paths_agree(rays, "subnormal origins");
    EXPECT_GT(count_hits(hits), rays.size() / 2);
}

// A power-of-two rescaling that keeps every component normal is the same ray
// exactly: same triangle, u and v, t scaled by the inverse power (ldexp
// rounding included, +inf when it overflows).
TEST(DirectionScale, PowerOfTwoScalingScalesTExactly) {
    const Fixture& f = fixture();
    std::vector<Hit> unit(kRays);
    brute_force_intersect(f.mesh, f.unit, unit);
    std::size_t checked = 0;
    for (int e : {-140, -126, -100, -40, -33, -1, 1, 33, 40, 100, 127}) {
        std::vector<Ray> rays = f.unit;
        std::vector<char> exact(kRays, 1);
        for (std::size_t i = 0; i < kRays; ++i) {
            Ray& r = rays[i];
            for (int k = 0; k < 3; ++k) {
                const float d = std::ldexp(r.dir[k], e);
                if (r.dir[k] != 0.0f && !(std::isnormal(d) && std::isnormal(r.dir[k]))) exact[i] = 0;
                r.dir[k] = d;
            }
        }
        std::vector<Hit> b8(kRays);
        for (Isa isa : kAllIsas) {
            if (!supported(isa)) continue;
            intersect(f.bvh8, rays, b8, with_isa({}, isa));
            std::size_t bad = 0;
            for (std::size_t i = 0; i < kRays; ++i) {
                if (!exact[i]) continue;
                checked += isa == Isa::scalar;
                Hit want = unit[i];
                if (want.hit()) want.t = std::ldexp(want.t, -e);
                if (!(b8[i] == want) && bad++ < 3)
                    ADD_FAILURE() << "2^" << e << " " << name(isa) << " ray " << i << ": " << describe(b8[i])
                                  << ", want " << describe(want);
            }
            EXPECT_EQ(bad, 0u) << "2^" << e << " " << name(isa);
        }
    }
    EXPECT_GT(checked, 5u * kRays);
}

// Where the caller's t exceeds FLT_MAX (a triangle 8 units away along a
// direction of length 2^-126 is 2^129 units of t away), the hit keeps its
// triangle, u and v, with t = +inf, on every path.
TEST(DirectionScale, HitsBeyondFloatRangeKeepTheirTriangleWithInfiniteT) {
    Mesh m;
    m.positions = {{-1, -1, -8}, {3, -1, -8}, {-1, 3, -8}, {-1, -1, -9}, {3, -1, -9}, {-1, 3, -9}};
    m.triangles = {{3, 4, 5}, {0, 1, 2}};
    const Bvh2 b2 = Bvh2::build(m);
    const Bvh8 b8 = Bvh8::build(b2);
    const Ray unit{{0.25f, 0.5f, 0.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, std::numeric_limits<float>::infinity()};
    const Hit near = brute_force_intersect(m, unit);
    ASSERT_EQ(near.prim, 1u);
    ASSERT_EQ(near.t, 8.0f);
    for (int e : {-126, -130, -149}) {
        Ray r = unit;
        r.dir.z = std::ldexp(-1.0f, e);
        Hit want = near;
        want.t = std::numeric_limits<float>::infinity();
        EXPECT_EQ(brute_force_intersect(m, r), want) << "2^" << e << ": " << describe(brute_force_intersect(m, r));
        EXPECT_EQ(intersect(b2, r), want) << "2^" << e;
        EXPECT_TRUE(occluded(b2, r).hit()) << "2^" << e;
        for (Isa isa : kAllIsas) {
            if (!supported(isa)) continue;
            EXPECT_EQ(intersect(b8, r, with_isa({}, isa)), want) << "2^" << e << " " << name(isa);
            EXPECT_TRUE(occluded(b8, r, with_isa({}, isa)).hit()) << "2^" << e << " " << name(isa);
        }
        // A finite tmax in the caller's units still limits the hits.
        r.tmax = 1e38f;
        EXPECT_FALSE(brute_force_intersect(m, r).hit()) << "2^" << e;
        EXPECT_FALSE(intersect(b2, r).hit()) << "2^" << e;
        for (Isa isa : kAllIsas)
            if (supported(isa)) {
                EXPECT_FALSE(intersect(b8, r, with_isa({}, isa)).hit()) << "2^" << e << " " << name(isa);
            }
    }
    // A huge direction: t = 8 / 2^127, rounded once (ldexp), same triangle.
    Ray big = unit;
    big.dir.z = -0x1p127f;
    Hit want = near;
    want.t = std::ldexp(8.0f, -127);
    EXPECT_EQ(intersect(b2, big), want) << describe(intersect(b2, big));
    for (Isa isa : kAllIsas)
        if (supported(isa)) {
            EXPECT_EQ(intersect(b8, big, with_isa({}, isa)), want) << name(isa);
        }
}

}  // namespace
}  // namespace simdbvh
