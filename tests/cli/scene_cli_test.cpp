// simdbvh info/trace on scene descriptions: a JSON scene traced by the CLI
// gives the API's brute-force scene hits; a bad scene file exits 2 with the
// file and the JSON path in the message and writes nothing; bench --scene
// writes a report whose JSON (parsed here with nlohmann-json) holds ours bit
// for bit against the brute force, the tessellation and precision studies and
// the planes comparison.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <string>

#include "simdbvh/workloads/rays.h"
#include "simdbvh/io/ray_files.h"
#include "simdbvh/workloads/scene_desc.h"
#include "simdbvh/io/scene_hits.h"
#include "support/cli.h"

namespace fs = std::filesystem;

namespace simdbvh {
namespace {

using test::CliRun;
using test::run_cli;

class SceneCli : public testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("simdbvh_scene_cli_" + std::to_string(::getpid()) + "_" +
                                            testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(path(name)) << text;
        return path(name);
    }
    fs::path dir_;
};

const char* kScene = R"({
  "geometries": [
    {"name": "ball", "mesh": "icosphere-2"},
    {"spheres": [{"center": [0, 0, 0], "radius": 0.5}, {"center": [1, 1, 0], "radius": 0.25}]},
    {"boxes": [{"min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]}]}],
  "instances": [
    {"geometry": "ball", "translate": [-2, 0, 0], "scale": 0.8},
    {"geometry": "ball", "translate": [2, 0, 0], "rotate": {"axis": [1, 1, 0], "degrees": 30}, "scale": [1, 2, 1]},
    {"geometry": 1, "translate": [0, 2, 0]},
    {"geometry": 2, "transform": [[1, 0.5, 0, 0], [0, 1, 0, -2], [0, 0, 1, 0]]}],
  "planes": [{"point": [0, -4, 0], "normal": [0, 1, 0]}]
})";

std::vector<Ray> rays(std::size_t n) {
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Ray> out;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 o{8 * u(rng), 8 * u(rng), 8 * u(rng)}, t{3 * u(rng), 3 * u(rng), u(rng)};
        out.push_back(Ray{o, 0.0f, t - o, INFINITY});
    }
    return out;
}

TEST_F(SceneCli, TraceJsonSceneMatchesTheApi) {
    const std::string scene = write("scene.json", kScene), ray_file = path("rays.bin");
    const auto r = rays(2000);
    io::write_rays(ray_file, r);
    std::vector<SceneHit> want(r.size());
    brute_force_intersect(workloads::load_scene_json(scene), r, want);
    std::size_t n_hit = 0;
    for (const SceneHit& h : want) n_hit += h.hit();
    EXPECT_GT(n_hit, 500u);
    for (const char* method : {"bvh4", "bvh8", "bvh16", "brute"}) {
        const std::string out = path(std::string(method) + ".hits");
        const CliRun t =
            run_cli("trace --scene " + scene + " --rays " + ray_file + " --out " + out + " --method " + method);
        ASSERT_EQ(t.status, 0) << t.output;
        EXPECT_NE(t.output.find("isa"), std::string::npos);
        const auto got = io::read_scene_hits(out);
        ASSERT_EQ(got.size(), want.size());
        for (std::size_t i = 0; i < got.size(); ++i) ASSERT_TRUE(got[i] == want[i]) << method << " ray " << i;
    }
    const CliRun info = run_cli("info --scene " + scene);
    ASSERT_EQ(info.status, 0) << info.output;
    EXPECT_NE(info.output.find("instances    4"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("planes       1"), std::string::npos) << info.output;
}

TEST_F(SceneCli, GenRaysAimsAtTheSceneBounds) {
    const std::string scene = write("scene.json", kScene), ray_file = path("rays.bin"), out = path("out.hits");
    const CliRun g = run_cli("gen-rays --scene " + scene + " --kind incoherent --count 1000 --out " + ray_file);
    ASSERT_EQ(g.status, 0) << g.output;
    const auto r = io::read_rays(ray_file);
    ASSERT_EQ(r.size(), 1000u);
    const CliRun t = run_cli("trace --scene " + scene + " --rays " + ray_file + " --out " + out);
    ASSERT_EQ(t.status, 0) << t.output;
    std::size_t n_hit = 0;
    for (const SceneHit& h : io::read_scene_hits(out)) n_hit += h.hit();
    EXPECT_GT(n_hit, 100u);
    const CliRun d = run_cli("gen-rays --scene " + scene + " --kind diffuse --count 10 --out " + path("d.bin"));
    EXPECT_EQ(d.status, 2) << d.output;
    EXPECT_FALSE(fs::exists(path("d.bin")));
}

TEST_F(SceneCli, BenchOnASceneWritesTheSceneReport) {
    const std::string scene = write("scene.json", kScene), dir = path("report");
    const CliRun b =
        run_cli("bench --scene " + scene + " --quick --rays 4096 --reps 1 --build-reps 1 --sample 64 --report " + dir);
    ASSERT_EQ(b.status, 0) << b.output;
    std::ifstream f(dir + "/bench.json");
    const nlohmann::json j = nlohmann::json::parse(f);
    EXPECT_EQ(j["instances"], 4);
    EXPECT_EQ(j["planes"], 1);
    std::set<std::string> methods;
    for (const auto& s : j["speed"]) {
        methods.insert(s["method"].get<std::string>());
        EXPECT_GT(s["mrays_per_s"].get<double>(), 0.0) << s.dump();
    }
    EXPECT_EQ(methods,
              (std::set<std::string>{"BVH8 scene (child-corners)", "BVH8 scene (corners)", "Embree instanced"}));
    EXPECT_EQ(j["speed"].size(), 3u * 4u);  // primary/incoherent x closest/any
    int brute_rows = 0;
    for (const auto& a : j["agreement"]) {
        const std::string m = a["method"];
        if (m == "brute force" || m == "BVH8 scene (corners)") {  // our paths: the same bits on every ray
            brute_rows += m == "brute force";
            EXPECT_EQ(a["same_bits"], a["count"]) << a.dump();
            EXPECT_GT(a["count"].get<int>(), 0);
        }
        if (m == "Embree instanced") {
            EXPECT_GE(a["same"].get<double>(), 0.99 * a["count"].get<double>()) << a.dump();
            // Every ray where Embree differs from us is refereed in double: ours is never wrong there, beyond
            // float rounding (marginal).
            EXPECT_EQ(a["refereed"], a["differ"]) << a.dump();
            const auto& o = a["ours"];
            EXPECT_EQ(o["false_miss"].get<int>() + o["false_hit"].get<int>() + o["farther_hit"].get<int>() +
                          o["t_error"].get<int>(),
                      o["marginal"].get<int>())
                << a.dump();
            EXPECT_EQ(o["agree"].get<int>() + o["tie"].get<int>() + o["marginal"].get<int>(), a["differ"].get<int>());
        }
    }
    EXPECT_EQ(brute_rows, 2);
    // Tessellation: two analytic rows, then icosphere levels 0..5 with 20 * 4^level triangles per sphere (the
    // scene's 2 spheres), each level's median hit-point error below the previous one's (the chords shrink 4x).
    const auto& t = j["tessellation"];
    ASSERT_EQ(t.size(), 8u);
    EXPECT_EQ(j["tessellation_spheres"], 2);
    for (int level = 0; level < 6; ++level) {
        const auto& row = t[std::size_t(level) + 2];
        EXPECT_EQ(row["triangles"].get<std::size_t>(), 2u * 20u << (2 * level));
        if (level > 0) {
            EXPECT_LT(row["median_err"].get<double>(), 0.5 * t[std::size_t(level) + 1]["median_err"].get<double>());
        }
    }
    EXPECT_LT(t[0]["median_err"].get<double>(), 1e-6);  // analytic: float rounding of t only
    // Precision: the robust test never misses; the naive float quadratic does once the sphere is far away.
    double naive_misses = 0;
    for (const auto& p : j["sphere_precision"]) {
        EXPECT_EQ(p["miss_robust"].get<double>(), 0.0) << p.dump();
        naive_misses += p["miss_naive"].get<double>();
    }
    EXPECT_GT(naive_misses, 0.5);
    // Planes: the one axis-aligned plane put in our tree as a flat box gives the same t on (nearly) every ray
    // (the slab test's t is the plane test's; Embree's float quads differ in the last bits, so not checked).
    EXPECT_EQ(j["planes_in_tree"], 1);
    int ours = 0;
    for (const auto& p : j["plane_rows"])
        if (p["method"].get<std::string>().starts_with("BVH8")) {
            ++ours;
            EXPECT_GE(p["same_t"].get<double>(), 0.99 * p["count"].get<double>()) << p.dump();
        }
    EXPECT_EQ(ours, 4);
    EXPECT_TRUE(fs::exists(dir + "/report.md"));
    EXPECT_TRUE(fs::exists(dir + "/scene_render.png"));
    // Options of the mesh bench that a scene bench would ignore are refused, before anything is written.
    const std::string dir2 = path("report2");
    const CliRun refused = run_cli("bench --scene " + scene + " --threads 2 --report " + dir2);
    EXPECT_EQ(refused.status, 2) << refused.output;
    EXPECT_NE(refused.output.find("--threads does not apply"), std::string::npos) << refused.output;
    EXPECT_FALSE(fs::exists(dir2));
}

TEST_F(SceneCli, BadJsonExits2NamingThePathAndWritesNothing) {
    std::string bad = kScene;
    bad.replace(bad.find("\"scale\": [1, 2, 1]"), 18, "\"scale\": [1, 0, 1]");
    const std::string scene = write("bad.json", bad), ray_file = path("rays.bin"), out = path("out.hits");
    io::write_rays(ray_file, rays(10));
    const CliRun t = run_cli("trace --scene " + scene + " --rays " + ray_file + " --out " + out);
    EXPECT_EQ(t.status, 2) << t.output;
    EXPECT_NE(t.output.find("bad.json: instances[1].transform: singular"), std::string::npos) << t.output;
    EXPECT_FALSE(fs::exists(out));
    const CliRun i = run_cli("info --scene " + scene);
    EXPECT_EQ(i.status, 2) << i.output;
    EXPECT_NE(i.output.find("instances[1].transform"), std::string::npos) << i.output;
    // An instance scaled past the float range: refused up front (it used to stop the build with an internal error).
    const std::string huge = write("huge.json", R"({"geometries": [{"boxes": [{"min": [-3e38, -3e38, -3e38],
        "max": [3e38, 3e38, 3e38]}]}], "instances": [{"geometry": 0}, {"geometry": 0}, {"geometry": 0, "scale": 1e30}]})");
    const CliRun h = run_cli("trace --scene " + huge + " --rays " + ray_file + " --out " + out);
    EXPECT_EQ(h.status, 2) << h.output;
    EXPECT_NE(h.output.find("huge.json: instances[2].transform: takes geometries[0] beyond the float range"),
              std::string::npos)
        << h.output;
    EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace simdbvh
