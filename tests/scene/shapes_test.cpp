// Analytic primitive tests and transforms against answers worked out by hand
// (or in double by an independent formula), not by the code under test.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/scene/shapes.h"
#include "simdbvh/scene/transform.h"

namespace simdbvh {
namespace {

PreparedRay ray(Vec3 o, Vec3 d, float tmin = 0.0f, float tmax = INFINITY) { return prepare(Ray{o, tmin, d, tmax}); }

TEST(Sphere, HeadOnHitAtTheSouthPole) {
    float t, u, v;
    ASSERT_TRUE(hit_sphere(ray({0, 0, -5}, {0, 0, 1}), Sphere{{0, 0, 0}, 1}, INFINITY, &t, &u, &v));
    EXPECT_EQ(t, 4.0f);
    EXPECT_EQ(u, 0.5f);  // atan2(0, 0) = 0 -> (0 + pi) / 2pi
    EXPECT_EQ(v, 1.0f);  // n = (0, 0, -1): acos(-1) / pi
}

TEST(Sphere, UnnormalisedDirectionKeepsTheRayParameter) {
    float t, u, v;
    ASSERT_TRUE(hit_sphere(ray({0, 0, 0}, {0, 0, 2}), Sphere{{0, 0, 5}, 1}, INFINITY, &t, &u, &v));
    EXPECT_EQ(t, 2.0f);  // z = 4 at t = 2
}

TEST(Sphere, OriginInsideReportsTheExit) {
    float t, u, v;
    ASSERT_TRUE(hit_sphere(ray({0, 0, 0}, {1, 0, 0}), Sphere{{0, 0, 0}, 2}, INFINITY, &t, &u, &v));
    EXPECT_EQ(t, 2.0f);
    EXPECT_EQ(v, 0.5f);  // equator
    EXPECT_EQ(u, 0.5f);  // n = (1, 0, 0): atan2(0, 1) = 0
}

TEST(Sphere, MissesBesideAndBehindAndBeyondTmax) {
    float t, u, v;
    EXPECT_FALSE(hit_sphere(ray({1.5f, 0, -5}, {0, 0, 1}), Sphere{{0, 0, 0}, 1}, INFINITY, &t, &u, &v));
    EXPECT_FALSE(hit_sphere(ray({0, 0, 5}, {0, 0, 1}), Sphere{{0, 0, 0}, 1}, INFINITY, &t, &u, &v));
    EXPECT_FALSE(hit_sphere(ray({0, 0, -5}, {0, 0, 1}), Sphere{{0, 0, 0}, 1}, 3.5f, &t, &u, &v));
    EXPECT_TRUE(hit_sphere(ray({0, 0, -5}, {0, 0, 1}), Sphere{{0, 0, 0}, 1}, 4.0f, &t, &u, &v));  // inclusive
}

// Haines et al. 2019: a small sphere far away. The naive float quadratic
// (b^2 - c with b ~ 1e4, c ~ 1e8) loses the discriminant entirely; the
// closest-approach form keeps it. Expected: t = z_c - sqrt(r^2 - y^2), in double.
// u, v against libm's atan2 and acos of the hit normal (in double, from the
// reported t), over hits in every octant of the sphere and at the poles and
// seams: within 2 float ulps of 1 (the polynomial atan2 is within 1.1e-14).
TEST(Sphere, LongitudeAndColatitudeMatchLibm) {
    std::mt19937 rng(17);
    std::normal_distribution<float> g;
    const Sphere s{{0.25f, -0.5f, 1.0f}, 0.75f};
    const double kPi = 3.14159265358979323846;
    int hits = 0, octants = 0;
    for (int i = 0; i < 20000; ++i) {
        Vec3 d{g(rng), g(rng), g(rng)};
        if (i < 6)  // the six poles and seams first
            d = Vec3{float(i == 0) - float(i == 1), float(i == 2) - float(i == 3), float(i == 4) - float(i == 5)};
        const Vec3 o = s.center - d * 3.0f;  // aimed at the centre: every direction hits
        float t, u, v;
        ASSERT_TRUE(hit_sphere(ray(o, d), s, INFINITY, &t, &u, &v)) << i;
        ++hits;
        double n[3];
        for (int a = 0; a < 3; ++a) n[a] = (double(o[a]) + double(t) * double(d[a]) - double(s.center[a])) / 0.75;
        octants |= 1 << ((n[0] > 0) + 2 * (n[1] > 0) + 4 * (n[2] > 0));
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        const double ru = (std::atan2(n[1], n[0]) + kPi) / (2 * kPi);
        const double rv = std::acos(std::clamp(n[2] / len, -1.0, 1.0)) / kPi;
        // The reference recomputes n from the float t: allow t's rounding (|dn| <= ulp(t) |d| / r).
        const double slack = 2.0 * std::ldexp(1.0, std::ilogb(t) - 23) * double(length(d)) / 0.75;
        EXPECT_NEAR(u, ru, 2.4e-7 + slack) << i;
        EXPECT_NEAR(v, rv, 2.4e-7 + slack) << i;
        EXPECT_GE(u, 0.0f);
        EXPECT_LE(u, 1.0f);
        EXPECT_GE(v, 0.0f);
        EXPECT_LE(v, 1.0f);
    }
    EXPECT_EQ(hits, 20000);
    EXPECT_EQ(octants, 255);
}

TEST(Sphere, DistantSmallSphereIsPrecise) {
    const double zc = 1e4, r = 1.0, y = 0.5;
    float t, u, v;
    ASSERT_TRUE(
        hit_sphere(ray({0, float(y), 0}, {0, 0, 1}), Sphere{{0, 0, float(zc)}, float(r)}, INFINITY, &t, &u, &v));
    EXPECT_EQ(t, float(zc - std::sqrt(r * r - y * y)));
    // Farther and smaller: 1e6 away, radius 1e-2, 0.6 of the radius off axis.
    const double zc2 = 1e6, r2 = 1e-2, y2 = 6e-3;
    ASSERT_TRUE(
        hit_sphere(ray({0, float(y2), 0}, {0, 0, 1}), Sphere{{0, 0, float(zc2)}, float(r2)}, INFINITY, &t, &u, &v));
    EXPECT_EQ(t, float(double(float(zc2)) -
                       std::sqrt(double(float(r2)) * double(float(r2)) - double(float(y2)) * double(float(y2)))));
}

TEST(Box, EntryFaceAndFaceCoordinates) {
    float t, u, v;
    const Aabb b{{0, 0, 0}, {1, 1, 1}};
    ASSERT_TRUE(hit_box(ray({-5, 0.25f, 0.5f}, {1, 0, 0}), b, INFINITY, &t, &u, &v));
    EXPECT_EQ(t, 5.0f);
    EXPECT_EQ(u, 0.25f);  // face x: u = y, v = z
    EXPECT_EQ(v, 0.5f);
    ASSERT_TRUE(hit_box(ray({0.75f, 3, 0.125f}, {0, -2, 0}), b, INFINITY, &t, &u, &v));
    EXPECT_EQ(t, 1.0f);   // y = 1 at t = 1
    EXPECT_EQ(u, 0.75f);  // face y: u = x, v = z
    EXPECT_EQ(v, 0.125f);
}

TEST(Box, OriginInsideReportsTheExitAndParallelRaysOutsideMiss) {
    float t, u, v;
    const Aabb b{{0, 0, 0}, {1, 1, 1}};
    ASSERT_TRUE(hit_box(ray({0.5f, 0.5f, 0.5f}, {0, 1, 0}), b, INFINITY, &t, &u, &v));
    EXPECT_EQ(t, 0.5f);
    EXPECT_FALSE(hit_box(ray({-5, 2, 0.5f}, {1, 0, 0}), b, INFINITY, &t, &u, &v));
    EXPECT_FALSE(hit_box(ray({-5, 0.5f, 0.5f}, {-1, 0, 0}), b, INFINITY, &t, &u, &v));
}

// Two boxes sharing the face x = 1: every ray crossing that face inside its
// rectangle hits one of them (no crack), at the same t from either side.
TEST(Box, SharedFaceHasNoCrack) {
    const Aabb a{{0, 0, 0}, {1, 1, 1}}, b{{1, 0, 0}, {2, 1, 1}};
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), wide(-3.0f, 3.0f);
    int hits = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 target{1.0f, unit(rng), unit(rng)};
        const Vec3 org{wide(rng) * 10, wide(rng) * 10, wide(rng) * 10};
        if (org.x > -1 && org.x < 3) continue;
        const Vec3 dir = target - org;
        float t0, t1, u, v;
        const bool ha = hit_box(ray(org, dir), a, INFINITY, &t0, &u, &v);
        const bool hb = hit_box(ray(org, dir), b, INFINITY, &t1, &u, &v);
        ASSERT_TRUE(ha || hb) << "ray " << i;
        hits++;
    }
    EXPECT_GT(hits, 1000);
}

