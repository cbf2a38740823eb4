#include "common.h"

#include <algorithm>

#include <unistd.h>

#include <iostream>

#include "simdbvh/workloads/scenes.h"

namespace simdbvh::cli {

void progress(const std::string& msg, bool force) {
    if (force || isatty(STDERR_FILENO)) std::cerr << "[simdbvh] " << msg << "\n" << std::flush;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

Mesh load_scene_with_progress(const std::string& name) {
    const auto t0 = std::chrono::steady_clock::now();
    progress("loading " + name + " ...");
    Mesh m = workloads::load_scene(name);
    progress("loaded " + name + ": " + std::to_string(m.size()) + " triangles in " + std::to_string(seconds_since(t0)) +
             " s");
    return m;
}

std::string default_scene(std::string* why) {
    if (workloads::is_cached("dragon")) {
        if (why) *why = "the Stanford Dragon (cached)";
        return "dragon";
    }
    if (why) *why = "the procedural terrain (the dragon is not cached: run scripts/fetch_scenes.sh)";
    return "terrain";
}

}  // namespace simdbvh::cli
