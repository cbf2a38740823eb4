// SPDX-License-Identifier: MIT
// The JSON the commands write (bench, panel, accuracy) parses, whatever the
// paths and arguments hold (quotes, backslashes, a tab, a byte that is not
// UTF-8) and whatever the results are (the direction-scale family gives
// infinite t errors: null in the JSON). Parsed with nlohmann-json, not with
// the code under test.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "inside_points.h"
#include "simdbvh/workloads/scenes.h"
#include "support/cli.h"

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

// A folder and file names that break hand-written JSON and shell quoting.
const std::string kNasty = "we\"ird\\ 'name\t";

std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

class JsonReports : public testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("simdbvh_json_" + std::to_string(::getpid()) + "_" +
                testing::UnitTest::GetInstance()->current_test_info()->name()) /
               kNasty;
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_.parent_path()); }
    // A tetrahedron as an OFF file under a nasty name.
    std::string tetra() const {
        const fs::path p = dir_ / (kNasty + "tetra\xff.off");
        std::ofstream(p) << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
        return p.string();
    }
    static Json parse(const fs::path& p) {
        std::ifstream f(p);
        EXPECT_TRUE(f.good()) << p;
        return Json::parse(f);  // throws, failing the test, on invalid JSON
    }
    fs::path dir_;
};

TEST_F(JsonReports, AccuracyWithInfiniteErrorsParses) {
    const fs::path json = dir_ / "acc\"u\\racy.json";
    const std::string args =
        "accuracy --quick --family direction-scale --no-embree --json " + shell_quote(json.string());
    const test::CliRun r = test::run_cli(args);
    ASSERT_EQ(r.status, 0) << r.output;
    const Json j = parse(json);
    EXPECT_EQ(j["command_line"].get<std::string>(),
              "simdbvh accuracy --quick --family direction-scale --no-embree --json " + json.string());
    ASSERT_FALSE(j["rows"].empty());
    std::size_t nulls = 0;
    for (const Json& row : j["rows"]) {
        EXPECT_EQ(row["family"].get<std::string>(), "direction-scale");
        ASSERT_TRUE(row["max_rel_t_error"].is_null() || row["max_rel_t_error"].is_number());
        nulls += row["max_rel_t_error"].is_null();
    }
    // Rays whose t exceeds FLT_MAX hit at t = +inf: their relative t error is infinite.
    EXPECT_GT(nulls, 0u) << "the direction-scale family no longer produces an infinite t error; pick another case";
}

