#pragma once
// Shared test helpers: scenes from the npm cache (skipped with a clear message
// when not fetched), tiny meshes, temp folders and files.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <string_view>

#include "simdbvh/kernels/mesh.h"

namespace test {

// True when `name` is procedural, a path, or a cached npm scene.
bool available(std::string_view name);
// "scene 'dragon' is not cached in <dir>; run scripts/fetch_scenes.sh".
std::string skip_message(std::string_view name);

// Loads a scene by name; when an npm scene is not cached, records a GTest skip
// and returns an empty mesh. Callers return right after:
//   const auto m = test::load_or_skip("dragon"); if (::testing::Test::IsSkipped()) return;
// or use SIMDBVH_LOAD_OR_SKIP(m, "dragon"); which does both.
simdbvh::Mesh load_or_skip(std::string_view name);
#define SIMDBVH_LOAD_OR_SKIP(var, name)                     \
    const ::simdbvh::Mesh var = ::test::load_or_skip(name); \
    if (::testing::Test::IsSkipped()) return

// Tiny meshes.
simdbvh::Mesh one_triangle();  // (0,0,0) (1,0,0) (0,1,0)
simdbvh::Mesh unit_cube();     // [0,1]^3, 12 triangles, outward counter-clockwise

// A fresh, empty temporary folder removed (recursively) on destruction.
class TempDir {
public:
    TempDir();
    // in_memory: under /dev/shm when it is usable (many small files, e.g. fuzzing).
    explicit TempDir(bool in_memory);
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(std::string_view name) const { return path_ / std::string(name); }

private:
    std::filesystem::path path_;
};

void write_text(const std::filesystem::path& file, std::string_view text);
std::string read_bytes(const std::filesystem::path& file);
// gzip-compresses `bytes` into `file` (zlib).
void write_gzip(const std::filesystem::path& file, std::string_view bytes);
// tests/data/<name> in the source tree.
std::filesystem::path data_file(std::string_view name);

}  // namespace test
