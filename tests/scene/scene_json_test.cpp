// The JSON scene loader: files read as the meshes are (regular files only,
// bounded), mesh paths relative to the file, names and keys quoted in
// messages, default instances, nesting and size bounds.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "simdbvh/kernels/error.h"
#include "simdbvh/scene/scene_desc.h"
#include "support/scene.h"

namespace simdbvh::scene {
namespace {

namespace fs = std::filesystem;

// The message of loading `file` ("" when it loaded).
std::string json_error(const fs::path& file) {
    try {
        load_scene_json(file);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

void expect_has(const std::string& msg, const std::string& part) {
    EXPECT_NE(msg.find(part), std::string::npos) << "wanted '" << part << "' in: " << msg;
}

// A FIFO named x.json is refused at once (it blocked in open, then read
// whatever a writer sent). A writer thread feeds it a valid scene if the
// loader ever opens it for reading, so the old behaviour loads "{}" instead
// of hanging the test.
TEST(SceneJsonFile, FifoIsRefusedWithoutBlocking) {
    test::TempDir dir;
    const fs::path fifo = dir / "x.json";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::signal(SIGPIPE, SIG_IGN);
    std::atomic<bool> stop{false};
    std::thread writer([&] {
        while (!stop) {
            const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
            if (fd >= 0) {
                [[maybe_unused]] const ssize_t n = ::write(fd, "{}", 2);
                ::close(fd);
                return;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
    });
    const std::string msg = json_error(fifo);
    stop = true;
    writer.join();
    expect_has(msg, fifo.string() + ": is not a regular file");
}

// A symlink to a device (/dev/zero was read until memory ran out; /dev/null
// here, which the old loader read as empty text) and a folder named x.json.
TEST(SceneJsonFile, DevicesAndFoldersAreRefusedByKind) {
    test::TempDir dir;
    fs::create_symlink("/dev/null", dir / "null.json");
    expect_has(json_error(dir / "null.json"), (dir / "null.json").string() + ": is not a regular file");
    fs::create_directory(dir / "d.json");
    expect_has(json_error(dir / "d.json"), (dir / "d.json").string() + ": is a directory");
    expect_has(json_error(dir / "none.json"), (dir / "none.json").string() + ": cannot open");
    test::write_text(dir / "empty.json", "");
    expect_has(json_error(dir / "empty.json"), "empty.json: file is empty");
    // A symlink to a regular file is read through.
    test::write_text(dir / "real.json", R"({"geometries": [{"spheres": [{"center": [0, 0, 0], "radius": 1}]}],
                                           "instances": [{"geometry": 0}]})");
    fs::create_symlink(dir / "real.json", dir / "link.json");
    EXPECT_EQ(load_scene_json(dir / "link.json").instances.size(), 1u);
}

}  // namespace
}  // namespace simdbvh::scene
