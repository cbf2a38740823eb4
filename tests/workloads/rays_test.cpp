// Ray generation (deterministic, documented properties) and the ray/hit files
// (round trips, size errors, atomic writes).
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/io/ray_files.h"
#include "simdbvh/workloads/scenes.h"
#include "support/rays.h"
#include "support/scene.h"

namespace fs = std::filesystem;
using simdbvh::Aabb;
using simdbvh::Hit;
using simdbvh::Mesh;
using simdbvh::Ray;
using simdbvh::Vec3;
namespace io = simdbvh::io;
namespace wl = simdbvh::workloads;

namespace {

bool same_bytes(const std::vector<Ray>& a, const std::vector<Ray>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Ray)) == 0;
}

std::string error_of(auto&& f) {
    try {
        f();
    } catch (const simdbvh::Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(RayKind, Names) {
    for (auto k : wl::kRayKinds) EXPECT_EQ(wl::parse_ray_kind(wl::name(k)), k);
    EXPECT_EQ(wl::name(wl::RayKind::area_shadow), "area-shadow");
    EXPECT_EQ(wl::name(wl::RayKind::diffuse_shuffled), "diffuse-shuffled");
    EXPECT_FALSE(wl::parse_ray_kind("coherent").has_value());
    EXPECT_NE(wl::ray_kind_names().find("lidar"), std::string::npos);
}

TEST(Camera, ThreeQuarterViewCoversBounds) {
    const Aabb b{{-1, 0, -2}, {3, 2, 2}};
    const wl::Camera cam = wl::default_camera(b, 64, 32);
    EXPECT_GT(cam.eye.x, b.hi.x);
    EXPECT_GT(cam.eye.y, b.hi.y);
    EXPECT_GT(cam.eye.z, b.hi.z);
    EXPECT_NEAR(simdbvh::length(cam.forward), 1.0f, 1e-6f);
    EXPECT_NEAR(simdbvh::length(cam.up), std::tan(22.5 * M_PI / 180.0), 1e-6);
    EXPECT_NEAR(simdbvh::length(cam.right), 2.0 * std::tan(22.5 * M_PI / 180.0), 1e-6);
    EXPECT_NEAR(simdbvh::dot(cam.forward, cam.up), 0.0f, 1e-6f);
    EXPECT_GT(cam.up.y, 0.0f);
    const auto rays = wl::primary_rays(cam);
    ASSERT_EQ(rays.size(), 64u * 32u);
    // Row-major from the top-left: the first ray goes up and left of the last.
    EXPECT_GT(rays.front().dir.y, rays.back().dir.y);
    for (const Ray& r : rays) {
        EXPECT_NEAR(simdbvh::length(r.dir), 1.0f, 1e-6f);
        EXPECT_EQ(r.tmin, 0.0f);
        EXPECT_TRUE(std::isinf(r.tmax));
    }
    // The centre ray points at the centre of the bounds.
    const Vec3 to_c = simdbvh::normalize(b.center() - cam.eye);
    EXPECT_GT(simdbvh::dot(to_c, cam.forward), 0.99999f);
}

TEST(Rays, IncoherentProperties) {
    const Aabb b{{0, 0, 0}, {2, 4, 4}};
    const auto rays = wl::incoherent_rays(b, 10000, 5);
    ASSERT_EQ(rays.size(), 10000u);
    const float r = 1.5f * 0.5f * simdbvh::length(b.extent());
    for (const Ray& ray : rays) {
        EXPECT_NEAR(simdbvh::length(ray.org - b.center()), r, 1e-4f * r);
        EXPECT_NEAR(simdbvh::length(ray.dir), 1.0f, 1e-6f);
        EXPECT_EQ(ray.tmin, 0.0f);
        EXPECT_TRUE(std::isinf(ray.tmax));
        // Aimed inside the box: it must pass through it.
        EXPECT_LT(simdbvh::dot(ray.dir, simdbvh::normalize(b.center() - ray.org)), 1.0001f);
    }
    EXPECT_TRUE(same_bytes(rays, wl::incoherent_rays(b, 10000, 5)));
    EXPECT_FALSE(same_bytes(rays, wl::incoherent_rays(b, 10000, 6)));
    EXPECT_EQ(wl::incoherent_rays(Aabb{}, 10, 1).size(), 10u);  // empty bounds: still rays
}

TEST(Rays, InteriorProperties) {
    // Origins inside the box, unit directions spread over the whole sphere (every octant, both signs of
    // every axis), deterministic by seed.
    const Aabb b{{-1, 2, 3}, {1, 6, 4}};
    const auto rays = wl::interior_rays(b, 20000, 9);
    ASSERT_EQ(rays.size(), 20000u);
    int octants[8] = {};
    double mean[3] = {0, 0, 0};
    for (const Ray& ray : rays) {
        for (int a = 0; a < 3; ++a) {
            EXPECT_GE(ray.org[a], b.lo[a]);
            EXPECT_LE(ray.org[a], b.hi[a]);
            mean[a] += ray.dir[a] / double(rays.size());
        }
        EXPECT_NEAR(simdbvh::length(ray.dir), 1.0f, 1e-6f);
        EXPECT_EQ(ray.tmin, 0.0f);
        EXPECT_TRUE(std::isinf(ray.tmax));
        ++octants[(ray.dir.x < 0) | ((ray.dir.y < 0) << 1) | ((ray.dir.z < 0) << 2)];
    }
    for (int o = 0; o < 8; ++o) EXPECT_GT(octants[o], 2000) << "octant " << o;  // 2500 expected each
    for (int a = 0; a < 3; ++a) EXPECT_LT(std::fabs(mean[a]), 0.03) << "axis " << a;
    EXPECT_TRUE(same_bytes(rays, wl::interior_rays(b, 20000, 9)));
    EXPECT_FALSE(same_bytes(rays, wl::interior_rays(b, 20000, 10)));
}

TEST(Rays, DiffuseFromHandMadeHits) {
    // A unit square in the z = 0 plane seen from above; hits at known barycentrics.
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    std::vector<Ray> primary(3);
    std::vector<Hit> hits(3);
    primary[0].org = {0.5f, 0.2f, 5.0f};
    primary[0].dir = {0, 0, -1};
    hits[0] = Hit{5.0f, 0.3f, 0.2f, 0};
    primary[1].dir = {0, 0, 1};  // a miss: skipped
    primary[2].org = {0.2f, 0.5f, -5.0f};
    primary[2].dir = {0, 0, 1};  // from below: normal flipped to -z
    hits[2] = Hit{5.0f, 0.3f, 0.4f, 1};
    const auto rays = wl::diffuse_rays(m, primary, hits, 1000, 9);
    ASSERT_EQ(rays.size(), 1000u);
    double mean_cos = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Ray& r = rays[i];
        const float side = i % 2 == 0 ? 1.0f : -1.0f;  // cycles through hits 0 and 2
        EXPECT_GT(r.dir.z * side, 0.0f) << i;
        EXPECT_GT(r.org.z * side, 0.0f) << i;       // offset off the surface, on the ray's side
        EXPECT_LT(std::fabs(r.org.z), 1e-4f) << i;  // but only slightly
        EXPECT_NEAR(simdbvh::length(r.dir), 1.0f, 1e-6f);
        mean_cos += std::fabs(r.dir.z);
    }
    EXPECT_NEAR(mean_cos / rays.size(), 2.0 / 3.0, 0.03);  // cosine-weighted: E[cos] = 2/3
    // Hit point from the barycentrics: P = (1-u-v) v0 + u v1 + v v2 = (0.5, 0.2, 0).
    EXPECT_NEAR(rays[0].org.x, 0.5f, 1e-6f);
    EXPECT_NEAR(rays[0].org.y, 0.2f, 1e-6f);
    EXPECT_TRUE(wl::diffuse_rays(m, primary, std::vector<Hit>(3), 10, 1).empty());  // nothing hit
}

TEST(Rays, DiffuseOffsetScalesWithScene) {
    // Scaling the scene by a power of two scales the offset origins exactly.
    Mesh a;
    a.positions = {{0.001f, 0.001f, 0.0f}, {0.01f, 0.001f, 0.0f}, {0.001f, 0.01f, 0.0f}};
    a.triangles = {{0, 1, 2}};
    Mesh b = a;
    for (Vec3& p : b.positions) p = p * 1024.0f;
    std::vector<Ray> pa(1), pb(1);
    pa[0].org = {0.003f, 0.003f, 1.0f};
    pa[0].dir = {0, 0, -1};
    pb[0] = pa[0];
    pb[0].org = pa[0].org * 1024.0f;
    const std::vector<Hit> h{Hit{1.0f, 0.25f, 0.25f, 0}};
    const auto ra = wl::diffuse_rays(a, pa, h, 4, 1), rb = wl::diffuse_rays(b, pb, h, 4, 1);
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(ra[i].org * 1024.0f, rb[i].org);
        EXPECT_EQ(ra[i].dir, rb[i].dir);
    }
}