TEST(Plane, HitParallelAndBehind) {
    float t;
    const Plane floor{{0, 0, 0}, {0, 1, 0}};
    ASSERT_TRUE(hit_plane(ray({3, 5, 1}, {0, -2, 1}), floor, INFINITY, &t));
    EXPECT_EQ(t, 2.5f);
    EXPECT_FALSE(hit_plane(ray({3, 5, 1}, {1, 0, 0}), floor, INFINITY, &t));
    EXPECT_FALSE(hit_plane(ray({3, 5, 1}, {0, 1, 0}), floor, INFINITY, &t));
    const Plane tilted{{0, 1, 0}, {0, 3, 4}};  // 3y + 4z = 3
    ASSERT_TRUE(hit_plane(ray({0, 0, 0}, {0, 0, 1}), tilted, INFINITY, &t));
    EXPECT_EQ(t, 0.75f);
}

// nearest_plane (every plane's hit_plane arithmetic, the choice by selects)
// against hit_plane over the planes one at a time: the nearest t in [tmin,
// tmax], the lower plane on a tie, the first hit for any; 1 to 9 planes, with
// repeated planes (exact ties), planes parallel to the ray and behind it,
// finite tmax and positive tmin.
TEST(Plane, NearestOfManyIsTheNearestHitPlaneLowerOnTies) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-4.0f, 4.0f);
    std::uniform_int_distribution<int> axis(0, 2);
    int hits = 0, ties = 0, parallel = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        std::vector<Plane> planes(std::size_t(1 + trial % 9));
        for (Plane& p : planes) {
            p.point = {u(rng), u(rng), u(rng)};
            p.normal = {u(rng), u(rng), u(rng)};
            if (trial % 3 == 0) p.normal = axis(rng) == 0 ? Vec3{0, 1, 0} : Vec3{0, 0, 2};
        }
        if (planes.size() > 2 && trial % 2 == 0) planes.back() = planes[1];  // an exact tie: the later loses
        Vec3 d{u(rng), u(rng), u(rng)};
        if (trial % 4 == 1) d.y = 0;  // parallel to the y planes
        const float tmin = trial % 5 == 0 ? 0.5f : 0.0f, tmax = trial % 7 == 0 ? 1.5f : INFINITY;
        const PreparedRay r = ray({u(rng), u(rng), u(rng)}, d, tmin, tmax);
        for (const bool any : {false, true}) {
            int want = -1;
            float want_t = 0;
            for (std::size_t k = 0; k < planes.size(); ++k) {
                float t;
                if (!hit_plane(r, planes[k], r.tmax, &t)) {
                    const Vec3 n = planes[k].normal;
                    parallel += !any && n.x * r.dir.x + n.y * r.dir.y + n.z * r.dir.z == 0.0f;
                    continue;
                }
                if (want >= 0 && t == want_t) ties += !any;
                if (want < 0 || t < want_t) {
                    want = int(k);
                    want_t = t;
                    if (any) break;
                }
            }
            float t = -1.0f;
            ASSERT_EQ(nearest_plane(r, planes, r.tmax, any, &t), want) << "trial " << trial << " any " << any;
            if (want >= 0) {
                EXPECT_EQ(std::bit_cast<std::uint32_t>(t), std::bit_cast<std::uint32_t>(want_t)) << "trial " << trial;
                hits += !any;
            }
        }
    }
    EXPECT_GT(hits, 2000);
    EXPECT_GT(ties, 100);
    EXPECT_GT(parallel, 100);
}