// The inside/outside panel: ours never wrong against CGAL; Embree's hit parity
// wrong somewhere (the families exist to break it). Open3D's rows: open3d_inside_test.cpp.
TEST_F(JsonReports, InsideOutsidePanel) {
    const fs::path json = dir_ / "inside.json";
    const test::CliRun r =
        test::run_cli("accuracy --quick --family watertight --inside --no-open3d --json " + shell_quote(json.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    const Json j = parse(json);
    if (j["inside"].empty()) GTEST_SKIP() << "no CGAL in this build";
    std::size_t ours = 0, embree_wrong = 0, diagonal = 0;
    // The diagonal family's points (tests/cli/inside_points_test.cpp checks them): all of them in each row.
    const std::size_t diagonal_points =
        simdbvh::lab::diagonal_through_vertices(simdbvh::workloads::icosphere(3), 4000).size();
    for (const Json& row : j["inside"]) {
        const std::string m = row["method"].get<std::string>();
        EXPECT_GT(row["points"].get<int>(), 0) << row.dump();
        if (row["mesh"] == "icosphere-3" && row["family"] == "diagonal rays through vertices") {
            ++diagonal;
            EXPECT_EQ(row["points"].get<std::size_t>() + row["on_surface"].get<std::size_t>(), diagonal_points);
        }
        if (m.rfind("simdbvh", 0) == 0) {
            ++ours;
            EXPECT_EQ(row["wrong"].get<int>(), 0) << row.dump();
        } else {
            embree_wrong += row["wrong"].get<std::size_t>();
        }
    }
    EXPECT_EQ(ours, 24u);     // 2 meshes x 4 point families x (+z with 2 rules, the shortest ray)
    EXPECT_EQ(diagonal, 5u);  // ours 3, Embree 2
    EXPECT_GT(embree_wrong, 0u);
}

TEST_F(JsonReports, PanelEscapesSceneAndCommand) {
    const std::string scene = tetra();
    const fs::path json = dir_ / "panel.json";
    const test::CliRun r = test::run_cli("panel --scene " + shell_quote(scene) +
                                         " --quick --rays 1024 --stats-rays 256 --reps 1 --no-report --json " +
                                         shell_quote(json.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    const Json j = parse(json);
    const std::string want = "simdbvh panel --scene " + scene;  // the byte 0xFF becomes U+FFFD
    const std::string fixed = want.substr(0, want.find('\xff')) + "\xEF\xBF\xBD" + want.substr(want.find('\xff') + 1);
    EXPECT_EQ(j["command"].get<std::string>().substr(0, fixed.size()), fixed);
    EXPECT_EQ(j["triangles"].get<int>(), 4);
    EXPECT_EQ(j["rows"].size(), 9u);
}

TEST_F(JsonReports, BenchRecordsEveryWidth) {
    const std::string scene = tetra();
    const fs::path json = dir_ / "bench.json";
    const test::CliRun r = test::run_cli("bench --scene " + shell_quote(scene) +
                                         " --quick --rays 1024 --sample 16 --reps 1 --build-reps 1 --stats-rays 64"
                                         " --width-scenes none --no-report --json " +
                                         shell_quote(json.string()));
    ASSERT_EQ(r.status, 0) << r.output;
    const Json j = parse(json);
    EXPECT_NE(j["command"].get<std::string>().find(kNasty), std::string::npos);
    std::set<int> widths;
    for (const Json& w : j["widths"]) {
        widths.insert(w["width"].get<int>());
        EXPECT_EQ(w["threads"].get<int>(), 1);
        EXPECT_TRUE(w["nodes_per_ray"].is_number()) << w.dump();
        EXPECT_TRUE(w["box_tests_per_ray"].is_number()) << w.dump();
    }
    EXPECT_EQ(widths, (std::set<int>{2, 4, 8, 16}));
    bool embree = false;
    for (const Json& rec : j["records"]) {
        EXPECT_TRUE(rec["build_ms_warm"].is_number());
        if (rec["method"].get<std::string>().rfind("embree", 0) == 0) {
            embree = true;
            EXPECT_TRUE(rec["nodes_per_ray"].is_null()) << "Embree has no node counters";
        }
    }
    EXPECT_TRUE(embree);
    // --quick: 3 refit frames, each twisted 0.1 rad more; the refit tree answers as the rebuilt one.
    ASSERT_EQ(j["refit"].size(), 3u);
    for (std::size_t f = 0; f < 3; ++f) {
        const Json& fr = j["refit"][f];
        EXPECT_EQ(fr["frame"].get<int>(), int(f) + 1);
        EXPECT_DOUBLE_EQ(fr["radians"].get<double>(), 0.1 * double(f + 1));
        EXPECT_EQ(fr["differ"].get<int>(), 0) << fr.dump();
        EXPECT_TRUE(fr["refit_ms"].is_number() && fr["embree_refit_ms"].is_number()) << fr.dump();
        EXPECT_EQ(fr["mrays_refit"].size(), 2u);
    }
}

TEST_F(JsonReports, BadWidthSceneFailsBeforeAnyOutput) {
    const fs::path json = dir_ / "bench.json";
    const test::CliRun r = test::run_cli("bench --scene icosphere-1 --quick --width-scenes " +
                                         shell_quote((dir_ / "missing.ply").string()) + " --no-report --json " +
                                         shell_quote(json.string()));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("missing.ply"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(json));
}

}  // namespace
