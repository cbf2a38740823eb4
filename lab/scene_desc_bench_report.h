// SPDX-License-Identifier: MIT
#pragma once
// simdbvh bench on a scene description, the report: terminal tables, the JSON
// file (--json), DIR/report.md with charts (scripts/plot_scene_bench.py) and a
// render, and the results block <!-- bench-scene:NAME:begin --> ... end
// (--readme, --publish; NAME is the scene's name without a .json suffix).
#include "lab.h"
#include "bench_run.h"
#include "scene_desc_bench_run.h"

namespace simdbvh::lab {

// Every file report_scene_desc_bench writes beyond --json and report.md, for check_outputs; throws when a doc
// lacks its block (before the run).
void add_scene_desc_bench_outputs(const BenchConfig& c, NamedPaths& outputs);
void report_scene_desc_bench(const BenchConfig& c, const SceneDescBenchResults& r);

}  // namespace simdbvh::lab
