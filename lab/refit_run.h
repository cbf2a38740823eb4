// SPDX-License-Identifier: MIT
#pragma once
// simdbvh bench, the refit sequence (docs/results.md, "Refit"): the bench scene twisted a
// little more each frame; per frame, our BVH8 refit against a BVH8 rebuild and
// Embree's refit (RTC_BUILD_QUALITY_REFIT) against Embree's rebuild (medium),
// in ms and in Mrays/s after each, one thread (our refit also on all cores).
#include <string>
#include <vector>

#include "lab.h"
#include "report.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::lab {

struct BenchConfig;

struct RefitFrame {
    int frame = 0;
    double radians = 0;                                     // twist of this frame (top of the mesh against its bottom)
    double refit_ms = 0, refit_ms_all = 0, rebuild_ms = 0;  // ours: BVH8 refit (1 thread, all cores), Bvh8::build
    double embree_refit_ms = 0, embree_rebuild_ms = 0;      // update_vertices: copy + rtcCommitScene
    double sah_refit = 0, sah_rebuild = 0;                  // BVH8 SAH cost after each
    // Mrays/s per ray kind (primary, incoherent), closest hit, one thread.
    double mrays_refit[2] = {}, mrays_rebuild[2] = {}, mrays_embree_refit[2] = {}, mrays_embree_rebuild[2] = {};
    std::size_t differ = 0;  // rays whose refit hit differs in any bit from the rebuild's (must be 0)
};

// c.refit_frames frames (0: none); rebuilds and refits are medians of
// max(1, c.build_reps) after the frame's first (untimed) one; traces the
// median of c.reps after a warm-up, on c.rays / 4 rays per kind.
std::vector<RefitFrame> run_refit(const BenchConfig& c, const Mesh& mesh);

Json refit_json(const std::vector<RefitFrame>& frames);
// The Markdown section (a table of every frame; the chart when `chart`).
std::string refit_markdown(const std::vector<RefitFrame>& frames, const std::string& img_dir, bool chart);

}  // namespace simdbvh::lab
