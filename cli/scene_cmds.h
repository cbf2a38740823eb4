#pragma once
// info and trace on scene descriptions (built-in instances-N, spheres-N, room,
// or a .json scene file): the scene layer of simdbvh/scene.
#include <string>

#include "image.h"
#include "methods.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/scene/scene.h"

namespace simdbvh::cli {

// True for the names the scene layer takes (a built-in scene or *.json).
bool is_scene_desc(const std::string& name);
// One rule for the options of the mesh methods that scenes have no use for (--test, --box, --quality,
// --robust, --packets, --reorder, --stats, --drop-invalid, --expected-rays, --heatmap): a UsageError naming
// the option when it is given.
void refuse_mesh_options(const Options& o, const std::string& name);
// --instance-bounds corners | child-corners (default child-corners).
InstanceBounds parse_instance_bounds(const Options& o);

int info_scene(const std::string& name, const MethodSpec& spec, InstanceBounds bounds);
// Writes a scene hit file (simdbvh/scene/scene_hits.h). --method bvh4|bvh8|bvh16 (default: bvh8) or brute.
int trace_scene(const Options& o, const std::string& name, const std::string& rays_file, const std::string& out,
                const MethodSpec& spec, bool any, InstanceBounds bounds);

// gen-rays on a scene: a mesh standing in for the scene's bounded extent
// (world_bounds), enough for primary and incoherent rays (diffuse needs a mesh).
Mesh scene_bounds_proxy(const std::string& name);

// Eye-light picture (|cos| of ray and normal), tinted per instance; planes grey.
Image render_scene_image(const std::string& name, const MethodSpec& spec, InstanceBounds bounds, int width, int height);
// The same written to `out` (PNG).
int render_scene(const std::string& name, const MethodSpec& spec, InstanceBounds bounds, int width, int height,
                 const std::string& out);

}  // namespace simdbvh::cli
