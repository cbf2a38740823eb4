// What the simdbvh executable (SIMDBVH_CLI) does to its outputs
// (docs/cli.md#bad-input): symlinks, modes, hard links and FIFOs survive a
// write; outputs are checked before the work, never equal an input or each
// other, and are written all or nothing; killed runs and stale temporary names
// leave nothing behind; sizes too large for memory and empty diffuse sets are
// clear errors; --version and <command> --help.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include "support/cli.h"
#include "support/sanitizer.h"
#include "support/scene.h"

namespace fs = std::filesystem;

namespace {

using test::CliRun;
using test::run_cli;

constexpr int kCount = 1000;  // rays: files of 32000 bytes

class Outputs : public testing::Test {
protected:
    void SetUp() override {
        if (!std::getenv("SIMDBVH_CLI")) GTEST_SKIP() << "SIMDBVH_CLI is not set (built without the tools)";
    }
    std::string p(const std::string& name) const { return (dir_ / name).string(); }
    CliRun gen_rays(const std::string& out, const std::string& prefix = "") const {
        return run_cli(
            "gen-rays --scene icosphere-2 --kind incoherent --count " + std::to_string(kCount) + " --out " + out,
            prefix);
    }
    // Hidden temporary files (.NAME.tmp.*) in the folder.
    std::vector<std::string> temps() const {
        std::vector<std::string> v;
        for (const auto& e : fs::directory_iterator(dir_.path()))
            if (e.path().filename().string().find(".tmp.") != std::string::npos) v.push_back(e.path().string());
        return v;
    }
    test::TempDir dir_;
};

// --out replaces whatever is at the path.
TEST_F(Outputs, SymlinkStaysASymlinkAndItsTargetIsWritten) {
    test::write_text(dir_ / "real.bin", "old");
    fs::create_symlink("real.bin", dir_ / "link.bin");
    const CliRun r = gen_rays(p("link.bin"));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::is_symlink(dir_ / "link.bin"));
    EXPECT_EQ(fs::file_size(dir_ / "real.bin"), std::uintmax_t(kCount) * 32);
    EXPECT_TRUE(temps().empty());
}

TEST_F(Outputs, DanglingSymlinkCreatesItsTarget) {
    fs::create_symlink("new.bin", dir_ / "link.bin");
    const CliRun r = gen_rays(p("link.bin"));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::is_symlink(dir_ / "link.bin"));
    EXPECT_EQ(fs::file_size(dir_ / "new.bin"), std::uintmax_t(kCount) * 32);
}

TEST_F(Outputs, ExistingFileKeepsItsMode) {
    test::write_text(dir_ / "r.bin", "old");
    fs::permissions(dir_ / "r.bin", fs::perms::owner_read | fs::perms::owner_write);
    const CliRun r = gen_rays(p("r.bin"));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(fs::status(dir_ / "r.bin").permissions(), fs::perms::owner_read | fs::perms::owner_write);
    EXPECT_EQ(fs::file_size(dir_ / "r.bin"), std::uintmax_t(kCount) * 32);
}

TEST_F(Outputs, HardLinksStayLinked) {
    test::write_text(dir_ / "a.bin", "old");
    fs::create_hard_link(dir_ / "a.bin", dir_ / "b.bin");
    const CliRun r = gen_rays(p("a.bin"));
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(fs::hard_link_count(dir_ / "a.bin"), 2u);
    EXPECT_EQ(fs::file_size(dir_ / "b.bin"), std::uintmax_t(kCount) * 32);
    EXPECT_EQ(test::read_bytes(dir_ / "a.bin"), test::read_bytes(dir_ / "b.bin"));
    EXPECT_TRUE(temps().empty());
}

