// The JSON scene loader: files read as the meshes are (regular files only,
// bounded), mesh paths relative to the file, names and keys quoted in
// messages, default instances, nesting and size bounds.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <sys/resource.h>

#include <atomic>
#include <csignal>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "simdbvh/kernels/error.h"
#include "simdbvh/io/load.h"
#include "simdbvh/workloads/scene_desc.h"
#include "simdbvh/workloads/scenes.h"
#include "support/scene.h"

namespace simdbvh::workloads {
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

// The message of parsing `text` ("" when it parsed).
std::string text_error(const std::string& text) {
    try {
        parse_scene_json(text, ".", "t.json");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

void expect_has(const std::string& msg, const std::string& part) {
    EXPECT_NE(msg.find(part), std::string::npos) << "wanted '" << part << "' in: " << msg;
}

// Growth of the process's peak resident set (MiB) while `f` runs (each test
// runs in a process of its own under ctest, so the peak is this test's).
template <class F>
double peak_growth_mib(F&& f) {
    rusage before{}, after{};
    getrusage(RUSAGE_SELF, &before);
    f();
    getrusage(RUSAGE_SELF, &after);
    return double(after.ru_maxrss - before.ru_maxrss) / 1024.0;
}

std::string repeat(std::string_view s, std::size_t n) {
    std::string out;
    out.reserve(s.size() * n);
    for (std::size_t i = 0; i < n; ++i) out += s;
    return out;
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

// Runs `f` with the current folder set to `dir`, then restores it.
template <class F>
void in_folder(const fs::path& dir, F&& f) {
    const fs::path before = fs::current_path();
    fs::current_path(dir);
    try {
        f();
    } catch (...) {
        fs::current_path(before);
        throw;
    }
    fs::current_path(before);
}

const std::string kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

// A mesh path is relative to the JSON file's folder and only there: scenes/s.json
// naming part.obj, loaded from other/ holding a part.obj, loaded other/part.obj.
TEST(SceneJsonMeshes, PathsAreRelativeToTheJsonFileNeverTheCurrentFolder) {
    test::TempDir dir;
    fs::create_directories(dir / "scenes" / "sub");
    fs::create_directories(dir / "other");
    test::write_text(dir / "other" / "part.obj", kTriangleObj);
    test::write_text(dir / "scenes" / "s.json", R"({"geometries": [{"mesh": "part.obj"}]})");
    std::string msg;
    in_folder(dir / "other", [&] { msg = json_error(fs::path("..") / "scenes" / "s.json"); });
    expect_has(msg, "../scenes/s.json: geometries[0].mesh: ../scenes/part.obj: cannot open");
    // Beside the file, in a folder below it, by an absolute path: found from any current folder.
    test::write_text(dir / "scenes" / "part.obj", kTriangleObj);
    test::write_text(dir / "scenes" / "sub" / "two.obj", kTriangleObj + "f 3 2 1\n");
    test::write_text(dir / "scenes" / "t.json", R"({"geometries": [{"mesh": "part.obj"}, {"mesh": "sub/two.obj"},
        {"mesh": ")" + (dir / "other" / "part.obj").string() +
                                                    R"("}, {"mesh": "icosphere-1"}]})");
    SceneDesc s;
    in_folder(dir / "other", [&] { s = load_scene_json(fs::path("..") / "scenes" / "t.json"); });
    ASSERT_EQ(s.geometries.size(), 4u);
    EXPECT_EQ(std::get<Mesh>(s.geometries[0]).triangles.size(), 1u);
    EXPECT_EQ(std::get<Mesh>(s.geometries[1]).triangles.size(), 2u);
    EXPECT_EQ(std::get<Mesh>(s.geometries[2]).triangles.size(), 1u);
    EXPECT_EQ(std::get<Mesh>(s.geometries[3]).triangles.size(), 80u);
}

// The rule (json_mesh_path): a '/' or a '.' makes a path; anything else is a
// mesh name, and an unknown name is an error, never a file of that name.
TEST(SceneJsonMeshes, NamesAreNeverFiles) {
    EXPECT_EQ(json_mesh_path("scenes", "part.obj"), fs::path("scenes/part.obj"));
    EXPECT_EQ(json_mesh_path("scenes", "sub/part"), fs::path("scenes/sub/part"));
    EXPECT_EQ(json_mesh_path("scenes", "/abs/part.ply"), fs::path("/abs/part.ply"));
    EXPECT_EQ(json_mesh_path("", "part.obj"), fs::path("part.obj"));
    EXPECT_EQ(json_mesh_path("scenes", "bunny"), std::nullopt);
    EXPECT_EQ(json_mesh_path("scenes", "icosphere-2"), std::nullopt);
    test::TempDir dir;
    test::write_text(dir / "bunnyy", kTriangleObj);  // a file named like the name: not read
    std::string msg;
    in_folder(dir.path(), [&] { msg = text_error(R"({"geometries": [{"mesh": "bunnyy"}]})"); });
    expect_has(msg, "t.json: geometries[0].mesh: 'bunnyy' is neither a mesh name (dragon, ");
    expect_has(msg, "nor a file path");
}

// A NUL in a mesh string cut the path there ("part.obj\u0000.ply" opened part.obj).
TEST(SceneJsonMeshes, NulInAMeshStringIsRefused) {
    test::TempDir dir;
    test::write_text(dir / "part.obj", kTriangleObj);
    test::write_text(dir / "s.json", R"({"geometries": [{"mesh": "part.obj\u0000.ply"}]})");
    const std::string msg = json_error(dir / "s.json");
    expect_has(msg, (dir / "s.json").string() + R"(: geometries[0].mesh: 'part.obj\x00.ply' contains a NUL character)");
    expect_has(text_error(R"({"geometries": [{"mesh": "bunny\u0000"}]})"),
               "geometries[0].mesh: 'bunny\\x00' contains a NUL");
}

// Text from the file is quoted short with its control characters escaped:
// a 1 MB unknown key was echoed whole, an ESC in a key, a name or a file name
// reached the terminal raw.
TEST(SceneJsonMessages, FileTextIsQuotedShortAndEscaped) {
    const std::string big(std::size_t(1) << 20, 'k');
    std::string msg = text_error(R"({")" + big + R"(": 1})");
    expect_has(msg, "t.json: ['kkkk");
    expect_has(msg, "...']: unknown key");
    EXPECT_LT(msg.size(), 200u) << msg.size();
    msg = text_error(R"({"geometries": [{"spheres": [], "\u001b[31mred": 1}]})");
    expect_has(msg, R"(t.json: geometries[0]['\x1b[31mred']: unknown key)");
    EXPECT_EQ(msg.find('\x1b'), std::string::npos);
    msg = text_error(R"({"geometries": [{"spheres": []}], "instances": [{"geometry": "\u001b]0;x\u0007"}]})");
    expect_has(msg, R"(t.json: instances[0].geometry: no geometry named '\x1b]0;x\x07')");
    msg = text_error(
        R"({"geometries": [{"name": "a", "spheres": []}, {"name": "a", "spheres": [], "radius": 1, "radius": 2}]})");
    expect_has(msg, "t.json: geometries[1]: duplicate key 'radius'");
    // nlohmann's message quotes the token it stopped in: cut short too.
    msg = text_error(R"({")" + big + "\x01" + R"("})");
    expect_has(msg, "t.json: not valid JSON at line 1, column 1048579: syntax error while parsing object key");
    EXPECT_LT(msg.size(), 300u) << msg.size();
    // File names, in the JSON loader's and the mesh loaders' messages.
    test::TempDir dir;
    const fs::path odd = dir / "a\x1b[2Jb.json";
    test::write_text(odd, "{");
    msg = json_error(odd);
    expect_has(msg, R"(a\x1b[2Jb.json: not valid JSON)");
    EXPECT_EQ(msg.find('\x1b'), std::string::npos) << msg;
    msg = json_error(dir / "c\x1b.json");
    expect_has(msg, R"(c\x1b.json: cannot open)");
    EXPECT_EQ(msg.find('\x1b'), std::string::npos) << msg;
    try {
        io::load_mesh(dir / "m\x1b.obj");
        ADD_FAILURE() << "loaded";
    } catch (const Error& e) {
        expect_has(e.what(), R"(m\x1b.obj: cannot open)");
    }
}

// Without "instances" every geometry is placed once, untransformed (it placed
// nothing: every ray missed), as Python's simdbvh.Scene without instances=;
// an explicit empty list places nothing.
TEST(SceneJsonInstances, AbsentPlacesEveryGeometryOnceEmptyPlacesNone) {
    const std::string g = R"("geometries": [{"spheres": [{"center": [0, 0, 0], "radius": 1}]},
                                             {"boxes": [{"min": [2, 0, 0], "max": [3, 1, 1]}]}])";
    const SceneDesc s = parse_scene_json("{" + g + "}", ".", "t.json");
    ASSERT_EQ(s.instances.size(), 2u);
    for (std::uint32_t i = 0; i < 2; ++i) {
        EXPECT_EQ(s.instances[i].geometry, i);
        EXPECT_EQ(s.instances[i].transform.m, Affine3{}.m);
    }
    EXPECT_TRUE(parse_scene_json("{" + g + R"(, "instances": []})", ".", "t.json").instances.empty());
    EXPECT_TRUE(parse_scene_json(R"({"planes": [{"point": [0, 0, 0], "normal": [0, 1, 0]}]})", ".", "t.json")
                    .instances.empty());
}

