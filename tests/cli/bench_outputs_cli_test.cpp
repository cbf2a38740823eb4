// What bench (and bench --sweep) writes, and when: every block a run will
// rewrite (--readme, --publish, --model-out) and every output is checked
// before any work; the report (JSON, Markdown, pictures, charts, docs) is one
// all-or-nothing set written at the end, so a bad target or a SIGINT midway
// leaves the earlier report as it was; --report DIR alone writes only under
// DIR; --publish DIR writes DIR/results.md and its pictures in DIR/results/.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/cli.h"
#include "support/scene.h"

namespace fs = std::filesystem;

namespace {

using test::CliRun;
using test::run_cli;

// A bench of a few seconds.
const std::string kQuick =
    " --scene icosphere-1 --quick --rays 1024 --sample 16 --reps 1 --build-reps 0 --stats-rays 16 --width-scenes none"
    " --refit-frames 0";

std::set<std::string> listing(const fs::path& dir) {
    std::set<std::string> s;
    for (const auto& e : fs::recursive_directory_iterator(dir)) s.insert(fs::relative(e.path(), dir).string());
    return s;
}

class BenchOutputs : public testing::Test {
protected:
    std::string p(const std::string& name) const { return (dir_ / name).string(); }
    test::TempDir dir_;
};

TEST_F(BenchOutputs, ReadmeWithoutTheBlockFailsBeforeAnyWork) {
    test::write_text(dir_ / "README.md", "# no markers\n");
    const auto t0 = std::chrono::steady_clock::now();
    const CliRun r = run_cli("bench" + kQuick + " --report " + p("out") + " --readme " + p("README.md"));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("README.md"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("<!-- bench:begin -->"), std::string::npos) << r.output;
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(2)) << "the bench ran first";
    EXPECT_EQ(listing(dir_.path()), std::set<std::string>{"README.md"});  // no out/, no docs/results
    EXPECT_EQ(test::read_bytes(dir_ / "README.md"), "# no markers\n");
}

// --quick and --full are two sizes of one run: both at once is a usage error
// before any work, naming both options, and nothing is written.
TEST_F(BenchOutputs, QuickWithFullIsAUsageError) {
    const CliRun r = run_cli("bench" + kQuick + " --full --report " + p("out"));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("--quick"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--full"), std::string::npos) << r.output;
    EXPECT_TRUE(listing(dir_.path()).empty());
}

TEST_F(BenchOutputs, SweepChecksEveryBlockBeforeTheSweep) {
    const std::string model =
        "// sweep:avx2:begin\n// sweep:avx2:end\n// sweep:avx512:begin\n// sweep:avx512:end\n"
        "// sweep:scalar:begin\n// sweep:scalar:end\n";
    test::write_text(dir_ / "fit.cpp", model);
    test::write_text(dir_ / "README.md", "# no markers\n");
    const std::string sweep = "bench --sweep --quick --reps 1 --build-reps 0 --budget-ms 1 --report " + p("out");
    const CliRun r = run_cli(sweep + " --model-out " + p("fit.cpp") + " --readme " + p("README.md"));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("<!-- sweep:begin -->"), std::string::npos) << r.output;
    EXPECT_EQ(test::read_bytes(dir_ / "fit.cpp"), model);  // not rewritten before the README was looked at
    // --model-out without its block: refused before the sweep too.
    test::write_text(dir_ / "bare.cpp", "int x;\n");
    const CliRun m = run_cli(sweep + " --model-out " + p("bare.cpp"));
    EXPECT_EQ(m.status, 2) << m.output;
    EXPECT_NE(m.output.find("bare.cpp"), std::string::npos) << m.output;
    EXPECT_NE(m.output.find("// sweep:"), std::string::npos) << m.output;
    EXPECT_EQ(listing(dir_.path()), (std::set<std::string>{"README.md", "bare.cpp", "fit.cpp"}));
}

// A picture that cannot be written (a folder in its place) is found before the run, not after the JSON.
TEST_F(BenchOutputs, BadPictureTargetFailsBeforeAnyOutput) {
    fs::create_directories(dir_ / "out" / "heat_bvh8.png");
    test::write_text(dir_ / "out" / "report.md", "old");
    const CliRun r = run_cli("bench" + kQuick + " --report " + p("out"));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("heat_bvh8.png"), std::string::npos) << r.output;
    EXPECT_EQ(listing(dir_ / "out"), (std::set<std::string>{"heat_bvh8.png", "report.md"}));
    EXPECT_EQ(test::read_bytes(dir_ / "out" / "report.md"), "old");
}

