#pragma once
// The files a scene name leads to: what an output must never replace.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace simdbvh::workloads {

struct SceneInput {
    std::filesystem::path path;
    // How the name reaches it, for messages: "" (the name is this file), "the cache file of 'bunny'",
    // "geometries[2].mesh", chained with " -> " through nested references ("geometries[2].mesh ->
    // sub/inner.json: geometries[0].mesh").
    std::string via;
};

// Every file that load_scene(name) or load_scene_desc(name) may read, under either reading (a name that is
// not a scene of the other loader is a path there): the file at that path; a cached scene's file
// (cached_scene_file); the cached meshes of a built-in scene (room: bunny and teapot; instances-N: dragon);
// a JSON scene's mesh references, resolved as load_scene_json resolves them (json_mesh_path),
// and theirs in turn (each JSON file once). Procedural names (icosphere, soup, terrain, spheres-N) read
// nothing, nor does a cached name that is not cached. Other paths are listed whether or not a file exists
// there; a JSON file that does not parse adds only itself (loading it fails before any output is written).
std::vector<SceneInput> scene_input_files(std::string_view name_or_path);

}  // namespace simdbvh::workloads
