// gen-rays on scenes with huge coordinates (a triangle spanning +-1e20, +-1e30,
// +-3.4e38; JSON scenes scaled by 1e30 or holding a sphere of radius 3.4e38):
// every ray has a finite origin and a finite unit direction, and the rays are
// aimed at the scene: a double-precision ray-triangle test (written here) finds
// hits, and the scene layer hits the JSON scenes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "simdbvh/io/ray_files.h"
#include "simdbvh/io/scene_hits.h"
#include "support/cli.h"
#include "support/scene.h"

namespace {

using test::CliRun;
using test::run_cli;

struct D3 {
    double x, y, z;
};
D3 sub(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 cross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 d3(simdbvh::Vec3 v) { return {v.x, v.y, v.z}; }

// Moller-Trumbore in double: products of coordinates up to 3.4e38 stay far below the double range.
bool crosses(const simdbvh::Ray& r, const D3 v[3]) {
    const D3 o = d3(r.org), d = d3(r.dir), e1 = sub(v[1], v[0]), e2 = sub(v[2], v[0]);
    const D3 p = cross(d, e2);
    const double det = dot(e1, p);
    if (det == 0.0) return false;
    const D3 s = sub(o, v[0]);
    const double u = dot(s, p) / det;
    if (u < 0.0 || u > 1.0) return false;
    const D3 q = cross(s, e1);
    const double w = dot(d, q) / det;
    if (w < 0.0 || u + w > 1.0) return false;
    return dot(e2, q) / det > 0.0;
}

// Finite origins, finite unit directions.
void expect_usable(const std::vector<simdbvh::Ray>& rays, const std::string& what) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const simdbvh::Ray& r = rays[i];
        ASSERT_TRUE(std::isfinite(r.org.x) && std::isfinite(r.org.y) && std::isfinite(r.org.z)) << what << " ray " << i;
        const double len = std::sqrt(dot(d3(r.dir), d3(r.dir)));
        ASSERT_NEAR(len, 1.0, 1e-5) << what << " ray " << i << " direction " << r.dir.x << " " << r.dir.y << " "
                                    << r.dir.z;
    }
}

class GenRaysHuge : public testing::Test {
protected:
    std::string p(const std::string& name) const { return (dir_ / name).string(); }
    std::vector<simdbvh::Ray> gen(const std::string& scene, const std::string& kind) const {
        const CliRun g = run_cli("gen-rays --scene " + scene + " --kind " + kind + " --count 1000 --out " + p("r.bin"));
        EXPECT_EQ(g.status, 0) << g.output;
        return g.status == 0 ? simdbvh::io::read_rays(p("r.bin")) : std::vector<simdbvh::Ray>{};
    }
    test::TempDir dir_;
};

TEST_F(GenRaysHuge, TrianglesOfEveryScaleGetRaysThatReachThem) {
    for (const char* s : {"1e20", "1e30", "3.4e38"}) {
        const double a = std::stod(s);
        const std::string v(s);
        test::write_text(dir_ / "huge.obj",
                         "v -" + v + " -" + v + " 0\nv " + v + " -" + v + " 0\nv 0 " + v + " " + v + "\nf 1 2 3\n");
        const D3 tri[3] = {{-a, -a, 0}, {a, -a, 0}, {0, a, a}};
        for (const char* kind : {"incoherent", "primary"}) {
            const std::string what = std::string(kind) + " rays at " + s;
            const auto rays = gen(p("huge.obj"), kind);
            ASSERT_EQ(rays.size(), 1000u) << what;
            expect_usable(rays, what);
            std::size_t hit = 0;
            for (const auto& r : rays) hit += crosses(r, tri);
            // Incoherent rays aim at random points of the bounds, half of which the slanted triangle covers
            // as seen from the origins; the camera frames the bounds.
            EXPECT_GT(hit, std::strcmp(kind, "incoherent") == 0 ? 200u : 50u) << what;
        }
    }
}

TEST_F(GenRaysHuge, HugeJsonScenesAreHit) {
    test::write_text(
        dir_ / "sphere.json",
        R"({"geometries": [{"spheres": [{"center": [0, 0, 0], "radius": 3.4e38}]}], "instances": [{"geometry": 0}]})");
    test::write_text(dir_ / "scaled.json",
                     R"({"geometries": [{"mesh": "icosphere-2"}], "instances": [{"geometry": 0, "scale": 1e30}]})");
    for (const char* scene : {"sphere.json", "scaled.json"})
        for (const char* kind : {"incoherent", "primary"}) {
            const std::string what = std::string(kind) + " rays on " + scene;
            const auto rays = gen(p(scene), kind);
            ASSERT_EQ(rays.size(), 1000u) << what;
            expect_usable(rays, what);
            const CliRun t = run_cli("trace --scene " + p(scene) + " --rays " + p("r.bin") + " --out " + p("h.bin"));
            ASSERT_EQ(t.status, 0) << t.output;
            std::size_t hit = 0;
            for (const simdbvh::SceneHit& h : simdbvh::io::read_scene_hits(p("h.bin"))) hit += h.hit();
            EXPECT_GT(hit, 100u) << what;
        }
}

}  // namespace