// nearest_planes on every ISA, closest and any, against nearest_plane on
// prepare_scaled(ray) per ray: the plane's index and the bits of t in the
// caller's parameter. seen(i, prepared ray, any, isa, hit) for the callers' counts.
template <class Seen>
void expect_batch_is_per_ray(const std::vector<Ray>& rays, const std::vector<Plane>& planes, int trial, Seen&& seen) {
    for (const bool any : {false, true})
        for (const Isa isa : supported_isas()) {
            std::vector<int> plane(rays.size(), 99);
            std::vector<float> t(rays.size(), -7.0f);
            nearest_planes(rays, planes, any, plane, t, isa);
            for (std::size_t i = 0; i < rays.size(); ++i) {
                const PreparedRay pr = prepare_scaled(rays[i]);
                float want_t = 0.0f;
                const int want = pr.valid ? nearest_plane(pr, planes, pr.tmax, any, &want_t) : -1;
                ASSERT_EQ(plane[i], want) << name(isa) << " trial " << trial << " ray " << i << " any " << any;
                if (want >= 0) {
                    ASSERT_EQ(std::bit_cast<std::uint32_t>(t[i]), std::bit_cast<std::uint32_t>(to_caller_t(pr, want_t)))
                        << name(isa) << " trial " << trial << " ray " << i;
                }
                seen(i, pr, any, isa, want >= 0);
            }
        }
}

