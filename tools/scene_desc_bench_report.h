// SPDX-License-Identifier: MIT
#pragma once
// simdbvh bench on a scene description, the report: terminal tables, the JSON
// file (--json), DIR/report.md with charts (scripts/plot_scene_bench.py) and a
// render, and the README block <!-- bench-scene:NAME:begin --> ... end
// (--readme; NAME is the scene's name without a .json suffix).
#include "bench_run.h"
#include "scene_desc_bench_run.h"

namespace simdbvh::cli {

void report_scene_desc_bench(const BenchConfig& c, const SceneDescBenchResults& r);

}  // namespace simdbvh::cli
