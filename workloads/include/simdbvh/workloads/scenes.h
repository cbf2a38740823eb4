#pragma once
// Named scenes: real meshes from the npm cache (scripts/fetch_scenes.sh) and
// procedural scenes generated in code (always available, offline).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "simdbvh/kernels/mesh.h"

namespace simdbvh::workloads {

// The cache folder: $SIMDBVH_CACHE, else <source tree>/.cache/scenes.
std::filesystem::path cache_dir();

// Names: dragon, dragon-res2, dragon-res3, dragon-res4, bunny, teapot (cache);
// icosphere[-N] (level N, default 4), soup[-N] (N random triangles, default
// 10000), terrain (>= 1M triangles, uneven density). Anything else is a path.
std::vector<std::string> scene_names();
// A name load_scene() reads without a file of that name: a cached scene's
// name, icosphere[-N], soup[-N] or terrain (N decimal digits; a bad level or
// count is load_scene's to report).
bool is_mesh_name(std::string_view name);
// The cached file of a named npm scene, or nullopt when it is not cached.
std::optional<std::filesystem::path> cached_scene_file(std::string_view name);
bool is_cached(std::string_view name);
// Loads a scene by name or path; throws simdbvh::Error (a missing cached
// scene says how to fetch it).
Mesh load_scene(std::string_view name_or_path);

// Procedural scenes.
Mesh icosphere(int level, float radius = 1.0f, Vec3 center = {});             // closed, 20*4^level triangles
Mesh random_soup(std::size_t triangles, std::uint64_t seed);                  // in the unit cube
Mesh terrain(std::size_t min_triangles = 1'000'000, std::uint64_t seed = 1);  // fractal terrain + scattered objects

}  // namespace simdbvh::workloads