// The batch form: nearest_plane on prepare_scaled(ray) per ray, the index and
// the bits of t in the caller's parameter, for batches of every length mod 4,
// with invalid rays, rescaled directions (subnormal ones too), subnormal
// components (flushed: parallel to a plane), negative tmin, finite tmax,
// exact ties and parallel rays, closest and any, on every ISA.
TEST(Plane, BatchIsNearestPlaneOfEachRay) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-4.0f, 4.0f);
    int hits = 0, rescaled = 0, invalid = 0;
    for (int trial = 0; trial < 300; ++trial) {
        std::vector<Plane> planes(std::size_t(1 + trial % 7));
        for (Plane& p : planes) {
            p.point = {u(rng), u(rng), u(rng)};
            p.normal = trial % 3 == 0 ? Vec3{0, 1, 0} : trial % 3 == 1 ? Vec3{0, 0, 1} : Vec3{u(rng), u(rng), u(rng)};
        }
        if (planes.size() > 2) planes.back() = planes[1];  // an exact tie
        std::vector<Ray> rays(std::size_t(1 + trial % 13));
        for (std::size_t i = 0; i < rays.size(); ++i) {
            Ray& r = rays[i];
            r.org = {u(rng), u(rng), u(rng)};
            r.dir = {u(rng), u(rng), u(rng)};
            if (i % 5 == 1) r.dir.y = 0;                // parallel to the y planes
            if (i % 7 == 2) r.dir = r.dir * 0x1p-60f;   // rescaled: t in the caller's parameter is 2^60 larger
            if (i % 7 == 6) r.dir = r.dir * 0x1p-135f;  // rescaled from subnormal components
            if (i % 9 == 3) r.dir.z = 1e-40f;           // a subnormal component prepare_scaled flushes to zero
            if (i % 9 == 4) r.dir.y = -1e-40f;
            if (i % 4 == 3) r.tmin = -1.0f;
            if (i % 6 == 4) r.tmax = 1.5f;
            if (i % 11 == 5) r.org.x = std::numeric_limits<float>::quiet_NaN();
        }
        expect_batch_is_per_ray(rays, planes, trial,
                                [&](std::size_t, const PreparedRay& pr, bool any, Isa isa, bool hit) {
                                    const bool count = !any && isa == Isa::scalar;
                                    invalid += count && !pr.valid;
                                    hits += count && hit;
                                    rescaled += count && hit && pr.t_exp != 0;
                                });
    }
    EXPECT_GT(hits, 500);
    EXPECT_GT(rescaled, 20);
    EXPECT_GT(invalid, 20);
    std::vector<int> plane(1);
    std::vector<float> t(2);
    const std::vector<Ray> two(2);
    EXPECT_THROW(nearest_planes(two, {}, false, plane, t), Error);
}