// A non-regular target (a FIFO here; /dev/null as root in real life) is written, not replaced.
TEST_F(Outputs, FifoIsWrittenThroughNotReplaced) {
    ASSERT_EQ(::mkfifo(p("fifo").c_str(), 0600), 0);
    // The reader runs in the background (and gives up after 20 s if nothing ever opens the FIFO).
    const CliRun r = gen_rays(p("fifo"), "(timeout 20 cat " + p("fifo") + " > " + p("got.bin") + " &); ");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(fs::status(dir_ / "fifo").type(), fs::file_type::fifo);
    const auto t0 = std::chrono::steady_clock::now();
    while ((!fs::exists(dir_ / "got.bin") || fs::file_size(dir_ / "got.bin") < std::uintmax_t(kCount) * 32) &&
           std::chrono::steady_clock::now() - t0 < std::chrono::seconds(10))
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_EQ(fs::file_size(dir_ / "got.bin"), std::uintmax_t(kCount) * 32);
    EXPECT_TRUE(temps().empty());
}

TEST_F(Outputs, DirectoryTargetIsRefused) {
    fs::create_directory(dir_ / "d");
    const CliRun r = gen_rays(p("d"));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("is a directory"), std::string::npos) << r.output;
    EXPECT_TRUE(fs::is_empty(dir_ / "d"));
}

// The output is checked before anything is loaded: the missing folder is reported, not the missing rays.
TEST_F(Outputs, BadOutIsFoundBeforeTheWork) {
    const CliRun r = run_cli("trace --scene icosphere-2 --rays " + p("missing.bin") + " --out " + p("nodir/h.bin"));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("nodir"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("does not exist"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("missing.bin"), std::string::npos) << r.output;
    const CliRun g = run_cli("gen-rays --kind watertight --out " + p("nodir/r.bin"));
    EXPECT_EQ(g.status, 2) << g.output;
    EXPECT_NE(g.output.find("does not exist"), std::string::npos) << g.output;
}

// SIGTERM while the output's temporary file is being written leaves neither it nor the output.
TEST_F(Outputs, SigtermRemovesTheTemporaryFile) {
    const char* cli = std::getenv("SIMDBVH_CLI");
    const std::string out = p("big.bin");
    bool killed_while_writing = false;
    for (long count = 4'000'000; count <= 64'000'000 && !killed_while_writing; count *= 2) {
        const std::string n = std::to_string(count);
        const pid_t pid = fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            const int null = ::open("/dev/null", O_WRONLY);
            ::dup2(null, 1);
            ::dup2(null, 2);
            ::execl(cli, cli, "gen-rays", "--scene", "icosphere-2", "--kind", "incoherent", "--count", n.c_str(),
                    "--out", out.c_str(), static_cast<char*>(nullptr));
            ::_exit(127);
        }
        int st = 0;
        const auto t0 = std::chrono::steady_clock::now();
        while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120)) {
            if (::waitpid(pid, &st, WNOHANG) == pid) break;  // finished before we saw the temp file: bigger job
            bool writing = false;
            for (const std::string& t : temps()) {
                std::error_code ec;
                if (fs::file_size(t, ec) > 0 && !ec) writing = true;
            }
            if (writing) {
                ::kill(pid, SIGTERM);
                ::waitpid(pid, &st, 0);
                killed_while_writing = true;
                break;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        if (!killed_while_writing) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &st, 0);
            fs::remove(out);
        } else {
            EXPECT_TRUE(WIFSIGNALED(st) && WTERMSIG(st) == SIGTERM) << "status " << st;
        }
    }
    ASSERT_TRUE(killed_while_writing) << "never saw the temporary file being written";
    EXPECT_TRUE(temps().empty()) << temps().front();
    EXPECT_FALSE(fs::exists(out));
}

// A leftover temporary file with the name a run used to pick (PID and counter; as PID 1 in a container
// every run has the same PID) does not block the run, and is not ours to remove.
TEST_F(Outputs, StaleTemporaryNameDoesNotBlock) {
    // exec keeps the shell's PID ($$) for simdbvh.
    const CliRun r = gen_rays(p("r.bin"), "touch " + p(".r.bin.tmp.") + "$$.0; exec ");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(fs::file_size(dir_ / "r.bin"), std::uintmax_t(kCount) * 32);
    EXPECT_EQ(temps().size(), 1u);
}

