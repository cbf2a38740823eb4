// SPDX-License-Identifier: MIT
#pragma once
// simdbvh accuracy, the run: every ray family against every method variant,
// one row per (case, method), summed per family and per offset.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "lab.h"
#include "inside_panel.h"
#include "methods.h"
#include "simdbvh/reference/classify.h"
#include "simdbvh/workloads/families.h"

namespace simdbvh::lab {

struct AccuracyConfig {
    bool quick = false;
    bool embree = true;
    bool open3d = true;  // Open3D's rows in the inside/outside panel (--no-open3d leaves them out)
    bool inside = true;  // the inside/outside panel (default without --family; --inside adds it)
    int threads = 2;     // the double reference only; traces run on one thread
    workloads::FamilyOptions families;
    std::vector<workloads::Family> which;
    // Only these variants (accuracy_variants names), in that list's order; empty: every variant. The first
    // variant run is the default path the others are compared with bit for bit, so keep it first.
    std::vector<std::string> only;
    std::string json_file, report_dir;  // empty: not written
    std::string command;                // the command line, for the report
};

struct Variant {
    std::string name;  // row label: bvh2/watertight/conservative, bvh8/avx2/..., embree/robust, ...
    MethodSpec spec;
    bool ours = false;  // a tree traversal of ours: has TraceStats, must be bit-identical to the default
};

struct AccuracyRow {  // one method on one case (or summed over a family's cases)
    std::string family, case_name, method;
    double offset = 0;
    std::size_t rays = 0, triangles = 0;
    double seconds = 0;  // trace time for `rays` rays (one thread)
    reference::Tally tally;
    std::uint64_t expect_violations = 0;     // must-hit missed, must-miss hit
    std::uint64_t self_hits = 0;             // surface-start: hit the starting triangle
    std::uint64_t nan_outputs = 0;           // a hit with a NaN t, u or v
    std::uint64_t differ_from_default = -1;  // ours: rays not bit-identical to bvh2/watertight/conservative
    double nodes_per_ray = -1;               // ours: TraceStats
    double max_rel_t_error = 0;              // hits on the reference's triangle set: max |t - t_ref| / t_ref
    int depth = 0;

    double mrays() const { return seconds > 0 ? double(rays) / seconds / 1e6 : 0.0; }
    void add(const AccuracyRow& o);
};

struct AccuracyResults {
    std::vector<AccuracyRow> cases;
    std::map<std::string, std::vector<AccuracyRow>> families;  // family -> one row per method (summed)
    std::map<double, std::vector<AccuracyRow>> offsets;        // the offsets family: per offset, per method
    std::vector<InsideRow> inside;                             // the inside/outside panel
};

std::vector<Variant> accuracy_variants(bool with_embree);
AccuracyResults run_accuracy(const AccuracyConfig& c);

// The report (accuracy.md text and the JSON rows scripts/plot_accuracy.py reads); writes the files the
// config names and runs the chart script.
void report_accuracy(const AccuracyConfig& c, const AccuracyResults& r);

}  // namespace simdbvh::lab
