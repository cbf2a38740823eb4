#pragma once
// Scene descriptions (simdbvh/scene/scene.h) from names and files: the
// built-in scenes and the strict JSON scene format (docs/scenes.md#scene-files-json).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string_view>
#include <vector>

#include "simdbvh/workloads/rays.h"
#include "simdbvh/scene/scene.h"

namespace simdbvh::workloads {

// N copies of a mesh with random rotations (any axis), scales (0.5..1.5) and
// positions (a cube growing with cbrt(N), in units of the mesh's diagonal),
// from a fixed seed (SplitMix64: the same scene on every machine).
SceneDesc instances_scene(const Mesh& mesh, std::size_t n, std::uint64_t seed = 14);
// N random analytic spheres in the unit cube (radius 0.1 .. 0.5 of the mean
// spacing 1/cbrt(N), seed 002's setting), one geometry, one identity instance.
SceneDesc spheres_scene(std::size_t n, std::uint64_t seed = 2);
// Seed 004's room: floor and three walls as planes, a box set, a sphere set,
// the bunny and two rotated teapots as instances (bunny and teapot from the
// cache: throws simdbvh::Error saying how to fetch them when missing).
SceneDesc room_scene();

// instances-N (N dragons), spheres-N, room. Every name of the two families
// ("instances-" or "spheres-" followed by anything without a '/' or a '.') is
// a built-in name, so builtin_scene reports a bad count ("spheres-0", "spheres--5":
// N must be a whole number from 1 to 10000000) instead of a mesh loader.
bool is_builtin_scene(std::string_view name);
SceneDesc builtin_scene(std::string_view name);

// A JSON scene file, read as the mesh files are: a regular file (symlinks
// resolved; a FIFO, device or folder refused), raw or gzip, at most 4 GiB
// (and the physical memory). Throws simdbvh::Error "<file>: <JSON path>:
// <problem>" for malformed JSON, unknown keys, wrong types, missing
// references, negative radii, singular transforms or non-finite numbers. Mesh
// references are mesh names or paths relative to the file's folder
// (json_mesh_path).
SceneDesc load_scene_json(const std::filesystem::path& file);
// How a JSON scene's "mesh" string is read: a string with a '/' or a '.' is a
// mesh file's path (a file name has its format's extension), relative to the
// JSON file's folder `json_dir` unless absolute, and never looked up in the
// current folder; anything else is a mesh name for load_scene (bunny,
// icosphere-3, ...; is_mesh_name), never a file. Returns the path, or
// nullopt for a name.
std::optional<std::filesystem::path> json_mesh_path(const std::filesystem::path& json_dir, std::string_view ref);
SceneDesc parse_scene_json(std::string_view text, const std::filesystem::path& base_dir, std::string_view label);

// A built-in name, a .json file, or any mesh load_scene() takes (as one
// geometry with one identity instance).
SceneDesc load_scene_desc(std::string_view name_or_path);

// The camera of simdbvh render --scene and of the scene benches' primary rays:
// default_camera over the bounded part (world_bounds), with the eye moved
// toward the centre until it is in front of every plane whose front side
// holds the centre (a room's walls).
Camera scene_camera(const SceneDesc& desc, int width, int height);
// Its rays on a square image of about n pixels (at least 16 x 16).
std::vector<Ray> scene_camera_rays(const SceneDesc& desc, std::size_t n);

}  // namespace simdbvh::workloads