// The SIMD batches take four rays as given when prepare_scaled() would not
// change them (plane_batch-inl.h): groups of four where every ray is plain,
// and groups where exactly one ray needs prepare_scaled for one reason (a
// rescaled direction, large or small, a subnormal component, a NaN or an
// infinite origin, a zero direction, tmin > tmax, a NaN tmax), each kind in
// each lane, against nearest_plane per ray on every ISA.
TEST(Plane, BatchTakesPlainGroupsAsGiven) {
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u(-4.0f, 4.0f);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    std::vector<Plane> planes(5);
    for (Plane& p : planes) p = {{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}};
    planes[3].normal = {0, 1, 0};
    auto plain = [&] {
        Ray r;
        r.org = {u(rng), u(rng), u(rng)};
        r.dir = {u(rng), u(rng), u(rng)};
        return r;
    };
    const std::vector<std::function<void(Ray&)>> odd = {
        [](Ray& r) { r.dir = r.dir * 0x1p-60f; },
        [](Ray& r) { r.dir = r.dir * 0x1p40f; },
        [](Ray& r) { r.dir.y = 1e-40f; },
        [&](Ray& r) { r.org.z = nan; },
        [&](Ray& r) { r.org.x = inf; },
        [](Ray& r) {
            r.dir = {0, 0, 0};
        },
        [](Ray& r) { r.tmin = 2.0f, r.tmax = 1.0f; },
        [&](Ray& r) { r.tmax = nan; },
        [&](Ray& r) { r.dir.x = inf; },
    };
    int plain_hits = 0, checked = 0;
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<Ray> rays;
        for (int g = 0; g < 4; ++g) {  // a plain group, with a zero component, negative tmin, finite tmax
            Ray r = plain();
            if (g == 1) r.dir.y = 0.0f;
            if (g == 2) r.tmin = -1.0f;
            if (g == 3) r.tmax = 1.5f;
            rays.push_back(r);
        }
        for (std::size_t k = 0; k < odd.size(); ++k)
            for (int lane = 0; lane < 4; ++lane)
                for (int g = 0; g < 4; ++g) {
                    Ray r = plain();
                    if (g == lane) odd[k](r);
                    rays.push_back(r);
                }
        expect_batch_is_per_ray(rays, planes, trial,
                                [&](std::size_t i, const PreparedRay&, bool any, Isa isa, bool hit) {
                                    ++checked;
                                    plain_hits += hit && i < 4 && !any && isa == Isa::scalar;
                                });
    }
    EXPECT_GT(plain_hits, 200);
    EXPECT_GT(checked, 10000);
}

TEST(Transform, InverseOfScaleRotateTranslate) {
    // x_world = 2 * Rz(90) x + (1, 2, 3): Rz(90) maps (x, y, z) to (-y, x, z).
    Affine3 m;
    m.m = {{{0, -2, 0, 1}, {2, 0, 0, 2}, {0, 0, 2, 3}}};
    const InverseAffine inv = invert(m);
    // The inverse, by hand: x = Rz(-90) (w - b) / 2: (wy - 2) / 2, -(wx - 1) / 2, (wz - 3) / 2.
    const Affine3 want{{{{0, 0.5f, 0, -1}, {-0.5f, 0, 0, 0.5f}, {0, 0, 0.5f, -1.5f}}}};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) EXPECT_EQ(inv.inv.m[r][c], want.m[r][c]) << r << "," << c;
    EXPECT_EQ(inv.cond, 1.0);  // a similarity: ||A|| ||A^-1|| = 2 * 0.5
    const Ray w{{1, 2, 13}, 0.0f, {0, 0, -4}, 100.0f};
    const Ray o = object_ray(inv.inv, w);  // origin (0, 0, 5), direction (0, 0, -2)
    EXPECT_EQ(o.org.x, 0.0f);
    EXPECT_EQ(o.org.y, 0.0f);
    EXPECT_EQ(o.org.z, 5.0f);
    EXPECT_EQ(o.dir.z, -2.0f);
    EXPECT_EQ(o.tmax, 100.0f);
    const Aabb box = transform_box(m, Aabb{{0, 0, 0}, {1, 1, 1}});  // x in [-1, 1], y in [2, 4], z in [3, 5]
    EXPECT_LE(box.lo.x, -1.0f);
    EXPECT_GE(box.lo.x, std::nextafter(-1.0f, -2.0f));
    EXPECT_GE(box.hi.y, 4.0f);
    EXPECT_LE(box.hi.y, std::nextafter(4.0f, 5.0f));
}

