// SPDX-License-Identifier: MIT
#pragma once
// simdbvh bench --sweep (the data behind --method auto's cost model): time to answer (build + trace) for every
// method over a grid of scene sizes and ray counts, one thread and all cores,
// primary and incoherent rays; the cost model fitted to the grid's fit scenes
// and checked on held-out points (sweep_fit.cpp); the report in
// sweep_report.cpp.
#include <string>
#include <vector>

#include "lab.h"
#include "results_doc.h"
#include "simdbvh/accel/cost_model.h"

namespace simdbvh::lab {

struct SweepConfig {
    bool quick = false;
    int threads_all = 1;
    int reps = 5;           // timed traces per row (median), after one untimed warm-up; methods interleaved
    int build_reps = 3;     // warm builds per method (median), after the cold one
    double budget_ms = 40;  // a trace expected to take longer is timed on evenly spaced rays and scaled
    Isa isa = Isa::scalar;  // brute8 and the wide trees run with it (SIMDBVH_ISA forces another)
    std::string json_file, report_dir, model_out;
    std::vector<ResultsDoc> docs;  // --readme, --publish
    std::string machine, command;
};

struct SweepScene {
    std::string name;
    std::size_t triangles = 0;
    bool held_out = false;          // not used for fitting: the auto check's points
    std::vector<std::size_t> rays;  // the ray counts measured on it
};

struct SweepRow {
    std::string scene, method, ray_kind;
    std::size_t triangles = 0, rays = 0;
    bool held_out = false;
    int threads = 1;
    double build_ms = 0, trace_ms = 0;  // build: median of the warm builds; trace: median of reps
    std::size_t traced_rays = 0;        // < rays: timed on this many evenly spaced rays and scaled
    double total_ms() const { return build_ms + trace_ms; }
};

struct SweepCheck {  // one held-out point: auto's choice against the best measured method
    std::string scene, ray_kind;
    std::size_t triangles = 0, rays = 0;
    int threads = 1;
    std::string chosen, best;
    double predicted_ms = 0, chosen_ms = 0, best_ms = 0, embree_ms = 0;
    double ratio() const { return best_ms > 0 ? chosen_ms / best_ms : 0.0; }
};

struct SweepResults {
    std::vector<SweepScene> scenes;
    std::vector<SweepRow> rows;
    CostModel model;  // fitted to the one-thread rows of the fit scenes
    std::vector<SweepCheck> checks;
};

// The scenes the sweep measures (cached meshes where available, procedural stand-ins otherwise).
std::vector<SweepScene> sweep_scenes(bool quick);
SweepResults run_sweep(const SweepConfig& c);
// sweep_fit.cpp: the model from the fit rows, and the check on the held-out rows.
CostModel fit_cost_model(const std::vector<SweepRow>& rows, Isa isa);
std::vector<SweepCheck> check_auto(const std::vector<SweepRow>& rows, const CostModel& model);
// Every file report_sweep writes beyond --json and sweep.md, for check_outputs; throws when --model-out or a
// doc lacks its block (before the run).
void add_sweep_outputs(const SweepConfig& c, NamedPaths& outputs);
void report_sweep(const SweepConfig& c, const SweepResults& r);

}  // namespace simdbvh::lab
