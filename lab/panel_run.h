// SPDX-License-Identifier: MIT
#pragma once
// simdbvh panel, the run: one row per builder (binned SAH at 8/16/32/64 bins,
// sweep SAH, midpoint, median, variance) and the sphere hierarchy.
#include <array>
#include <string>
#include <vector>

#include "lab.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::lab {

inline constexpr int kFrameW = 640, kFrameH = 480;
// Leaf-size histogram buckets: 1, 2, 3, 4, 5-8, 9-16, 17+.
inline constexpr std::array<const char*, 7> kLeafBuckets = {"1", "2", "3", "4", "5-8", "9-16", "17+"};

struct PanelConfig {
    std::string scene, scene_why;
    bool quick = false;
    int threads_all = 1, reps = 5, build_reps = 3;
    std::size_t rays = 262144, stats_rays = 32768;
    std::string json_file, report_dir;  // report_dir empty: --no-report
    std::string machine, command;
    Isa isa = Isa::scalar;  // the BVH8's
};

struct PanelRow {
    std::string name;     // e.g. "sah-binned/16", "spheres"
    std::string builder;  // the BVH2 builder ("variance" for spheres)
    int bins = 0;
    bool skipped = false;
    std::string note;
    double build_ms_1 = 0, build_ms_all = 0, bvh8_ms = 0;
    double sah = 0, sah_bvh8 = 0, bytes_per_tri = 0, bytes_per_tri_bvh8 = 0;
    int depth = 0;
    std::size_t nodes = 0, leaves = 0;
    std::array<std::size_t, 7> leaf_hist{};
    std::array<double, 3> mrays2{}, mrays8{};  // per kind, closest hit, 1 thread
    std::array<double, 3> nodes_per_ray2{}, nodes_per_ray8{}, tris_per_ray2{};
    double frame_ms = 0;  // 640x480 primary, BVH2 (or spheres), 1 thread, closest hit
    double frame_ms_bvh8 = 0;
    std::size_t frame_mismatch = 0;  // frame hits that differ (bitwise) from the reference row
};

std::vector<PanelRow> run_panel(const PanelConfig& c, const Mesh& mesh);
// Terminal table, JSON (c.json_file), panel.md with charts (c.report_dir).
void report_panel(const PanelConfig& c, const Mesh& mesh, const std::vector<PanelRow>& rows);

}  // namespace simdbvh::lab
