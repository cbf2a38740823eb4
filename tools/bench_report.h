#pragma once
// The bench's report: the terminal table, the JSON file (scripts/plot_bench.py
// reads it), DIR/report.md with charts and pictures, and the README's results
// block (--readme).
#include "bench_run.h"

namespace simdbvh::cli {

void report_bench(const BenchConfig& c, const Mesh& mesh, const BenchResults& r);

}  // namespace simdbvh::cli
