// The bad-input rules (docs/accuracy.md, "Bad input and robustness";
// docs/cli.md#bad-input) through the simdbvh executable (SIMDBVH_CLI): each
// row's message and exit status. The loaders' own messages are checked in
// tests/scene (load_errors_test); here: what a user of the CLI sees.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "simdbvh/kernels/ray.h"
#include "simdbvh/io/ray_files.h"
#include "support/cli.h"
#include "support/scene.h"

namespace fs = std::filesystem;

namespace simdbvh {
namespace {

using test::CliRun;
using test::run_cli;

class BadInput : public testing::Test {
protected:
    void SetUp() override {
        if (!std::getenv("SIMDBVH_CLI")) GTEST_SKIP() << "SIMDBVH_CLI is not set (built without the tools)";
        rays_ = (dir_ / "r.bin").string();
        ASSERT_EQ(run_cli("gen-rays --scene icosphere-2 --kind incoherent --count 200 --out " + rays_).status, 0);
    }
    std::string file(const std::string& name, const std::string& bytes) {
        const fs::path p = dir_ / name;
        std::ofstream(p, std::ios::binary) << bytes;
        return p.string();
    }
    // trace must fail with status 2, name the file and every part, and leave no output.
    void expect_trace_error(const std::string& mesh, std::initializer_list<const char*> parts) {
        const std::string out = (dir_ / "never.hits").string();
        const CliRun t = run_cli("trace --scene " + mesh + " --rays " + rays_ + " --out " + out);
        EXPECT_EQ(t.status, 2) << mesh << "\n" << t.output;
        EXPECT_NE(t.output.find("simdbvh: "), std::string::npos) << t.output;
        EXPECT_NE(t.output.find(fs::path(mesh).filename().string()), std::string::npos) << t.output;
        for (const char* p : parts) EXPECT_NE(t.output.find(p), std::string::npos) << "'" << p << "' in\n" << t.output;
        EXPECT_FALSE(fs::exists(out));
    }
    test::TempDir dir_;
    std::string rays_;
};

const std::string kPlyHead =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

TEST_F(BadInput, MalformedFilesOfEveryFormat) {
    expect_trace_error(file("trunc.ply", kPlyHead + "0 0 0\n1 0 0\n"), {":3:"});
    expect_trace_error(file("header.ply", "plx\nformat ascii 1.0\nend_header\n"), {":1:", "not a PLY"});
    expect_trace_error(file("junk.ply", kPlyHead + "0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n"), {":11:", "'zero'"});
    expect_trace_error(file("junk.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0 junk\nf 1 2 3\n"), {":3:", "'junk'"});
    expect_trace_error(file("short.obj", "v 0 0\n"), {":1:"});
    expect_trace_error(
        file("trunc.stl", std::string(80, 'x') + std::string("\x05\x00\x00\x00", 4) + std::string(60, '\0')), {});
    expect_trace_error(file("junk.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zero\n"), {"'zero'"});
    expect_trace_error(file("trunc.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n"), {});
    expect_trace_error(file("junk.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 x\n3 0 1 2\n"), {"'x'"});
    expect_trace_error(file("unknown.3ds", "whatever"), {"unknown mesh format"});
    expect_trace_error((dir_ / "missing.ply").string(), {});
}

TEST_F(BadInput, AssimpInvalidModels) {
    const fs::path dir = "/usr/share/assimp/models/invalid";
    if (!fs::exists(dir)) GTEST_SKIP() << "assimp-testmodels not installed (apt-get install assimp-testmodels)";
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (!e.is_regular_file() || e.path().filename() == "readme.txt") continue;
        SCOPED_TRACE(e.path().string());
        ++n;
        expect_trace_error(e.path().string(), {});
    }
    EXPECT_GE(n, 5u);
}

TEST_F(BadInput, CountsLargerThanTheFileFailBeforeAllocating) {
    // 3 vertices present, 5e9 faces declared (more than the 32-bit triangle ids hold).
    expect_trace_error(file("big.ply",
                            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                            "property float z\nelement face 5000000000\nproperty list uchar int "
                            "vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                       {":7:", "5000000000"});
    expect_trace_error(file("big.off", "OFF\n1000000000 1000000000 0\n0 0 0\n"), {"1000000000"});
    std::string stl(80, ' ');
    stl += std::string("\xff\xff\xff\x7f", 4);  // 2^31 - 1 facets, none present
    stl += std::string(50, '\0');
    expect_trace_error(file("big.stl", stl), {"2147483647"});
}

TEST_F(BadInput, NonFiniteVerticesRejectedWithCountAndFirstIndexOrDropped) {
    const std::string mesh = file("nan.obj",
                                  "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 nan 0\nv inf 1 0\nv 0 0 1\n"
                                  "f 1 2 3\nf 1 4 3\nf 2 5 6\nf 1 2 6\n");
    expect_trace_error(mesh, {"2 vertices", "vertex 3"});
    const std::string out = (dir_ / "o.hits").string();
    const CliRun d = run_cli("trace --scene " + mesh + " --rays " + rays_ + " --out " + out + " --drop-invalid");
    EXPECT_EQ(d.status, 0) << d.output;
    EXPECT_NE(d.output.find("dropped 2 triangles"), std::string::npos) << d.output;
    EXPECT_EQ(io::read_hits(out).size(), 200u);
}

TEST_F(BadInput, OutOfRangeIndexNamesTheTriangle) {
    expect_trace_error(file("idx.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n"), {":5:", "triangle 1", "9"});
    expect_trace_error(file("idx.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"), {"triangle 0", "index 3"});
}

TEST_F(BadInput, EmptyMeshEveryRayMisses) {
    for (const auto& [name, text] : {std::pair<std::string, std::string>{"e.obj", "# nothing but a comment\n"},
                                     {"e.ply",
                                      "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float "
                                      "y\nproperty float z\nelement face 0\nproperty list uchar int "
                                      "vertex_indices\nend_header\n"},
                                     {"e.off", "OFF\n0 0 0\n"}}) {
        const std::string mesh = file(name, text), out = (dir_ / (name + ".hits")).string();
        for (const char* m : {"bvh2", "bvh8", "brute", "embree"}) {
            const CliRun t = run_cli("trace --scene " + mesh + " --rays " + rays_ + " --out " + out + " --method " + m);
            ASSERT_EQ(t.status, 0) << name << " " << m << "\n" << t.output;
            for (const Hit& h : io::read_hits(out)) ASSERT_EQ(h, Hit{}) << name << " " << m;
        }
    }
}

TEST_F(BadInput, InvalidRaysMissOnEveryMethod) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const std::vector<Ray> bad = {
        {{0, 0, 0}, 0.0f, {0, 0, 0}, inf},   {{0, 0, 0}, 0.0f, {nan, 0, 1}, inf}, {{0, 0, 0}, 0.0f, {inf, 0, 1}, inf},
        {{nan, 0, 0}, 0.0f, {0, 0, 1}, inf}, {{inf, 0, 0}, 0.0f, {0, 0, 1}, inf}, {{0, 0, 0}, 2.0f, {0, 0, 1}, 1.0f},
        {{0, 0, 0}, nan, {0, 0, 1}, inf},    {{0, 0, 0}, 0.0f, {0, 0, 1}, inf},  // the last one is valid: a hit
    };
    const std::string rays = (dir_ / "bad_rays.bin").string(), out = (dir_ / "o.hits").string();
    io::write_rays(rays, bad);
    for (const char* m : {"bvh2", "bvh8", "brute", "embree"})
        for (const char* extra : {"", " --any-hit", " --test moller", " --box plain"}) {
            if (std::string(extra) == " --box plain" && std::string(m) != "bvh2") continue;
            if (std::string(extra) == " --test moller" && std::string(m) == "embree") continue;  // not Embree's
            const CliRun t = run_cli(std::string("trace --scene icosphere-2 --rays ") + rays + " --out " + out +
                                     " --method " + m + extra);
            ASSERT_EQ(t.status, 0) << m << extra << "\n" << t.output;
            const auto hits = io::read_hits(out);
            ASSERT_EQ(hits.size(), bad.size());
            for (std::size_t i = 0; i + 1 < hits.size(); ++i) EXPECT_EQ(hits[i], Hit{}) << m << extra << " ray " << i;
            EXPECT_TRUE(hits.back().hit()) << m << extra;
        }
}

TEST_F(BadInput, PlainBoxIsABvh2VariantOnly) {
    const CliRun t = run_cli("trace --scene icosphere-1 --rays " + rays_ + " --out x.hits --method bvh8 --box plain");
    EXPECT_EQ(t.status, 2);
    EXPECT_NE(t.output.find("--box plain"), std::string::npos) << t.output;
    const CliRun u = run_cli("trace --scene icosphere-1 --rays " + rays_ + " --out x.hits --box wobbly");
    EXPECT_EQ(u.status, 2);
    EXPECT_NE(u.output.find("wobbly"), std::string::npos) << u.output;
}

// Output write failure: the file size limit makes the write fail (EFBIG, with
// SIGXFSZ ignored); the command exits 2 and the earlier output is untouched.
TEST_F(BadInput, FailedWriteLeavesEarlierOutputUntouched) {
    const std::string out = (dir_ / "keep.hits").string(), many = (dir_ / "many.bin").string();
    ASSERT_EQ(run_cli("gen-rays --scene icosphere-2 --kind incoherent --count 4000 --out " + many).status, 0);
    ASSERT_EQ(run_cli("trace --scene icosphere-2 --rays " + rays_ + " --out " + out).status, 0);
    const std::string before = test::read_bytes(out);
    // 4000 hits = 64000 bytes > 16 blocks (512 or 1024 bytes, by shell); the ray file is only read.
    const CliRun t =
        run_cli("trace --scene icosphere-2 --rays " + many + " --out " + out, "trap '' XFSZ; ulimit -f 16; ");
    EXPECT_EQ(t.status, 2) << t.output;
    EXPECT_NE(t.output.find(out), std::string::npos) << t.output;
    EXPECT_EQ(test::read_bytes(out), before);
    for (const auto& e : fs::directory_iterator(dir_.path()))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "stray " << e.path();
    // A missing folder: a clear error, nothing written.
    const CliRun m =
        run_cli("trace --scene icosphere-2 --rays " + rays_ + " --out " + (dir_ / "no/such/dir/x.hits").string());
    EXPECT_EQ(m.status, 2);
    EXPECT_NE(m.output.find("no/such/dir"), std::string::npos) << m.output;
    // gen-rays --mesh-out and accuracy --json fail the same way.
    const CliRun g = run_cli("gen-rays --kind grazing --quick --out " + (dir_ / "g.bin").string() + " --mesh-out " +
                             (dir_ / "no/g.ply").string());
    EXPECT_EQ(g.status, 2) << g.output;
    EXPECT_FALSE(fs::exists(dir_ / "g.bin"));
}

TEST_F(BadInput, FamilyKindsOwnTheirScene) {
    const std::string out = (dir_ / "f.bin").string(), mesh = (dir_ / "f.ply").string();
    const CliRun a = run_cli("gen-rays --kind watertight --scene bunny --out " + out);
    EXPECT_EQ(a.status, 2);
    EXPECT_NE(a.output.find("--mesh-out"), std::string::npos) << a.output;
    const CliRun b = run_cli("gen-rays --kind needles --quick --case nope --out " + out);
    EXPECT_EQ(b.status, 2);
    EXPECT_NE(b.output.find("needles/aspect1e7"), std::string::npos) << "lists the cases: " << b.output;
    const CliRun c =
        run_cli("gen-rays --kind watertight --quick --case watertight/torus --out " + out + " --mesh-out " + mesh);
    ASSERT_EQ(c.status, 0) << c.output;
    const CliRun t = run_cli("trace --scene " + mesh + " --rays " + out + " --out " + (dir_ / "f.hits").string());
    ASSERT_EQ(t.status, 0) << t.output;
    for (const Hit& h : io::read_hits(dir_ / "f.hits")) ASSERT_TRUE(h.hit()) << "watertight rays must hit";
}

}  // namespace
}  // namespace simdbvh
