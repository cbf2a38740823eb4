// simdbvh info/trace on scene descriptions: a JSON scene traced by the CLI
// gives the API's brute-force scene hits; a bad scene file exits 2 with the
// file and the JSON path in the message and writes nothing.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "simdbvh/scene/rays.h"
#include "simdbvh/scene/scene_desc.h"
#include "simdbvh/scene/scene_hits.h"
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
    scene::write_rays(ray_file, r);
    std::vector<SceneHit> want(r.size());
    brute_force_intersect(scene::load_scene_json(scene), r, want);
    std::size_t n_hit = 0;
    for (const SceneHit& h : want) n_hit += h.hit();
    EXPECT_GT(n_hit, 500u);
    for (const char* method : {"bvh4", "bvh8", "bvh16", "brute"}) {
        const std::string out = path(std::string(method) + ".hits");
        const CliRun t = run_cli("trace --scene " + scene + " --rays " + ray_file + " --out " + out + " --method " + method);
        ASSERT_EQ(t.status, 0) << t.output;
        EXPECT_NE(t.output.find("isa"), std::string::npos);
        const auto got = scene::read_scene_hits(out);
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
    const auto r = scene::read_rays(ray_file);
    ASSERT_EQ(r.size(), 1000u);
    const CliRun t = run_cli("trace --scene " + scene + " --rays " + ray_file + " --out " + out);
    ASSERT_EQ(t.status, 0) << t.output;
    std::size_t n_hit = 0;
    for (const SceneHit& h : scene::read_scene_hits(out)) n_hit += h.hit();
    EXPECT_GT(n_hit, 100u);
    const CliRun d = run_cli("gen-rays --scene " + scene + " --kind diffuse --count 10 --out " + path("d.bin"));
    EXPECT_EQ(d.status, 2) << d.output;
    EXPECT_FALSE(fs::exists(path("d.bin")));
}

TEST_F(SceneCli, BadJsonExits2NamingThePathAndWritesNothing) {
    std::string bad = kScene;
    bad.replace(bad.find("\"scale\": [1, 2, 1]"), 18, "\"scale\": [1, 0, 1]");
    const std::string scene = write("bad.json", bad), ray_file = path("rays.bin"), out = path("out.hits");
    scene::write_rays(ray_file, rays(10));
    const CliRun t = run_cli("trace --scene " + scene + " --rays " + ray_file + " --out " + out);
    EXPECT_EQ(t.status, 2) << t.output;
    EXPECT_NE(t.output.find("bad.json: instances[1].transform: singular"), std::string::npos) << t.output;
    EXPECT_FALSE(fs::exists(out));
    const CliRun i = run_cli("info --scene " + scene);
    EXPECT_EQ(i.status, 2) << i.output;
    EXPECT_NE(i.output.find("instances[1].transform"), std::string::npos) << i.output;
}

}  // namespace
}  // namespace simdbvh
