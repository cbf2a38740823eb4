// An output is never a file the command reads, also when the command line names
// that file only through a scene: a JSON scene's meshes (relative to the JSON
// file), a named scene's cache file, a built-in scene's cached meshes, under
// another name (symlink, hard link). Every command with an output exits 2
// naming the input and leaves the file as it was.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "support/cli.h"
#include "support/scene.h"

namespace fs = std::filesystem;

namespace {

using test::CliRun;
using test::run_cli;

const char* kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
const char* kTrianglePly =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

class OutputNotInput : public testing::Test {
protected:
    void SetUp() override {
        test::write_text(dir_ / "floor.obj", kTriangleObj);
        test::write_text(dir_ / "scene.json", R"({"geometries": [{"mesh": "floor.obj"}]})");
        fs::create_directory(dir_ / "cache");
        test::write_text(dir_ / "cache" / "bunny.ply", kTrianglePly);
        ASSERT_EQ(run_cli("gen-rays --scene icosphere-1 --kind incoherent --count 64 --out " + p("r.bin")).status, 0);
        ASSERT_EQ(run_cli("gen-points --scene icosphere-1 --count 64 --out " + p("pts.bin")).status, 0);
        ASSERT_EQ(
            run_cli("trace --scene icosphere-1 --method bvh2 --rays " + p("r.bin") + " --out " + p("h.bin")).status, 0);
    }
    std::string p(const std::string& name) const { return (dir_ / name).string(); }
    // The command with the cache of this test; `file` (written afresh with `text`) must come out as it went in.
    void expect_refused(const std::string& args, const std::string& file, const std::string& text,
                        const std::string& input_named) const {
        test::write_text(file, text);  // in place: a hard link to it stays one
        const std::string before = test::read_bytes(file);
        const CliRun r = run_cli(args, "SIMDBVH_CACHE=" + p("cache") + " ");
        EXPECT_EQ(r.status, 2) << args << "\n" << r.output;
        EXPECT_NE(r.output.find("refusing to replace an input"), std::string::npos) << args << "\n" << r.output;
        EXPECT_NE(r.output.find(input_named), std::string::npos) << args << "\n" << r.output;
        EXPECT_EQ(test::read_bytes(file), before) << args;
    }
    test::TempDir dir_;
};

TEST_F(OutputNotInput, JsonScenesMeshIsAnInput) {
    // Run from another folder: the mesh is found relative to the JSON file, and so is the clash.
    expect_refused("trace --scene " + p("scene.json") + " --rays " + p("r.bin") + " --out " + p("floor.obj"),
                   p("floor.obj"), kTriangleObj, "geometries[0].mesh");
    fs::create_symlink("floor.obj", dir_ / "alias.obj");
    fs::create_hard_link(dir_ / "floor.obj", dir_ / "hard.obj");
    for (const char* out : {"alias.obj", "hard.obj"})
        expect_refused("trace --scene " + p("scene.json") + " --rays " + p("r.bin") + " --out " + p(out),
                       p("floor.obj"), kTriangleObj, "floor.obj");
    expect_refused("render --scene " + p("scene.json") + " --width 8 --height 8 --out " + p("floor.obj"),
                   p("floor.obj"), kTriangleObj, "floor.obj");
    expect_refused("gen-rays --scene " + p("scene.json") + " --kind incoherent --count 8 --out " + p("floor.obj"),
                   p("floor.obj"), kTriangleObj, "floor.obj");
}

TEST_F(OutputNotInput, NamedScenesCacheFileIsAnInputOfEveryCommand) {
    const std::string cached = p("cache/bunny.ply");
    const std::string r = " --rays " + p("r.bin"), pts = " --points " + p("pts.bin");
    const std::string bench = " --quick --rays 1024 --reps 1 --build-reps 0 --sample 16 --refit-frames 0 --no-report";
    const std::vector<std::string> commands{
        "trace --scene bunny" + r + " --out " + cached,
        "trace --scene room" + r + " --out " + cached,  // room's bunny (its teapot is not cached: not reached)
        "render --scene bunny --width 8 --height 8 --out " + cached,
        "gen-rays --scene bunny --kind primary --count 8 --out " + cached,
        "gen-rays --kind random --scene bunny --out " + cached,
        "gen-points --scene bunny --count 8 --out " + cached,
        "distance --scene bunny" + pts + " --out " + cached,
        "inside --scene bunny" + pts + " --out " + cached,
        "classify --scene bunny" + r + " --hits " + p("h.bin") + " --json " + cached,
        "bench --scene bunny --width-scenes none" + bench + " --json " + cached,
        "bench --scene icosphere-1 --width-scenes bunny" + bench + " --json " + cached,
        "bench --scene room --quick --rays 1024 --reps 1 --build-reps 0 --sample 16 --no-report --json " + cached,
        "panel --scene bunny --quick --rays 1024 --reps 1 --stats-rays 256 --no-report --json " + cached,
        "accuracy --family random --scene bunny --quick --no-embree --no-open3d --json " + cached,
        "bench --sweep --quick --reps 1 --build-reps 0 --budget-ms 1 --no-report --json " + cached,
    };
    for (const std::string& c : commands) expect_refused(c, cached, kTrianglePly, "the cache file of 'bunny'");
}

}  // namespace