// "scale": [1e-11, 1e10, 1] (det 0.1) was refused as singular; a singular
// transform's message says what the test measures and its limit.
TEST(SceneJsonInstances, AnisotropicScaleIsAccepted) {
    const std::string g = R"("geometries": [{"spheres": [{"center": [0, 0, 0], "radius": 1}]}])";
    const SceneDesc s =
        parse_scene_json("{" + g + R"(, "instances": [{"geometry": 0, "scale": [1e-11, 1e10, 1]}]})", ".", "t.json");
    ASSERT_EQ(s.instances.size(), 1u);
    EXPECT_EQ(s.instances[0].transform.m[0][0], 1e-11f);
    EXPECT_EQ(s.instances[0].transform.m[1][1], 1e10f);
    expect_has(text_error("{" + g + R"(, "instances": [{"geometry": 0, "scale": [1, 0, 1]}]})"),
               "t.json: instances[0].transform: singular: |det| is 0 of the sum of the magnitudes of its six terms, "
               "at most 2^-40");
}

// An array of n instances parses in work linear in n (nlohmann's parser
// callback walked the whole array after each element: 10^5 instances took
// 1.5 s, 10^6 270 s). Not timed: this checks the content of a large array.
TEST(SceneJsonBounds, LargeInstanceArrays) {
    const std::size_t n = 100'000;
    std::string text = R"({"geometries": [{"spheres": [{"center": [0, 0, 0], "radius": 1}]}], "instances": [)";
    for (std::size_t i = 0; i < n; ++i)
        text += (i ? ", " : "") + std::string(R"({"geometry": 0, "translate": [)") + std::to_string(i) + ", 0, 0]}";
    text += "]}";
    const SceneDesc s = parse_scene_json(text, ".", "t.json");
    ASSERT_EQ(s.instances.size(), n);
    for (std::size_t i = 0; i < n; i += 997) EXPECT_EQ(s.instances[i].transform.m[0][3], float(i)) << i;
}