TEST(Rays, GenerateDeterministicAllKinds) {
    const Mesh m = wl::icosphere(3);
    for (auto kind : wl::kRayKinds) {
        SCOPED_TRACE(std::string(wl::name(kind)));
        const auto a = test::rays(m, kind, 5000, 11), b = test::rays(m, kind, 5000, 11);
        ASSERT_EQ(a.size(), 5000u);
        EXPECT_TRUE(same_bytes(a, b));
        for (const Ray& r : a) ASSERT_TRUE(simdbvh::is_finite(r.org) && simdbvh::is_finite(r.dir));
    }
    // Diffuse rays start on the (convex) icosphere's surface, on the outside (primary rays come from
    // outside), so none may hit it again.
    const auto d = test::rays(m, wl::RayKind::diffuse, 2000, 3);
    const auto bvh = simdbvh::Bvh2::build(m);
    for (const Ray& r : d) {
        EXPECT_NEAR(simdbvh::length(r.org), 1.0f, 1e-2f);
        EXPECT_FALSE(simdbvh::intersect(bvh, r).hit()) << "diffuse ray from a convex surface hit it";
    }
}

// The distributions beyond the bench's three: each has the documented shape (rays.h).
TEST(Rays, ShuffledDiffuseIsAPermutationOfDiffuse) {
    const Mesh m = wl::icosphere(3);
    const auto d = test::rays(m, wl::RayKind::diffuse, 3000, 5);
    const auto s = test::rays(m, wl::RayKind::diffuse_shuffled, 3000, 5);
    ASSERT_EQ(s.size(), d.size());
    EXPECT_FALSE(same_bytes(s, d)) << "not shuffled";
    auto key = [](const Ray& r) {
        std::array<std::uint32_t, 8> k;
        std::memcpy(k.data(), &r, sizeof(Ray));
        return k;
    };
    std::vector<std::array<std::uint32_t, 8>> a, b;
    for (const Ray& r : d) a.push_back(key(r));
    for (const Ray& r : s) b.push_back(key(r));
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    EXPECT_EQ(a, b) << "the shuffled rays are not the same rays";
}