// --report out alone, from a fresh working folder: everything lands in out/ (no docs/results, no staging
// folder left in TMPDIR, no temporaries, no __pycache__ beside the chart scripts); --publish adds its doc.
TEST_F(BenchOutputs, ReportWritesOnlyUnderItsFolderAndPublishWritesTheDoc) {
    fs::create_directory(dir_ / "work");
    fs::create_directory(dir_ / "tmp");
    const fs::path pycache = fs::path(SIMDBVH_BINARY_DIR) / "share" / "simdbvh" / "scripts" / "__pycache__";
    const bool had_pycache = fs::exists(pycache);
    const std::string in_work = "cd " + p("work") + " && TMPDIR=" + p("tmp") + " env -u PYTHONDONTWRITEBYTECODE ";
    // The scene bench: its chart script imports a sibling module (plot_sphere_precision.py).
    const CliRun s = run_cli(
        "bench --scene spheres-10 --quick --rays 1024 --sample 16 --reps 1 --build-reps 0 --report out", in_work);
    ASSERT_EQ(s.status, 0) << s.output;
    const CliRun r = run_cli("bench" + kQuick + " --report out2", in_work);
    ASSERT_EQ(r.status, 0) << r.output;
    std::set<std::string> top;
    for (const auto& e : fs::directory_iterator(dir_ / "work")) top.insert(e.path().filename().string());
    EXPECT_EQ(top, (std::set<std::string>{"out", "out2"}));
    for (const char* f : {"bench.json", "report.md", "scene_render.png"})
        EXPECT_TRUE(fs::exists(dir_ / "work/out" / f)) << f;
    for (const char* f : {"bench.json", "report.md", "render_bvh8.png", "heat_bvh2.png", "heat_bvh8.png",
                          "disagree_bvh2_bvh8.png", "disagree_bvh8_embree.png"})
        EXPECT_TRUE(fs::exists(dir_ / "work/out2" / f)) << f;
    for (const char* d : {"work/out", "work/out2"})
        for (const std::string& f : listing(dir_ / d)) EXPECT_EQ(f.find(".tmp."), std::string::npos) << f;
    EXPECT_TRUE(fs::is_empty(dir_ / "tmp")) << *listing(dir_ / "tmp").begin();
    if (!had_pycache) {
        EXPECT_FALSE(fs::exists(pycache)) << "the chart scripts wrote bytecode into the source tree";
    }

    // --publish into a doc with prose around the block: the prose stays, the block and pictures are new.
    fs::create_directories(dir_ / "pub");
    test::write_text(dir_ / "pub/results.md",
                     "# Results\n\nprose\n<!-- bench:begin -->\nold\n<!-- bench:end -->\nmore\n");
    const CliRun u = run_cli("bench" + kQuick + " --report out3 --publish " + p("pub"), in_work);
    ASSERT_EQ(u.status, 0) << u.output;
    const std::string doc = test::read_bytes(dir_ / "pub/results.md");
    EXPECT_EQ(doc.rfind("# Results\n\nprose\n<!-- bench:begin -->\n_Generated by `simdbvh bench", 0), 0u) << doc;
    EXPECT_EQ(doc.find("\nold\n"), std::string::npos) << doc;
    EXPECT_NE(doc.find("![render](results/render_bvh8.png)"), std::string::npos) << doc;
    EXPECT_TRUE(doc.ends_with("<!-- bench:end -->\nmore\n")) << doc;
    EXPECT_EQ(test::read_bytes(dir_ / "pub/results/render_bvh8.png"),
              test::read_bytes(dir_ / "work/out3/render_bvh8.png"));
    top.clear();
    for (const auto& e : fs::directory_iterator(dir_ / "work")) top.insert(e.path().filename().string());
    EXPECT_EQ(top, (std::set<std::string>{"out", "out2", "out3"}));
}