// Nesting is limited to 512 arrays and objects: 10^6 nested objects stop at
// the limit (their document took about 150 bytes each, 10^7 of them 3 GB).
TEST(SceneJsonBounds, NestingDeeperThan512Stops) {
    const std::size_t n = 1'000'000;
    const std::string deep = repeat(R"({"a":)", n) + "{}" + std::string(n, '}');
    std::string msg;
    const double mib = peak_growth_mib([&] { msg = text_error(deep); });
    expect_has(msg, "t.json: not valid JSON for a scene: arrays and objects nested deeper than 512 levels");
    EXPECT_LT(mib, 32.0) << msg;
    // 512 levels are parsed (the scene's own checks answer), 513 are not.
    expect_has(text_error(R"({"planes": )" + std::string(511, '[') + std::string(511, ']') + "}"),
               "t.json: planes[0]: expected an object");
    expect_has(text_error(R"({"planes": )" + std::string(512, '[') + std::string(512, ']') + "}"),
               "nested deeper than 512 levels");
}

// The text is held once: 64 MiB of whitespace around a scene cost about 64
// MiB (it was copied from the stream into a string, and nlohmann's lexer kept
// a copy of each run of whitespace in its token buffer).
TEST(SceneJsonBounds, WhitespaceIsHeldOnce) {
    test::TempDir dir;
    const fs::path file = dir / "blank.json";
    {
        std::ofstream out(file, std::ios::binary);
        const std::string mib(std::size_t(1) << 20, ' '), lines(std::size_t(1) << 20, '\n');
        for (int i = 0; i < 32; ++i) out << mib << lines;
        out << R"({"geometries": [{"spheres": [{"center": [0, 0, 0], "radius": 1}]}]})" << mib;
    }
    SceneDesc s;
    const double mib = peak_growth_mib([&] { s = load_scene_json(file); });
    EXPECT_EQ(s.geometries.size(), 1u);
    EXPECT_LT(mib, 96.0);
}

// Long runs of whitespace are passed short, but not inside strings (names
// differing only there stay different, an escaped quote included), and errors
// after them give the file's own line and column.
TEST(SceneJsonBounds, LongWhitespaceKeepsStringsAndPositions) {
    // Runs of 5000 and of 4096 spaces inside names, plain and after an escaped quote:
    // squeezed to 4096, two names would be the same ("duplicate name").
    const std::string sphere = R"("spheres": [{"center": [0, 0, 0], "radius": 1}])";
    std::string text = R"({"geometries": [)";
    for (const char* head : {"", "\\\""})
        for (std::size_t run : {5000, 4096})
            text += std::string(text.back() == '[' ? "" : ", ") + R"({"name": ")" + head + std::string(run, ' ') +
                    "x\", " + sphere + "}";
    text += R"(], "instances": [{"geometry": "\")" + std::string(4096, ' ') + "x\"}]}";
    const SceneDesc s = parse_scene_json(text, ".", "t.json");
    ASSERT_EQ(s.geometries.size(), 4u);
    ASSERT_EQ(s.instances.size(), 1u);
    EXPECT_EQ(s.instances[0].geometry, 3u);
    expect_has(text_error(std::string(3, '\n') + std::string(10000, ' ') + "{\"geometries\":\n" +
                          std::string(20000, ' ') + "[1, NaN]}"),
               "t.json: not valid JSON at line 5, column 20005: syntax error while parsing value - invalid literal");
    expect_has(text_error("{\"geometries\": [1, NaN]}"), "t.json: not valid JSON at line 1, column 20: syntax error");
}

}  // namespace
}  // namespace simdbvh::workloads
