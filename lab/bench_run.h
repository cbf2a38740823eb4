// SPDX-License-Identifier: MIT
#pragma once
// simdbvh bench, the run: every method on one scene (and the tree methods on
// the width scenes): builds cold and warm, Mrays/s per ray kind, query and
// thread count, traversal counters, agreement with brute force on a sample.
#include <map>
#include <string>
#include <vector>

#include "lab.h"
#include "accuracy.h"
#include "accuracy_run.h"
#include "refit_run.h"
#include "results_doc.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::lab {

struct BenchConfig {
    std::string scene, scene_why;
    std::vector<std::string> width_scenes;  // further scenes for the wide-vs-binary chart (tree methods only)
    bool quick = false;                     // --quick: 65,536 rays, 3 repetitions
    bool full = false;                      // --full: 262,144 rays, 20 refit frames, the terrain's width rows
    int threads_all = 1;
    int reps = 5;           // timed traces per row (median), after one untimed warm-up; methods interleaved
    int build_reps = 3;     // warm builds per method (median), after the cold (first) one
    int refit_frames = 20;  // the refit sequence (refit_run.h); 0: none
    std::size_t rays = 262144, sample = 1000, stats_rays = 16384;
    std::string json_file, report_dir;  // report_dir empty: --no-report
    std::vector<ResultsDoc> docs;       // --readme, --publish
    std::string machine, command;
};

struct Record {
    std::string scene, method, isa, builder, ray_kind, query;
    int threads = 1;
    int width = 0;  // node width: 2 (bvh2), 4, 8, 16; 0 for brute and Embree
    double mrays_per_s = 0;
    double build_ms = 0, build_ms_all = 0;            // cold: the first build of the process for this method
    double build_ms_warm = 0, build_ms_all_warm = 0;  // warm: median of build_reps further builds
    double collapse_ms = 0;  // the wide BVHs: collapse + pack (median of the warm builds); in build_ms too
    double bytes_per_triangle = 0, sah_cost = 0;
    double nodes_per_ray = -1, box_tests_per_ray = -1;  // our trees (TraceStats on a sample); -1: not counted
    double agreement = 0;  // fraction of the accuracy sample that agrees with the reference
    Tally tally;
    std::size_t rays = 0, sample = 0;
};

struct BenchResults {
    std::vector<Record> records;  // every method on c.scene
    std::vector<Record> widths;   // bvh2 and bvhN per ISA, one thread, on c.scene and every width scene
    std::vector<std::pair<std::string, std::size_t>> width_scene_sizes;  // (scene, triangles)
    std::vector<RefitFrame> refit;                                       // the refit sequence on c.scene
    // The hard accuracy families (quick cases, `simdbvh accuracy --quick --family ...`) for our default
    // paths and Embree's: family -> one row per method, summed over the family's cases.
    std::map<std::string, std::vector<AccuracyRow>> hard;
};

struct NamedMesh {
    std::string name;
    Mesh mesh;
};

// `mesh` is c.scene; `width_meshes` the width scenes (loaded up front, so a bad one fails before the run).
// The families whose disagreements the speed-against-accuracy chart shows (the bench's own rays agree).
inline constexpr workloads::Family kHardFamilies[] = {workloads::Family::watertight, workloads::Family::grazing,
                                                      workloads::Family::offsets, workloads::Family::direction_scale};
// Runs them on one thread per trace (the reference on `threads`).
std::map<std::string, std::vector<AccuracyRow>> run_hard_families(int threads);
// The bench label ("bvh2", "bvh8/avx2", "embree/medium/default") an accuracy variant's row measures; empty
// when no bench row runs that variant.
std::string bench_label_of(const std::string& variant);

BenchResults run_bench(const BenchConfig& c, const Mesh& mesh, const std::vector<NamedMesh>& width_meshes);

}  // namespace simdbvh::lab