TEST(Rays, ShadowRaysEndShortOfTheLight) {
    const Mesh m = wl::icosphere(3);
    const Vec3 light = wl::light_position(m.bounds());
    EXPECT_GT(light.y, m.bounds().hi.y);
    const float side = 0.5f * simdbvh::length(m.bounds().extent());
    for (bool area : {false, true}) {
        SCOPED_TRACE(area ? "area" : "point");
        const auto r = test::rays(m, area ? wl::RayKind::area_shadow : wl::RayKind::shadow, 2000, 9);
        ASSERT_EQ(r.size(), 2000u);
        for (const Ray& x : r) {
            ASSERT_TRUE(std::isfinite(x.tmax));
            EXPECT_NEAR(simdbvh::length(x.org), 1.0f, 1e-2f);  // on the unit icosphere
            const Vec3 end = x.org + x.dir * (x.tmax / 0.9999f);
            EXPECT_NEAR(end.y, light.y, 1e-3f);
            if (!area) {
                EXPECT_NEAR(end.x, light.x, 1e-3f);
                EXPECT_NEAR(end.z, light.z, 1e-3f);
            } else {
                EXPECT_LE(std::fabs(end.x - light.x), 0.5f * side + 1e-3f);
                EXPECT_LE(std::fabs(end.z - light.z), 0.5f * side + 1e-3f);
            }
        }
    }
    // The area light's targets differ from ray to ray; the point light's do not.
    const auto a = test::rays(m, wl::RayKind::area_shadow, 64, 9);
    std::size_t distinct = 0;
    for (std::size_t i = 1; i < a.size(); ++i) distinct += !(a[i].dir == a[0].dir);
    EXPECT_GT(distinct, 50u);
}

