// simdbvh build --out FILE.simdbvh, then trace and info with --scene FILE:
// the saved tree traces to the same hit file as a fresh build; a bad file
// exits 2 naming the file and writes no output; build never replaces its input.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "support/cli.h"
#include "support/scene.h"

namespace {

using test::CliRun;
using test::run_cli;

class BuildSaved : public testing::Test {
protected:
    void SetUp() override {
        ASSERT_EQ(run_cli("gen-rays --scene icosphere-3 --kind incoherent --count 2000 --out " + p("r.bin")).status, 0);
    }
    std::string p(const std::string& name) const { return (dir_ / name).string(); }
    test::TempDir dir_;
};

TEST_F(BuildSaved, TraceOfTheSavedTreeWritesTheBuiltTreesHits) {
    for (const std::string nodes : {"", " --nodes quantized"}) {
        const CliRun b = run_cli("build --scene icosphere-3 --method bvh8" + nodes + " --out " + p("t.simdbvh"));
        ASSERT_EQ(b.status, 0) << b.output;
        EXPECT_NE(b.output.find("wrote"), std::string::npos) << b.output;
        const CliRun fresh = run_cli("trace --scene icosphere-3 --method bvh8" + nodes + " --isa scalar --rays " +
                                     p("r.bin") + " --out " + p("want.bin"));
        ASSERT_EQ(fresh.status, 0) << fresh.output;
        const CliRun saved = run_cli("trace --scene " + p("t.simdbvh") + " --isa scalar --rays " + p("r.bin") +
                                     " --out " + p("got.bin"));
        ASSERT_EQ(saved.status, 0) << saved.output;
        EXPECT_NE(saved.output.find("method bvh8"), std::string::npos) << saved.output;
        EXPECT_EQ(test::read_bytes(p("got.bin")), test::read_bytes(p("want.bin")));
        const CliRun info = run_cli("info --scene " + p("t.simdbvh"));
        ASSERT_EQ(info.status, 0) << info.output;
        EXPECT_NE(info.output.find(nodes.empty() ? "tree         bvh8\n" : "bvh8 (quantized nodes)"), std::string::npos)
            << info.output;
        EXPECT_NE(info.output.find("triangles    1280"), std::string::npos) << info.output;
        EXPECT_NE(info.output.find("checksum ok"), std::string::npos) << info.output;
    }
    // Another --method than the file holds is refused.
    const CliRun other =
        run_cli("trace --scene " + p("t.simdbvh") + " --method bvh4 --rays " + p("r.bin") + " --out " + p("x.bin"));
    EXPECT_EQ(other.status, 2) << other.output;
    EXPECT_NE(other.output.find("not the --method bvh4"), std::string::npos) << other.output;
    EXPECT_FALSE(std::filesystem::exists(p("x.bin")));
}

TEST_F(BuildSaved, BadFileExitsTwoNamingItAndWritesNothing) {
    ASSERT_EQ(run_cli("build --scene icosphere-2 --out " + p("t.simdbvh")).status, 0);
    std::string bytes = test::read_bytes(p("t.simdbvh"));
    bytes[bytes.size() - 7] ^= 2;
    test::write_text(p("bad.simdbvh"), bytes);
    for (const std::string cmd :
         {"trace --rays " + p("r.bin") + " --out " + p("h.bin") + " --scene ", std::string("info --scene ")}) {
        const CliRun r = run_cli(cmd + p("bad.simdbvh"));
        EXPECT_EQ(r.status, 2) << r.output;
        EXPECT_NE(r.output.find(p("bad.simdbvh") + ": checksum mismatch"), std::string::npos) << r.output;
    }
    test::write_text(p("short.simdbvh"), bytes.substr(0, 1000));
    const CliRun r = run_cli("trace --rays " + p("r.bin") + " --out " + p("h.bin") + " --scene " + p("short.simdbvh"));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find(p("short.simdbvh") + ": truncated"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(p("h.bin")));
}

TEST_F(BuildSaved, BuildRefusesItsInputAndOtherMethods) {
    test::write_text(p("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string before = test::read_bytes(p("tri.obj"));
    const CliRun same = run_cli("build --scene " + p("tri.obj") + " --out " + p("tri.obj"));
    EXPECT_EQ(same.status, 2) << same.output;
    EXPECT_NE(same.output.find("refusing to replace an input"), std::string::npos) << same.output;
    EXPECT_EQ(test::read_bytes(p("tri.obj")), before);
    const CliRun brute = run_cli("build --scene " + p("tri.obj") + " --method brute --out " + p("b.simdbvh"));
    EXPECT_EQ(brute.status, 2) << brute.output;
    EXPECT_FALSE(std::filesystem::exists(p("b.simdbvh")));
    const CliRun q4 =
        run_cli("build --scene " + p("tri.obj") + " --method bvh4 --nodes quantized --out " + p("q.simdbvh"));
    EXPECT_EQ(q4.status, 2) << q4.output;
    EXPECT_FALSE(std::filesystem::exists(p("q.simdbvh")));
}

}  // namespace
