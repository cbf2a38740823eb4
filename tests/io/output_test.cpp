// io::write_files_atomic and check_writable (output.h): all or nothing,
// links and modes kept, the preflight's messages.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <string>
#include <vector>

#include "simdbvh/kernels/error.h"
#include "simdbvh/io/output.h"
#include "support/scene.h"

namespace fs = std::filesystem;
namespace io = simdbvh::io;

namespace {

std::span<const unsigned char> bytes(const std::string& s) {
    return {reinterpret_cast<const unsigned char*>(s.data()), s.size()};
}

bool has_temp(const fs::path& dir) {
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.path().filename().string().find(".tmp.") != std::string::npos) return true;
    return false;
}

TEST(Output, SeveralFilesAllOrNothing) {
    test::TempDir dir;
    test::write_text(dir / "a", "old a");
    const std::string na = "new a", nb = "new b";
    const std::vector<io::OutputFile> files{{dir / "a", bytes(na)}, {dir / "no/such/b", bytes(nb)}};
    EXPECT_THROW(io::write_files_atomic(files), simdbvh::Error);
    EXPECT_EQ(test::read_bytes(dir / "a"), "old a");
    EXPECT_FALSE(has_temp(dir.path()));
    const std::vector<io::OutputFile> ok{{dir / "a", bytes(na)}, {dir / "b", bytes(nb)}};
    io::write_files_atomic(ok);
    EXPECT_EQ(test::read_bytes(dir / "a"), na);
    EXPECT_EQ(test::read_bytes(dir / "b"), nb);
    EXPECT_FALSE(has_temp(dir.path()));
}

TEST(Output, NewFileGetsTheUmaskMode) {
    test::TempDir dir;
    const mode_t old = ::umask(022);
    io::write_file_atomic(dir / "f", bytes("x"));
    ::umask(old);
    struct stat st {};
    ASSERT_EQ(::stat((dir / "f").c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 07777, 0644u);  // not mkstemp's 0600
}

TEST(Output, CheckWritable) {
    test::TempDir dir;
    fs::create_directory(dir / "d");
    auto msg = [](auto f) {
        try {
            f();
        } catch (const simdbvh::Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(msg([&] { io::check_writable(dir / "d"); }).find("is a directory"), std::string::npos);
    EXPECT_NE(msg([&] { io::check_writable(dir / "no/f"); }).find("does not exist"), std::string::npos);
    EXPECT_EQ(msg([&] { io::check_writable(dir / "no/f", /*create_parent=*/true); }), "");
    EXPECT_EQ(msg([&] { io::check_writable(dir / "f"); }), "");
    EXPECT_FALSE(fs::exists(dir / "no"));
    EXPECT_FALSE(has_temp(dir.path()));
    test::write_text(dir / "file", "x");
    EXPECT_NE(msg([&] { io::check_writable(dir / "file/f"); }), "");
}

// A staging folder: private, removed with its files on destruction, and by remove_temp_files() (the signal
// handler's call) while it is live.
TEST(Output, StagingDirIsRemovedWithItsFiles) {
    test::TempDir dir;
    fs::path kept;
    {
        const io::StagingDir s(dir.path());
        kept = s.path();
        EXPECT_EQ(kept.parent_path(), dir.path());
        EXPECT_EQ(kept.filename().string().rfind("simdbvh-staging.", 0), 0u) << kept;
        test::write_text(kept / "a.png", "x");
        test::write_text(kept / "b.json", "y");
    }
    EXPECT_FALSE(fs::exists(kept));
    const io::StagingDir live(dir.path());
    for (int i = 0; i < 300; ++i) test::write_text(live.path() / std::to_string(i), "z");  // several listings
    io::remove_temp_files();
    EXPECT_FALSE(fs::exists(live.path()));
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

}  // namespace