TEST(Rays, AoRaysAreShortBouncesOutOfTheSurface) {
    const Mesh m = wl::icosphere(3);
    const auto r = test::rays(m, wl::RayKind::ao, 2000, 4);
    ASSERT_EQ(r.size(), 2000u);
    const float want = 0.1f * 0.5f * simdbvh::length(m.bounds().extent());
    const auto bvh = simdbvh::Bvh2::build(m);
    for (const Ray& x : r) {
        EXPECT_FLOAT_EQ(x.tmax, want);
        EXPECT_NEAR(simdbvh::length(x.org), 1.0f, 1e-2f);
        // Out of the facet it starts on, into its outer hemisphere: a convex surface is never hit again.
        Ray far = x;
        far.tmax = std::numeric_limits<float>::infinity();
        EXPECT_FALSE(simdbvh::intersect(bvh, far).hit()) << "an AO ray from a convex surface hit it";
    }
}

TEST(Rays, LidarSpinsFromTheCentreInFiringOrder) {
    const Aabb b{{-2, 0, -1}, {2, 4, 3}};
    const auto r = wl::lidar_rays(b, 64 * 100 + 10);
    ASSERT_EQ(r.size(), 64u * 100 + 10);
    for (const Ray& x : r) {
        EXPECT_EQ(x.org, b.center());
        EXPECT_NEAR(simdbvh::length(x.dir), 1.0f, 1e-6f);
        const float el = std::asin(x.dir.y) * 57.2957795f;
        EXPECT_GE(el, -25.001f);
        EXPECT_LE(el, 15.001f);
    }
    // One azimuth step holds all 64 beams, lowest first; the next step turns.
    for (int k = 1; k < 64; ++k) {
        EXPECT_NEAR(std::atan2(r[k].dir.z, r[k].dir.x), std::atan2(r[0].dir.z, r[0].dir.x), 1e-5f);
        EXPECT_GT(r[k].dir.y, r[k - 1].dir.y);
    }
    EXPECT_GT(std::fabs(std::atan2(r[64].dir.z, r[64].dir.x) - std::atan2(r[0].dir.z, r[0].dir.x)), 1e-3f);
}

TEST(Rays, SelfIntersectionFreeOnDragon) {
    SIMDBVH_LOAD_OR_SKIP(m, "dragon-res4");
    const auto d = test::rays(m, wl::RayKind::diffuse, 20000, 1);
    ASSERT_EQ(d.size(), 20000u);
    const auto bvh = simdbvh::Bvh2::build(m);
    std::vector<Hit> hits(d.size());
    simdbvh::intersect(bvh, d, hits);
    std::size_t tiny = 0;
    for (const Hit& h : hits) tiny += h.hit() && h.t < 1e-6f;
    EXPECT_EQ(tiny, 0u) << "diffuse rays hitting (almost) at their origin";
}

TEST(RayFiles, RoundTripBitExact) {
    test::TempDir dir;
    auto rays = wl::incoherent_rays(Aabb{{0, 0, 0}, {1, 1, 1}}, 100, 1);
    rays[3].dir = {-0.0f, std::numeric_limits<float>::quiet_NaN(), 0.0f};
    rays[4].tmin = 2.0f;
    io::write_rays(dir / "r.bin", rays);
    EXPECT_EQ(fs::file_size(dir / "r.bin"), 3200u);
    EXPECT_TRUE(same_bytes(io::read_rays(dir / "r.bin"), rays));
    std::vector<Hit> hits{Hit{}, Hit{1.5f, 0.25f, 0.5f, 7}, Hit{-0.0f, 1.0f, 0.0f, 0xFFFFFFFEu}};
    io::write_hits(dir / "h.bin", hits);
    EXPECT_EQ(fs::file_size(dir / "h.bin"), 48u);
    const auto back = io::read_hits(dir / "h.bin");
    ASSERT_EQ(back.size(), 3u);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(back[i], hits[i]);
    // Little-endian records: ray 0's origin x is the first four bytes.
    const std::string bytes = test::read_bytes(dir / "r.bin");
    const auto u = std::bit_cast<std::uint32_t>(rays[0].org.x);
    EXPECT_EQ(static_cast<unsigned char>(bytes[0]), u & 0xff);
    EXPECT_EQ(static_cast<unsigned char>(bytes[3]), u >> 24);
    // Empty files are valid.
    io::write_rays(dir / "e.bin", {});
    EXPECT_TRUE(io::read_rays(dir / "e.bin").empty());
}

