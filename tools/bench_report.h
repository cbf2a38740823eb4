#pragma once
// The bench's records and its Markdown report (charts by scripts/plot_bench.py,
// pictures rendered here).
#include <string>
#include <vector>

#include "accuracy.h"
#include "simdbvh/mesh.h"

namespace simdbvh::cli {

struct Record {
    std::string method, isa, builder, ray_kind, query;
    int threads = 1;
    double mrays_per_s = 0, build_ms = 0, build_ms_all = 0, bytes_per_triangle = 0, sah_cost = 0;
    double agreement = 0;  // fraction of the accuracy sample that agrees with the reference
    Tally tally;
    std::size_t rays = 0, sample = 0;
};

struct ReportInputs {
    std::string dir, json_file, scene, scene_why, machine;
    const Mesh* mesh = nullptr;
    const std::vector<Record>* records = nullptr;
    bool quick = false;
    int threads_all = 1;
    std::string readme;  // non-empty: replace the README's results block
    std::string command; // the command line that produced the records
};

void write_report(const ReportInputs& in);

}  // namespace simdbvh::cli
