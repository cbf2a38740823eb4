#pragma once
// Shared CLI plumbing: progress on stderr, timing, scene loading.
#include <chrono>
#include <string>
#include <vector>

#include "simdbvh/kernels/mesh.h"

namespace simdbvh::cli {

// Progress on stderr for long phases, only when stderr is a terminal (or
// always with force, used by the bench).
void progress(const std::string& msg, bool force = false);
double seconds_since(std::chrono::steady_clock::time_point t0);
// The median of timings (the upper middle one for an even count); 0 for none.
double median(std::vector<double> v);
Mesh load_scene_with_progress(const std::string& name_or_path);
// The default scene: the dragon when cached, else the large procedural terrain.
std::string default_scene(std::string* why = nullptr);

int cmd_build(const std::vector<std::string>& args);
int cmd_info(const std::vector<std::string>& args);
int cmd_gen_rays(const std::vector<std::string>& args);
int cmd_trace(const std::vector<std::string>& args);
int cmd_render(const std::vector<std::string>& args);
int cmd_gen_points(const std::vector<std::string>& args);
int cmd_distance(const std::vector<std::string>& args);
int cmd_inside(const std::vector<std::string>& args);
int cmd_classify(const std::vector<std::string>& args);

}  // namespace simdbvh::cli
