// Rays that start on or within rounding of a face (docs/accuracy.md, "Rays
// that start on or near a surface"): every path takes the same decision at
// tmin = 0. A float t from the sheared depths can round across 0 for a ray
// that leaves a face from just behind it; the box tests see such a box behind
// the origin and cull it, so the triangle test decides the side of tmin in
// double (triangle.h, detail::accept_t), and the brute force, the SIMD brute
// force, BVH2 and BVH4/8/16 at every ISA must return the same bits.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/accel/brute_force8.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/kernels/isa.h"

namespace simdbvh {
namespace {

bool same_bits(const Hit& a, const Hit& b) {
    return a.prim == b.prim && std::memcmp(&a.t, &b.t, 4) == 0 && std::memcmp(&a.u, &b.u, 4) == 0 &&
           std::memcmp(&a.v, &b.v, 4) == 0;
}

Mesh unit_cube() {
    Mesh m;
    for (int i = 0; i < 8; ++i) m.positions.push_back({float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
    const std::uint32_t f[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                                    {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
    for (const auto& t : f) m.triangles.push_back({t[0], t[1], t[2]});
    return m;
}

// A floor z = 0 of half-width w in two triangles.
Mesh floor_of(float w) {
    Mesh m;
    m.positions = {{-w, -w, 0}, {w, -w, 0}, {w, w, 0}, {-w, w, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

// An octahedron of radius s around c: tilted faces, none axis-aligned.
Mesh octahedron(float s, Vec3 c) {
    Mesh m;
    m.positions = {{c.x + s, c.y, c.z}, {c.x - s, c.y, c.z}, {c.x, c.y + s, c.z},
                   {c.x, c.y - s, c.z}, {c.x, c.y, c.z + s}, {c.x, c.y, c.z - s}};
    const std::uint32_t f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                   {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (const auto& t : f) m.triangles.push_back({t[0], t[1], t[2]});
    return m;
}

// Rays from points on the faces, moved off each face along its normal by a
// distance from 1e-12 to 1e-3 of the mesh's size (either side), in random
// directions (toward and away from the face).
std::vector<Ray> near_face_rays(const Mesh& mesh, float size, std::size_t count, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0), sym(-1.0, 1.0), expo(-12.0, -3.0);
    std::vector<Ray> rays;
    for (std::size_t k = 0; k < count; ++k) {
        const std::size_t tri = rng() % mesh.size();
        const Vec3 a = mesh.vertex(tri, 0), b = mesh.vertex(tri, 1), c = mesh.vertex(tri, 2);
        double u = uni(rng), v = uni(rng);
        if (u + v > 1) u = 1 - u, v = 1 - v;
        double n[3] = {double(b.y - a.y) * (c.z - a.z) - double(b.z - a.z) * (c.y - a.y),
                       double(b.z - a.z) * (c.x - a.x) - double(b.x - a.x) * (c.z - a.z),
                       double(b.x - a.x) * (c.y - a.y) - double(b.y - a.y) * (c.x - a.x)};
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        const double off = (rng() & 1 ? 1.0 : -1.0) * size * std::pow(10.0, expo(rng));
        const double p[3] = {a.x + u * (b.x - a.x) + v * (c.x - a.x), a.y + u * (b.y - a.y) + v * (c.y - a.y),
                             a.z + u * (b.z - a.z) + v * (c.z - a.z)};
        Ray r;
        r.org = {float(p[0] + off * n[0] / len), float(p[1] + off * n[1] / len), float(p[2] + off * n[2] / len)};
        r.dir = {float(sym(rng)), float(sym(rng)), float(sym(rng))};
        rays.push_back(r);
    }
    return rays;
}

// Every path against the scalar brute force, closest (bit for bit) and any (hit or miss).
void expect_all_paths_agree(const Mesh& mesh, const std::vector<Ray>& rays, const std::string& what) {
    std::vector<Hit> want(rays.size()), want_any(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        want[i] = brute_force_intersect(mesh, rays[i]);
        want_any[i] = brute_force_occluded(mesh, rays[i]);
        ASSERT_EQ(want_any[i].hit(), want[i].hit()) << what << ": brute force any hit, ray " << i;
        if (want[i].hit()) {
            ASSERT_GE(want[i].t, 0.0f) << what << " ray " << i;
            ASSERT_FALSE(std::signbit(want[i].t)) << what << ": a t of -0, ray " << i;
        }
    }
    auto check = [&](const std::vector<Hit>& got, const std::vector<Hit>& any, const std::string& path) {
        std::size_t wrong = 0, wrong_any = 0, first = rays.size();
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (!same_bits(got[i], want[i])) wrong++, first = std::min(first, i);
            if (any[i].hit() != want[i].hit()) wrong_any++, first = std::min(first, i);
        }
        EXPECT_EQ(wrong + wrong_any, 0u) << what << ", " << path << ": " << wrong << " closest and " << wrong_any
                                         << " any hits of " << rays.size() << " differ from brute force (first: ray "
                                         << first << ")";
    };
    std::vector<Hit> got(rays.size()), any(rays.size());
    BuildOptions small;
    small.max_leaf_size = 1;
    const Bvh2 bvh2 = Bvh2::build(mesh, small);
    intersect(bvh2, rays, got);
    occluded(bvh2, rays, any);
    check(got, any, "BVH2");
    for (std::size_t i = 0; i < rays.size(); ++i) got[i] = intersect(bvh2, rays[i]), any[i] = occluded(bvh2, rays[i]);
    check(got, any, "BVH2 single rays");
    const BruteForce8 brute = BruteForce8::build(mesh);
    const Bvh4 b4 = Bvh4::build(bvh2);
    const Bvh8 b8 = Bvh8::build(bvh2);
    const Bvh16 b16 = Bvh16::build(bvh2);
    for (Isa isa : {Isa::scalar, Isa::avx2, Isa::avx512}) {
        if (!supported(isa)) continue;
        const std::string at = " " + std::string(name(isa));
        intersect(brute, rays, got, with_isa({}, isa));
        occluded(brute, rays, any, with_isa({}, isa));
        check(got, any, "SIMD brute force" + at);
        intersect(b4, rays, got, with_isa({}, isa));
        occluded(b4, rays, any, with_isa({}, isa));
        check(got, any, "BVH4" + at);
        intersect(b8, rays, got, with_isa({}, isa));
        occluded(b8, rays, any, with_isa({}, isa));
        check(got, any, "BVH8" + at);
        for (std::size_t i = 0; i < rays.size(); ++i)
            got[i] = intersect(b8, rays[i], with_isa({}, isa)), any[i] = occluded(b8, rays[i], with_isa({}, isa));
        check(got, any, "BVH8 single rays" + at);
        intersect(b16, rays, got, with_isa({}, isa));
        occluded(b16, rays, any, with_isa({}, isa));
        check(got, any, "BVH16" + at);
    }
}

// The ray of the report: it starts 4.8e-8 below the cube's bottom face z = 0
// and leaves it (true t = -3.6e-8): a miss on every path, closest and any.
TEST(LeavingFace, CubeRayJustBelowTheBottomFaceMissesOnEveryPath) {
    const Mesh cube = unit_cube();
    Ray r;
    r.org = {0.4799143671989441f, 0.885593593120575f, -4.848630652531938e-08f};
    r.dir = {1.3611253499984741f, -0.44708237051963806f, -1.3384815454483032f};
    EXPECT_FALSE(brute_force_intersect(cube, r).hit()) << "t = " << brute_force_intersect(cube, r).t;
    EXPECT_FALSE(brute_force_occluded(cube, r).hit());
    expect_all_paths_agree(cube, {r}, "cube");
}

// On a floor z = 0 the answer is known without the code: a ray from below
// going down misses, one from above going down hits at t >= 0, whatever the
// floor's size and however close to it the origin is.
TEST(LeavingFace, FloorsOfEverySizeDecideBySide) {
    for (float w : {1.0f, 100.0f, 2e6f}) {
        const Mesh floor = floor_of(w);
        std::mt19937 rng(11);
        std::uniform_real_distribution<float> xy(-0.9f * w, 0.9f * w), d(-1.0f, 1.0f), expo(-12.0f, -2.0f);
        std::vector<Ray> below, above;
        for (int k = 0; k < 2000; ++k) {
            const float off = w * std::pow(10.0f, expo(rng));
            Ray r;
            r.org = {xy(rng), xy(rng), -off};
            r.dir = {d(rng), d(rng), -std::fabs(d(rng)) - 1e-3f};
            below.push_back(r);
            r.org.z = off;
            above.push_back(r);
        }
        const std::string what = "floor of half-width " + std::to_string(w);
        for (std::size_t i = 0; i < below.size(); ++i) {
            ASSERT_FALSE(brute_force_intersect(floor, below[i]).hit()) << what << ", from below, ray " << i;
            ASSERT_FALSE(brute_force_occluded(floor, below[i]).hit()) << what << ", from below, ray " << i;
        }
        std::size_t hits = 0;
        for (const Ray& r : above) hits += brute_force_intersect(floor, r).hit();
        // Rays from above going down hit unless they leave the floor's edge first.
        EXPECT_GT(hits, above.size() * 9 / 10) << what;
        expect_all_paths_agree(floor, below, what + ", from below");
        expect_all_paths_agree(floor, above, what + ", from above");
    }
}

// Tilted faces of small and large triangles, near the origin and far from it.
TEST(LeavingFace, TiltedFacesAgreeOnEveryPath) {
    const struct {
        float size;
        Vec3 centre;
    } cases[] = {{1.0f, {0, 0, 0}}, {100.0f, {0, 0, 0}}, {1e6f, {0, 0, 0}}, {10.0f, {1e4f, -3e3f, 7e3f}}};
    unsigned seed = 3;
    for (const auto& c : cases) {
        const Mesh m = octahedron(c.size, c.centre);
        expect_all_paths_agree(m, near_face_rays(m, c.size, 3000, seed++),
                               "octahedron of size " + std::to_string(c.size));
    }
    const Mesh cube = unit_cube();
    expect_all_paths_agree(cube, near_face_rays(cube, 1.0f, 3000, 99), "unit cube");
}

}  // namespace
}  // namespace simdbvh