// Sizes the options allow but memory does not are named, not a bare std::bad_alloc.
TEST_F(Outputs, TooManyRaysNamesTheOption) {
    SIMDBVH_SKIP_ADDRESS_LIMIT_UNDER_SANITIZER();
    const CliRun r = run_cli("gen-rays --scene icosphere-2 --kind incoherent --count 2147483648 --out " + p("r.bin"),
                             "ulimit -v 4000000; ");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("--count 2147483648"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("memory"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("bad_alloc"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "r.bin"));
}

TEST_F(Outputs, TooLargeImageNamesTheOptions) {
    SIMDBVH_SKIP_ADDRESS_LIMIT_UNDER_SANITIZER();
    const CliRun r =
        run_cli("render --scene icosphere-2 --width 16384 --height 16384 --out " + p("i.png"), "ulimit -v 4000000; ");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("--width 16384 --height 16384"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("bad_alloc"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "i.png"));
}

// An output is never an input or another output; several outputs are all or nothing.
TEST_F(Outputs, MeshOutAndOutMustDiffer) {
    const CliRun r = run_cli("gen-rays --kind watertight --mesh-out " + p("x") + " --out " + p("x"));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("same file"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "x"));
}

TEST_F(Outputs, NoMeshLeftWhenTheRaysCannotBeWritten) {
    const CliRun r = run_cli("gen-rays --kind watertight --mesh-out " + p("m.ply") + " --out " + p("nodir/r.bin"));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "m.ply"));
    EXPECT_TRUE(temps().empty());
}

TEST_F(Outputs, TraceRefusesToReplaceItsInputs) {
    ASSERT_EQ(gen_rays(p("r.bin")).status, 0);
    const std::string before = test::read_bytes(dir_ / "r.bin");
    const CliRun r = run_cli("trace --scene icosphere-2 --rays " + p("r.bin") + " --out " + p("r.bin"));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("--rays"), std::string::npos) << r.output;
    EXPECT_EQ(test::read_bytes(dir_ / "r.bin"), before);

    test::write_text(dir_ / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    fs::create_symlink("tri.obj", dir_ / "alias.obj");  // the same file under another name
    const CliRun s = run_cli("trace --scene " + p("tri.obj") + " --rays " + p("r.bin") + " --out " + p("alias.obj"));
    EXPECT_EQ(s.status, 2) << s.output;
    EXPECT_NE(s.output.find("--scene"), std::string::npos) << s.output;
    EXPECT_EQ(test::read_bytes(dir_ / "tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
}

// Diffuse rays need primary hits; an empty mesh has none, and 0 of N rays is an error.
TEST_F(Outputs, DiffuseRaysOnAnEmptyMeshAreAnError) {
    test::write_text(dir_ / "empty.off", "OFF\n0 0 0\n");
    const CliRun r = run_cli("gen-rays --scene " + p("empty.off") + " --kind diffuse --count 100 --out " + p("d.bin"));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("empty.off"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("diffuse"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "d.bin"));
}

// --version and every command's --help / -h on stdout, exit 0.
std::pair<int, std::string> run_stdout(const std::string& args) {
    const std::string cmd = std::string(std::getenv("SIMDBVH_CLI")) + " " + args + " 2>/dev/null";
    FILE* f = popen(cmd.c_str(), "r");
    std::string out;
    char buf[4096];
    std::size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0) out.append(buf, n);
    const int st = pclose(f);
    return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, out};
}

TEST_F(Outputs, VersionAndPerCommandHelp) {
    const auto [vs, v] = run_stdout("--version");
    EXPECT_EQ(vs, 0) << v;
    EXPECT_EQ(v.rfind("simdbvh 0.1.0", 0), 0u) << v;
    EXPECT_NE(v.find("isa "), std::string::npos) << v;
    for (const char* c : {"info", "gen-rays", "trace", "bench", "render", "panel", "accuracy"})
        for (const char* h : {"--help", "-h"}) {
            const auto [s, out] = run_stdout(std::string(c) + " " + h);
            EXPECT_EQ(s, 0) << c << " " << h << "\n" << out;
            EXPECT_EQ(out.rfind(std::string("usage: simdbvh ") + c, 0), 0u) << c << " " << h << "\n" << out;
        }
}

}  // namespace