TEST(RayFiles, WrongSizeNamesTheFile) {
    test::TempDir dir;
    test::write_text(dir / "rays.bin", std::string(100, '\0'));
    const std::string m = error_of([&] { io::read_rays(dir / "rays.bin"); });
    EXPECT_NE(m.find("rays.bin: size 100 is not a multiple of 32 bytes"), std::string::npos) << m;
    test::write_text(dir / "hits.bin", std::string(20, '\0'));
    const std::string h = error_of([&] { io::read_hits(dir / "hits.bin"); });
    EXPECT_NE(h.find("hits.bin: size 20 is not a multiple of 16 bytes"), std::string::npos) << h;
    EXPECT_NE(error_of([&] { io::read_rays(dir / "missing.bin"); }).find("missing.bin"), std::string::npos);
    EXPECT_THROW(io::read_hits(dir.path()), simdbvh::Error);
}

TEST(RayFiles, AtomicWriteLeavesEarlierFileOnFailure) {
    test::TempDir dir;
    const std::vector<Ray> first(2), second(5);
    // Nonexistent folder: error naming the file, nothing created.
    EXPECT_NE(error_of([&] { io::write_rays(dir / "no/such/dir/r.bin", first); }).find("r.bin"), std::string::npos);
    EXPECT_FALSE(fs::exists(dir / "no"));
    // Target is a non-empty folder: rename fails; the temp file is removed.
    fs::create_directories(dir / "occupied" / "x");
    EXPECT_THROW(io::write_rays(dir / "occupied", first), simdbvh::Error);
    EXPECT_TRUE(fs::is_directory(dir / "occupied" / "x"));
    for (const auto& e : fs::directory_iterator(dir.path()))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "temp left: " << e.path();
    // Read-only folder: the earlier file is untouched (root ignores permissions; skip that part then).
    fs::create_directories(dir / "ro");
    io::write_rays(dir / "ro" / "r.bin", first);
    fs::permissions(dir / "ro", fs::perms::owner_read | fs::perms::owner_exec);
    if (::geteuid() != 0) {
        EXPECT_THROW(io::write_rays(dir / "ro" / "r.bin", second), simdbvh::Error);
        EXPECT_EQ(io::read_rays(dir / "ro" / "r.bin").size(), 2u);
    }
    fs::permissions(dir / "ro", fs::perms::owner_all);
    // A write that fails half way (file size limit, works as root too): earlier file untouched, no temp left.
    {
        rlimit old{};
        ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
        const auto prev = std::signal(SIGXFSZ, SIG_IGN);
        rlimit lim = old;
        lim.rlim_cur = 4096;
        ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &lim), 0);
        const std::string msg = error_of([&] { io::write_rays(dir / "ro" / "r.bin", std::vector<Ray>(5000)); });
        ::setrlimit(RLIMIT_FSIZE, &old);
        std::signal(SIGXFSZ, prev);
        EXPECT_NE(msg.find("r.bin"), std::string::npos) << msg;
        EXPECT_EQ(io::read_rays(dir / "ro" / "r.bin").size(), 2u);
        std::size_t n = 0;
        for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir / "ro")) ++n;
        EXPECT_EQ(n, 1u) << "temporary file left behind";
    }
    // Success replaces the file whole.
    io::write_rays(dir / "ro" / "r.bin", second);
    EXPECT_EQ(io::read_rays(dir / "ro" / "r.bin").size(), 5u);
    std::size_t entries = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir / "ro")) ++entries;
    EXPECT_EQ(entries, 1u);
}
