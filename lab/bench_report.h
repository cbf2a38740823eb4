#pragma once
// The bench's report: the terminal table, the JSON file (scripts/plot_bench.py
// reads it), DIR/report.md with charts and pictures, and the README's results
// block (--readme).
#include "lab.h"
#include "bench_run.h"

namespace simdbvh::lab {

// Every file report_bench writes beyond --json and report.md (pictures, charts, --readme and --publish docs
// and their pictures), for check_outputs; throws when a doc lacks its block (before the run).
void add_bench_outputs(const BenchConfig& c, NamedPaths& outputs);
void report_bench(const BenchConfig& c, const Mesh& mesh, const BenchResults& r);

}  // namespace simdbvh::lab
