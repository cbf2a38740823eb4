// SIMD brute force (bvh8/brute_force8.h) against the scalar brute force of
// bvh2.h: closest hits bit-identical (prim, t, u, v) at every ISA, both
// triangle tests, 1 and 2 threads, on a closed sphere (rays through its
// vertices and edges included), a random soup and a mesh whose size is not a
// multiple of the block width; any hit agrees on hit/miss and returns a hit
// the scalar test confirms. The ray count is not a multiple of the SIMD loops'
// tile of 8 rays, the block count spans several block tiles, and invalid rays
// sit inside tiles.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "simdbvh/accel/brute_force8.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/triangle.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh {
namespace {

bool same_bits(const Hit& a, const Hit& b) {
    return a.prim == b.prim && std::memcmp(&a.t, &b.t, 4) == 0 && std::memcmp(&a.u, &b.u, 4) == 0 &&
           std::memcmp(&a.v, &b.v, 4) == 0;
}

void check_mesh(const Mesh& mesh, const char* what) {
    const BruteForce8 brute = BruteForce8::build(mesh);
    EXPECT_EQ(brute.triangles(), mesh.size());
    EXPECT_EQ(brute.blocks().size(), (mesh.size() + 7) / 8);
    std::vector<Ray> rays;
    for (workloads::RayKind k :
         {workloads::RayKind::primary, workloads::RayKind::incoherent, workloads::RayKind::diffuse}) {
        const auto r = workloads::generate_rays(mesh, k, 700, /*seed=*/9);
        rays.insert(rays.end(), r.begin(), r.end());
    }
    // Rays aimed exactly at vertices and edge midpoints (shared by several triangles: the tie rule decides).
    for (std::size_t t = 0; t < mesh.size() && t < 300; t += 3) {
        const Vec3 a = mesh.vertex(t, 0), b = mesh.vertex(t, 1);
        const Vec3 mid{0.5f * (a.x + b.x), 0.5f * (a.y + b.y), 0.5f * (a.z + b.z)};
        for (const Vec3& p : {a, mid}) rays.push_back(Ray{{p.x + 3, p.y + 2, p.z + 1}, 0, {-3, -2, -1}});
    }
    // Invalid rays (zero and NaN directions) scattered through the tiles of 8 rays the SIMD loops walk.
    for (std::size_t i = 5; i < rays.size(); i += 37) rays[i].dir = (i % 2) ? Vec3{0, 0, 0} : Vec3{std::nanf(""), 1, 0};
    for (TriangleTest test : {TriangleTest::watertight, TriangleTest::moller}) {
        std::vector<Hit> want(rays.size());
        std::size_t hit_count = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            want[i] = brute_force_intersect(mesh, rays[i], test);
            hit_count += want[i].hit();
        }
        EXPECT_GT(hit_count, rays.size() / 10) << what;
        for (Isa isa : supported_isas()) {
            for (int threads : {1, 2}) {
                TraceOptions o;
                o.test = test;
                o.threads = threads;
                std::vector<Hit> got(rays.size()), any(rays.size());
                intersect(brute, rays, got, with_isa(o, isa));
                occluded(brute, rays, any, with_isa(o, isa));
                for (std::size_t i = 0; i < rays.size(); ++i) {
                    ASSERT_TRUE(same_bits(got[i], want[i])) << what << " ray " << i << " isa " << name(isa) << " prim "
                                                            << got[i].prim << " vs " << want[i].prim;
                    ASSERT_EQ(any[i].hit(), want[i].hit()) << what << " ray " << i << " isa " << name(isa);
                    if (!any[i].hit()) continue;
                    ASSERT_GE(any[i].t, rays[i].tmin);
                    ASSERT_LE(any[i].t, rays[i].tmax);
                    const Hit one =
                        brute_force_intersect(Mesh{mesh.positions, {mesh.triangles[any[i].prim]}}, rays[i], test);
                    ASSERT_TRUE(one.hit()) << what << " ray " << i << ": any hit names a triangle the ray misses";
                }
            }
        }
    }
}

TEST(BruteForce8, BitIdenticalToScalarBruteForce) {
    check_mesh(workloads::icosphere(3), "icosphere-3");
    check_mesh(workloads::random_soup(1003, 4), "soup-1003");
}

TEST(BruteForce8, EmptyMeshAndBadInput) {
    const BruteForce8 empty = BruteForce8::build(Mesh{});
    std::vector<Ray> rays{Ray{{0, 0, 0}, 0, {1, 0, 0}}};
    std::vector<Hit> hits(1);
    intersect(empty, rays, hits);
    EXPECT_FALSE(hits[0].hit());
    std::vector<Hit> none;
    EXPECT_THROW(intersect(empty, rays, none), Error);
    Mesh bad = workloads::icosphere(1);
    bad.triangles[0][1] = 1u << 30;
    EXPECT_THROW(BruteForce8::build(bad), Error);
}

}  // namespace
}  // namespace simdbvh
