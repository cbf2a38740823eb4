// Through the CLI: `simdbvh info` on finite meshes whose boxes overflow float
// areas (crash.obj, a triangle spanning 2e19, and coordinates up to +-3e38)
// exits 0 with finite SAH costs (it used to die with SIGSEGV, exit 139).
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "support/cli.h"
#include "support/huge_meshes.h"
#include "support/scene.h"

namespace {

class HugeCoordinatesCli : public testing::Test {
protected:
    void SetUp() override {
        if (!std::getenv("SIMDBVH_CLI")) GTEST_SKIP() << "SIMDBVH_CLI is not set (built without the tools)";
    }
    test::TempDir dir_;
};

void expect_info_ok(const std::string& file, const std::string& options) {
    const test::CliRun r = test::run_cli("info --scene " + file + options);
    EXPECT_EQ(r.status, 0) << options << "\n" << r.output;
    EXPECT_NE(r.output.find("bvh8"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find(" inf"), std::string::npos) << "a cost is not finite:\n" << r.output;
    EXPECT_EQ(r.output.find("nan"), std::string::npos) << "a cost is not finite:\n" << r.output;
}

TEST_F(HugeCoordinatesCli, InfoOnCrashObjExitsZero) {
    const auto file = dir_ / "crash.obj";
    test::write_obj(file, test::huge_triangle_mesh());
    for (const char* o : {"", " --collapse greedy", " --builder sah-sweep"}) expect_info_ok(file.string(), o);
}

TEST_F(HugeCoordinatesCli, InfoOnCoordinatesNearFloatMaxExitsZero) {
    const auto file = dir_ / "extreme.obj";
    test::write_obj(file, test::extreme_mesh());
    for (const char* o : {"", " --collapse greedy", " --builder sah-sweep"}) expect_info_ok(file.string(), o);
}

}  // namespace