// SIGINT while the chart script draws into the staging folder: the old report stays as it was, alone, and
// the staging folder is gone.
TEST_F(BenchOutputs, SigintMidwayLeavesTheOldReport) {
    const char* cli = std::getenv("SIMDBVH_CLI");
    ASSERT_NE(cli, nullptr);
    fs::create_directories(dir_ / "out");
    fs::create_directory(dir_ / "tmp");
    test::write_text(dir_ / "out/report.md", "old");
    const std::string out = p("out"), tmp = "TMPDIR=" + p("tmp");
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        const int null = ::open("/dev/null", O_WRONLY);
        ::dup2(null, 1);
        ::dup2(null, 2);
        ::putenv(const_cast<char*>(tmp.c_str()));
        ::execl(cli, cli, "bench", "--scene", "icosphere-1", "--quick", "--rays", "1024", "--sample", "16", "--reps",
                "1", "--build-reps", "0", "--stats-rays", "16", "--width-scenes", "none", "--refit-frames", "0",
                "--report", out.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    bool staged = false;
    int st = 0;
    const auto t0 = std::chrono::steady_clock::now();
    while (!staged && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120)) {
        if (::waitpid(pid, &st, WNOHANG) == pid) break;
        for (const auto& e : fs::directory_iterator(dir_ / "tmp"))
            if (e.path().filename().string().rfind("simdbvh-staging.", 0) == 0) staged = true;
        if (!staged) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (staged) {
        ::kill(pid, SIGINT);
        ::waitpid(pid, &st, 0);
        EXPECT_TRUE(WIFSIGNALED(st) && WTERMSIG(st) == SIGINT) << "status " << st;
    } else {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &st, 0);
    }
    ASSERT_TRUE(staged) << "never saw the staging folder";
    EXPECT_EQ(listing(dir_ / "out"), std::set<std::string>{"report.md"});
    EXPECT_EQ(test::read_bytes(dir_ / "out/report.md"), "old");
    std::string left;
    for (const auto& e : fs::recursive_directory_iterator(dir_ / "tmp")) left += " " + e.path().string();
    EXPECT_TRUE(left.empty()) << "left in TMPDIR:" << left;
}

}  // namespace

namespace {

// The main job ends with the headline per ray kind and query and where the report is; its JSON carries, per
// method, the disagreements on the hard accuracy families (the speed-against-accuracy chart's x axis).
TEST_F(BenchOutputs, MainJobPrintsTheSummaryAndTheHardFamilyDisagreements) {
    const CliRun r = run_cli("bench" + kQuick + " --no-report --json " + p("b.json"));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("summary (icosphere-1, 1 thread, Mrays/s):"), std::string::npos) << r.output;
    for (const char* line : {"  closest primary: ", "  closest diffuse: ", "  any incoherent: "})
        EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
    EXPECT_NE(r.output.find(", embree "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("report: " + p("b.json")), std::string::npos) << r.output;

    const nlohmann::json j = nlohmann::json::parse(test::read_bytes(dir_ / "b.json"));
    ASSERT_TRUE(j.contains("hard_families")) << j.dump();
    const auto& hard = j["hard_families"];
    const std::vector<std::string> fams{"watertight", "grazing", "offsets", "direction-scale"};
    EXPECT_EQ(hard["families"].get<std::vector<std::string>>(), fams);
    std::set<std::string> labels;
    for (const auto& m : hard["methods"]) {
        const std::string name = m["method"];
        std::uint64_t sum = 0;
        for (const std::string& f : fams) {
            ASSERT_TRUE(m["per_family"].contains(f)) << name << " " << f;
            EXPECT_GT(m["per_family"][f]["rays"].get<std::uint64_t>(), 0u) << name << " " << f;
            sum += m["per_family"][f]["disagreements"].get<std::uint64_t>();
        }
        EXPECT_EQ(m["disagreements"].get<std::uint64_t>(), sum) << name;
        if (!m["bench_label"].is_null()) labels.insert(m["bench_label"]);
        // Embree disagrees with the reference on directions scaled by 2^127 (an independent fact: the point of the chart).
        if (name == "embree/default") {
            EXPECT_GT(m["per_family"]["direction-scale"]["disagreements"].get<std::uint64_t>(), 0u);
        }
    }
    for (const char* l : {"bvh2", "embree/medium/default", "embree/medium/robust"}) EXPECT_TRUE(labels.count(l)) << l;
    // Every labelled method is a row of the bench.
    std::set<std::string> rows;
    for (const auto& rec : j["records"]) {
        const std::string m = rec["method"];
        rows.insert(rec["width"].get<int>() >= 4 ? m + "/" + rec["isa"].get<std::string>() : m);
    }
    for (const std::string& l : labels) EXPECT_TRUE(rows.count(l)) << l;
}

}  // namespace
