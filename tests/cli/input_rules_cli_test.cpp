// Small input rules of the CLI: numbers are parsed strictly (no spaces; a
// subnormal is a number); an option that does not apply to the scene or the
// method is refused naming it, never ignored; an existing output the user may
// not write is not replaced (as cp refuses it); control characters in names
// are printed escaped, never sent to the terminal.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "simdbvh/io/point_files.h"
#include "support/cli.h"
#include "support/scene.h"

namespace fs = std::filesystem;

namespace {

using test::CliRun;
using test::run_cli;

class InputRules : public testing::Test {
protected:
    std::string p(const std::string& name) const { return (dir_ / name).string(); }
    test::TempDir dir_;
};

TEST_F(InputRules, NumbersAreParsedStrictly) {
    ASSERT_EQ(run_cli("gen-points --scene icosphere-2 --count 50 --out " + p("p.bin")).status, 0);
    const std::string distance = "distance --scene icosphere-2 --points " + p("p.bin") + " --out " + p("d.bin");
    // 1e-45 is the smallest positive float (a subnormal): no point is that close to the sphere.
    const CliRun tiny = run_cli(distance + " --max-distance 1e-45");
    ASSERT_EQ(tiny.status, 0) << tiny.output;
    for (const auto& r : simdbvh::io::read_distances(p("d.bin"))) EXPECT_EQ(r.prim, 0xFFFFFFFFu);
    for (const char* ok : {"+1", "inf", "0"}) EXPECT_EQ(run_cli(distance + " --max-distance " + ok).status, 0) << ok;
    fs::remove(dir_ / "d.bin");
    for (const char* bad : {"' 1'", "'1 '", "' inf'", "1e39", "nan", "-1", "+-1", "1,5", "''"}) {
        const CliRun r = run_cli(distance + " --max-distance " + bad);
        EXPECT_EQ(r.status, 2) << bad << "\n" << r.output;
        EXPECT_NE(r.output.find("--max-distance"), std::string::npos) << bad << "\n" << r.output;
        EXPECT_FALSE(fs::exists(dir_ / "d.bin")) << bad;
    }
}

TEST_F(InputRules, OptionsThatDoNotApplyAreRefusedNamingThem) {
    test::write_text(dir_ / "s.json", R"({"geometries": [{"mesh": "icosphere-1"}], "instances": [{"geometry": 0}]})");
    ASSERT_EQ(run_cli("gen-rays --scene icosphere-1 --kind incoherent --count 64 --out " + p("r.bin")).status, 0);
    const std::string scene = p("s.json"), out = p("out.bin");
    const std::string trace = "trace --scene " + scene + " --rays " + p("r.bin") + " --out " + out;
    const std::string render = "render --scene " + scene + " --width 8 --height 8 --out " + out;
    const std::string info = "info --scene " + scene;
    struct Case {
        std::string command, option;
    };
    std::vector<Case> cases;
    for (const std::string& c : {trace, render, info})
        for (const char* o : {"--test moller", "--test watertight", "--robust", "--quality high", "--packets on",
                              "--reorder off", "--box plain", "--box conservative"})
            cases.push_back({c + " " + o, std::string(o).substr(0, std::string(o).find(' '))});
    cases.push_back({trace + " --drop-invalid", "--drop-invalid"});
    cases.push_back({trace + " --stats", "--stats"});
    cases.push_back({render + " --heatmap", "--heatmap"});
    cases.push_back({info + " --expected-rays 5", "--expected-rays"});
    // On meshes: Embree's settings on our methods, our triangle test on Embree.
    const std::string mesh = "trace --scene icosphere-1 --rays " + p("r.bin") + " --out " + out;
    cases.push_back({mesh + " --method bvh8 --quality high", "--quality"});
    cases.push_back({mesh + " --method bvh2 --robust", "--robust"});
    cases.push_back({mesh + " --method embree --test moller", "--test"});
    for (const Case& c : cases) {
        const CliRun r = run_cli(c.command);
        EXPECT_EQ(r.status, 2) << c.command << "\n" << r.output;
        EXPECT_NE(r.output.find(c.option), std::string::npos) << c.command << "\n" << r.output;
        EXPECT_FALSE(fs::exists(out)) << c.command;
    }
    // What does apply is still taken.
    for (const std::string& c :
         {trace + " --method bvh4 --builder sah-sweep --threads 2", info + " --method bvh16",
          mesh + " --method embree --quality high --robust", mesh + " --method bvh2 --test moller"}) {
        const CliRun r = run_cli(c);
        EXPECT_EQ(r.status, 0) << c << "\n" << r.output;
    }
}

// A write-protected file in a folder others may write: a rename would replace it; cp and `>` refuse, and
// so does every output. As root (who may write anything) the test runs the CLI as nobody.
TEST_F(InputRules, AnOutputTheUserCannotWriteIsNotReplaced) {
    std::string as_user;
    fs::create_directory(dir_ / "shared");
    fs::permissions(dir_ / "shared", fs::perms::all);  // 0777, no sticky bit
    fs::permissions(dir_.path(), fs::perms::owner_all | fs::perms::group_exec | fs::perms::others_exec);
    if (::geteuid() == 0) {
        if (std::system("command -v setpriv > /dev/null") != 0) GTEST_SKIP() << "running as root without setpriv";
        as_user = "setpriv --reuid=65534 --regid=65534 --clear-groups ";
    }
    const fs::path file = dir_ / "shared" / "r.bin";
    test::write_text(file, "keep");
    fs::permissions(file, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);  // 0444
    for (const std::string& args : {"gen-rays --scene icosphere-1 --kind incoherent --count 10 --out " + file.string(),
                                    "render --scene icosphere-1 --width 4 --height 4 --out " + file.string()}) {
        const CliRun r = run_cli(args, as_user);
        EXPECT_EQ(r.status, 2) << args << "\n" << r.output;
        EXPECT_NE(r.output.find("is not writable"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find(file.string()), std::string::npos) << r.output;
        EXPECT_EQ(test::read_bytes(file), "keep");
    }
    for (const auto& e : fs::directory_iterator(dir_ / "shared")) EXPECT_EQ(e.path(), file) << "stray file";
}

TEST_F(InputRules, ControlCharactersInNamesAreEscaped) {
    // A name from the command line, in the CLI's own messages (an error, and the line naming what it wrote):
    // ESC [ 31 m escaped, UTF-8 text (e acute) as it is.
    const std::string name = "\"$(printf '" + p("caf\303\251\033[31m.bin") + "')\"";
    const CliRun a = run_cli("info --scene " + name);
    EXPECT_EQ(a.status, 2) << a.output;
    EXPECT_EQ(a.output.find('\x1b'), std::string::npos) << a.output;
    EXPECT_NE(a.output.find("\\x1b[31m.bin"), std::string::npos) << a.output;
    const CliRun g = run_cli("gen-rays --scene icosphere-1 --kind incoherent --count 8 --out " + name);
    EXPECT_EQ(g.status, 0) << g.output;
    EXPECT_EQ(g.output.find('\x1b'), std::string::npos) << g.output;
    EXPECT_NE(g.output.find("caf\xc3\xa9\\x1b[31m.bin"), std::string::npos) << g.output;
    // One from a JSON scene: ESC ] 0 ; ... BEL (a title change) and CSI as the C1 control U+009B.
    test::write_text(dir_ / "s.json", R"({"geometries": [{"mesh": "\u001b]0;title\u0007x\u009b2Jy.obj"}]})");
    const CliRun j = run_cli("info --scene " + p("s.json"));
    EXPECT_EQ(j.status, 2) << j.output;
    for (const char* raw : {"\x1b", "\x07", "\xc2\x9b"}) EXPECT_EQ(j.output.find(raw), std::string::npos) << j.output;
    EXPECT_NE(j.output.find("\\x1b]0;title\\x07x"), std::string::npos) << j.output;
}

}  // namespace
