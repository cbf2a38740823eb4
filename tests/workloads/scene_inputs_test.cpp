// workloads::scene_input_files: every file a scene name leads to, resolved as the
// loaders resolve it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "simdbvh/workloads/scene_inputs.h"
#include "support/scene.h"

namespace fs = std::filesystem;
namespace wl = simdbvh::workloads;

namespace {

std::vector<std::string> paths(std::string_view name) {
    std::vector<std::string> v;
    for (const wl::SceneInput& in : wl::scene_input_files(name)) v.push_back(in.path.string());
    return v;
}

// SIMDBVH_CACHE for the length of a test.
class CacheDir {
public:
    explicit CacheDir(const fs::path& dir) {
        if (const char* old = std::getenv("SIMDBVH_CACHE")) old_ = old;
        ::setenv("SIMDBVH_CACHE", dir.c_str(), 1);
    }
    ~CacheDir() { old_.empty() ? ::unsetenv("SIMDBVH_CACHE") : ::setenv("SIMDBVH_CACHE", old_.c_str(), 1); }

private:
    std::string old_;
};

TEST(SceneInputs, ProceduralNamesReadNothing) {
    for (const char* n : {"icosphere", "icosphere-3", "soup-100", "terrain"})
        EXPECT_TRUE(wl::scene_input_files(n).empty()) << n;
    // spheres-N reads nothing as a scene; to the mesh commands it is a path.
    EXPECT_EQ(paths("spheres-10"), std::vector<std::string>{"spheres-10"});
}

TEST(SceneInputs, AMeshPathIsItself) {
    EXPECT_EQ(paths("some/mesh.ply"), std::vector<std::string>{"some/mesh.ply"});
    const auto in = wl::scene_input_files("some/mesh.ply");
    EXPECT_EQ(in.at(0).via, "");
}

TEST(SceneInputs, CachedNamesAndBuiltinsLeadToTheCacheFiles) {
    test::TempDir dir;
    const CacheDir cache(dir.path());
    EXPECT_TRUE(wl::scene_input_files("bunny").empty());  // not cached: nothing is read (loading fails)
    test::write_text(dir / "bunny.ply", "x");
    test::write_text(dir / "teapot.ply", "x");
    EXPECT_EQ(paths("bunny"), std::vector<std::string>{(dir / "bunny.ply").string()});
    EXPECT_EQ(wl::scene_input_files("bunny").at(0).via, "the cache file of 'bunny'");
    // room: the bunny and the teapot; and, to the mesh commands, a file named "room".
    EXPECT_EQ(paths("room"),
              (std::vector<std::string>{(dir / "bunny.ply").string(), (dir / "teapot.ply").string(), "room"}));
    EXPECT_EQ(wl::scene_input_files("room").at(1).via, "the cache file of 'teapot'");
}

TEST(SceneInputs, JsonMeshesRelativeToTheFileAndNestedScenes) {
    test::TempDir dir;
    const CacheDir cache(dir.path() / "cache");
    fs::create_directories(dir / "cache");
    test::write_text(dir / "cache" / "bunny.ply", "x");
    fs::create_directories(dir / "sub");
    test::write_text(dir / "a.obj", "x");
    test::write_text(dir / "sub" / "b.obj", "x");
    test::write_text(dir / "sub" / "inner.json", R"({"geometries": [{"mesh": "b.obj"}, {"mesh": "../main.json"}]})");
    test::write_text(dir / "main.json", R"({"geometries": [{"mesh": "a.obj"}, {"spheres": []}, {"mesh": "bunny"},
        {"mesh": "icosphere-2"}, {"mesh": "sub/inner.json"}, {"mesh": "elsewhere.obj"}]})");
    const std::string main = (dir / "main.json").string();
    const auto in = wl::scene_input_files(main);
    std::vector<std::string> got;
    for (const auto& i : in) got.push_back(i.path.string());
    const std::vector<std::string> want{
        main,
        (dir / "a.obj").string(),
        (dir / "cache" / "bunny.ply").string(),
        (dir / "sub/inner.json").string(),
        (dir / "sub/inner.json").parent_path().string() + "/b.obj",
        (dir / "elsewhere.obj").string()};  // missing: still beside the file, never the cwd
    EXPECT_EQ(got, want);
    EXPECT_EQ(in.at(1).via, "geometries[0].mesh");
    EXPECT_EQ(in.at(2).via, "geometries[2].mesh -> the cache file of 'bunny'");
    EXPECT_EQ(in.at(4).via, "geometries[4].mesh -> " + (dir / "sub/inner.json").string() + ": geometries[0].mesh");
}

// Read as load_scene_json reads it: a gzip-compressed JSON scene names its meshes too.
TEST(SceneInputs, GzipJsonSceneNamesItsMeshes) {
    test::TempDir dir;
    test::write_text(dir / "a.obj", "x");
    test::write_gzip(dir / "z.json", R"({"geometries": [{"mesh": "a.obj"}]})");
    EXPECT_EQ(paths((dir / "z.json").string()),
              (std::vector<std::string>{(dir / "z.json").string(), (dir / "a.obj").string()}));
}

TEST(SceneInputs, UnparsableJsonIsOnlyItself) {
    test::TempDir dir;
    test::write_text(dir / "bad.json", "{ not json");
    EXPECT_EQ(paths((dir / "bad.json").string()), std::vector<std::string>{(dir / "bad.json").string()});
}

}  // namespace