TEST(Transform, SingularAndNonFiniteThrow) {
    Affine3 flat;
    flat.m = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 0, 0}}};
    EXPECT_THROW(invert(flat), Error);
    Affine3 rank2;
    rank2.m = {{{1, 2, 3, 0}, {2, 4, 6, 0}, {0, 0, 1, 0}}};
    EXPECT_THROW(invert(rank2), Error);
    Affine3 nan;
    nan.m[1][3] = NAN;
    EXPECT_THROW(invert(nan), Error);
    Affine3 inf;
    inf.m[0][0] = INFINITY;
    EXPECT_THROW(invert(inf), Error);
    EXPECT_NO_THROW(invert(Affine3::scaling(1e-6f)));
}

// The singularity test is a condition test that per-axis scales pass: scale
// (1e-11, 1e10, 1) has det 0.1 and an exact inverse but was refused
// (|det| <= 1e-30 ||A||^3); a truly singular matrix whose computed det is
// rounding noise was accepted, and is refused.
TEST(Transform, ConditionTestAcceptsAxisScalesRefusesSingular) {
    Affine3 aniso;
    aniso.m = {{{1e-11f, 0, 0, 0}, {0, 1e10f, 0, 0}, {0, 0, 1, 0}}};
    const InverseAffine inv = invert(aniso);
    EXPECT_EQ(inv.inv.m[0][0], float(1.0 / double(1e-11f)));
    EXPECT_EQ(inv.inv.m[1][1], float(1.0 / double(1e10f)));
    EXPECT_EQ(inv.inv.m[2][2], 1.0f);
    EXPECT_NO_THROW(invert(Affine3::rotation({1, 2, 3}, 0.7) * aniso));
    EXPECT_NO_THROW(invert(aniso * Affine3::rotation({1, 2, 3}, 0.7)));
    // Ill-conditioned but exactly invertible: kept.
    Affine3 shear;
    shear.m = {{{1, 1, 0, 0}, {1, 1 + 0x1p-23f, 0, 0}, {0, 0, 1, 0}}};
    EXPECT_NO_THROW(invert(shear));
    // Row 0 = row 1 + row 2 exactly (checked below): singular, though the determinant computes to 8.9e-16.
    Affine3 sum;
    sum.m = {{{0x1.8c44eep+1f, 0x1.880e3cp+1f, 0x1.493b94p+1f, 0},
              {0x1.e0fd68p+0f, 0x1.18f2c4p+0f, 0x1.22cedap+0f, 0},
              {0x1.378c74p+0f, 0x1.f729b4p+0f, 0x1.6fa84ep+0f, 0}}};
    for (int c = 0; c < 3; ++c) ASSERT_EQ(double(sum.m[0][c]), double(sum.m[1][c]) + double(sum.m[2][c])) << c;
    try {
        invert(sum);
        ADD_FAILURE() << "a singular matrix was inverted";
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("transform: singular: |det| is "), std::string::npos) << msg;
        EXPECT_NE(msg.find("of the sum of the magnitudes of its six terms, at most 2^-40"), std::string::npos) << msg;
    }
}

}  // namespace
}  // namespace simdbvh
