// Streams (TraceOptions::packets, bvh8/internal/simdbvh/bvh8/internal/stream-inl.h: 32 rays per walk):
// forced on, off or chosen automatically, every width and ISA gives the
// BVH2's closest hits bit for bit (the BVH2 is bit-identical to brute force),
// and an any hit is a real hit of the ray (its triangle hit at exactly that t,
// u, v by the scalar watertight test) whenever the ray hits anything. The
// rays: a camera's in image order (coherent: the streams stay together),
// streams whose rays straddle direction octants, rays no stream may take
// (invalid, missing the bounds), negative tmin, a finite tmax, a batch whose
// size is not a multiple of the stream, and incoherent rays.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/kernels/triangle.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"
#include "wide_trace_checks.h"

namespace simdbvh {
namespace {

// A camera's rays looking down -z at the mesh's centre, so the image's middle
// row and column split the streams there between octants; then odd rays.
std::vector<Ray> packet_rays(const Mesh& mesh) {
    const Aabb b = mesh.bounds();
    const Vec3 c = b.center(), e = b.extent();
    std::vector<Ray> rays;
    const int side = 101;  // 10201 rays: not a multiple of 8 or 32
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
            Ray r;
            r.org = Vec3{c.x, c.y, b.hi.z + e.z};
            r.dir =
                normalize(Vec3{(float(x) / (side - 1) - 0.5f) * 0.8f, (float(y) / (side - 1) - 0.5f) * 0.8f, -1.0f});
            if (y % 7 == 3) r.tmin = -0.5f * e.z;  // a negative tmin on some rows
            if (y % 11 == 5) r.tmax = 1.6f * e.z;  // a finite tmax on others
            if (x == 17 && y % 5 == 0) r.org.x = std::numeric_limits<float>::quiet_NaN();  // invalid
            if (x == 40 && y % 5 == 1) r.dir = Vec3{0, 0, 0};                              // invalid
            if (x == 60 && y % 5 == 2) r.org.x += 10 * e.x;                                // misses the bounds
            rays.push_back(r);
        }
    return rays;
}

void check_any_hit_is_real(const Mesh& mesh, const Ray& ray, const Hit& h, const std::string& what) {
    ASSERT_LT(h.prim, mesh.triangles.size()) << what;
    const Triangle& t = mesh.triangles[h.prim];
    const PreparedRay p = prepare(ray);
    float tt, u, v;
    ASSERT_TRUE(intersect_triangle<TriangleTest::watertight>(p, mesh.positions[t[0]], mesh.positions[t[1]],
                                                             mesh.positions[t[2]], p.tmax, &tt, &u, &v))
        << what;
    EXPECT_EQ(tt, h.t) << what;
    EXPECT_EQ(u, h.u) << what;
    EXPECT_EQ(v, h.v) << what;
}

template <int N>
void check_width(const Mesh& mesh, const Bvh2& bvh2, const std::vector<Ray>& rays, const std::vector<Hit>& want,
                 Isa isa, const std::string& what) {
    const BvhN<N> bvh = BvhN<N>::build(bvh2);
    for (Packets mode : {Packets::on, Packets::automatic, Packets::off}) {
        const std::string how =
            what + " bvh" + std::to_string(N) + " " + std::string(name(isa)) + " packets " + std::to_string(int(mode));
        TraceOptions o;
        o.packets = mode;
        std::vector<Hit> any;
        test::wide::expect_hits(bvh, rays, want, o, isa, how, any);
        if (testing::Test::HasFatalFailure()) return;
        for (std::size_t i = 0; i < rays.size(); ++i)
            if (any[i].hit()) check_any_hit_is_real(mesh, rays[i], any[i], how + " any, ray " + std::to_string(i));
    }
}

class PacketHits : public testing::TestWithParam<Isa> {};

TEST_P(PacketHits, SameClosestHitsRealAnyHits) {
    const Isa isa = GetParam();
    if (!supported(isa)) GTEST_SKIP() << "CPU lacks " << name(isa);
    // 100000 triangles: past 4 MiB, so the single-ray blocks run 8 in flight; 3000: one at a time.
    for (std::size_t tris : {3000u, 100000u}) {
        const Mesh mesh = workloads::random_soup(tris, 5);
        const Bvh2 bvh2 = Bvh2::build(mesh);
        std::vector<Ray> rays = packet_rays(mesh);
        const std::vector<Ray> more = workloads::generate_rays(mesh, workloads::RayKind::incoherent, 1203, 4);
        rays.insert(rays.end(), more.begin(), more.end());
        std::vector<Hit> want(rays.size());
        intersect(bvh2, rays, want, {});
        std::size_t hits = 0;
        for (const Hit& h : want) hits += h.hit();
        ASSERT_GT(hits, rays.size() / 10);  // the camera sees the soup
        const std::string what = "soup-" + std::to_string(tris);
        check_width<4>(mesh, bvh2, rays, want, isa, what);
        check_width<8>(mesh, bvh2, rays, want, isa, what);
        check_width<16>(mesh, bvh2, rays, want, isa, what);
    }
}

INSTANTIATE_TEST_SUITE_P(Isas, PacketHits, testing::ValuesIn(kAllIsas),
                         [](const testing::TestParamInfo<Isa>& i) { return std::string(name(i.param)); });

}  // namespace
}  // namespace simdbvh
