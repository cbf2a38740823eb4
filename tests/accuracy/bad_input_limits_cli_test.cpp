// Bad input through the CLI (docs/cli.md#bad-input): a bad SIMDBVH_ISA has one "simdbvh: " prefix,
// /dev/zero is not a ray file, out of memory names the mesh file.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "support/cli.h"
#include "support/sanitizer.h"
#include "support/scene.h"

namespace fs = std::filesystem;

namespace {

class BadInputLimits : public testing::Test {
protected:
    void SetUp() override {
        if (!std::getenv("SIMDBVH_CLI")) GTEST_SKIP() << "SIMDBVH_CLI is not set (built without the tools)";
        rays_ = (dir_ / "r.bin").string();
        ASSERT_EQ(test::run_cli("gen-rays --scene icosphere-2 --kind incoherent --count 200 --out " + rays_).status, 0);
    }
    test::TempDir dir_;
    std::string rays_;
};

TEST_F(BadInputLimits, BadIsaHasOnePrefix) {
    const test::CliRun t = test::run_cli(
        "trace --scene icosphere-1 --rays " + rays_ + " --out " + (dir_ / "h").string(), "SIMDBVH_ISA=sse9 ");
    EXPECT_EQ(t.status, 2) << t.output;
    EXPECT_NE(t.output.find("simdbvh: SIMDBVH_ISA='sse9'"), std::string::npos) << t.output;
    EXPECT_EQ(t.output.find("simdbvh: simdbvh:"), std::string::npos) << t.output;
}

TEST_F(BadInputLimits, DevZeroIsNotARayFile) {
    const std::string out = (dir_ / "h").string();
    const test::CliRun t = test::run_cli("trace --scene icosphere-1 --rays /dev/zero --out " + out);
    EXPECT_EQ(t.status, 2) << t.output;
    EXPECT_NE(t.output.find("/dev/zero: is not a regular file"), std::string::npos) << t.output;
    EXPECT_FALSE(fs::exists(out));
}

// An honest OBJ of 512 MiB (gzip members of "v 0 0 0" lines) under a 384 MiB address-space limit.
TEST_F(BadInputLimits, OutOfMemoryNamesTheFile) {
    SIMDBVH_SKIP_ADDRESS_LIMIT_UNDER_SANITIZER();
    std::string lines;
    for (int i = 0; i < (8 << 20) / 8; ++i) lines += "v 0 0 0\n";
    const fs::path mesh = dir_ / "big.obj.gz";
    gzFile gz = gzopen(mesh.c_str(), "wb9");
    ASSERT_NE(gz, nullptr);
    for (int m = 0; m < 64; ++m) ASSERT_EQ(gzwrite(gz, lines.data(), unsigned(lines.size())), int(lines.size()));
    gzclose(gz);
    const std::string out = (dir_ / "h").string();
    const test::CliRun t =
        test::run_cli("trace --scene " + mesh.string() + " --rays " + rays_ + " --out " + out, "ulimit -v 393216; ");
    EXPECT_EQ(t.status, 2) << t.output;
    EXPECT_NE(t.output.find("big.obj.gz"), std::string::npos) << t.output;
    EXPECT_NE(t.output.find("out of memory"), std::string::npos) << t.output;
    EXPECT_FALSE(fs::exists(out));
}

}  // namespace
