// SPDX-License-Identifier: MIT
#pragma once
// The bench's tables (report.md, the README block, the terminal).
#include <string>
#include <vector>

#include "lab.h"
#include "bench_run.h"
#include "report.h"

namespace simdbvh::lab {

// "bvh8/avx2" for the wide BVHs, the method otherwise.
std::string label(const Record& r);
// Mrays/s per method, ray kind and query at `threads`, with the ratio to Embree medium in the same run.
Table speed_table(const std::vector<Record>& recs, int threads);
// Builds per method: cold (first) and warm (median), one thread and all cores; bytes per triangle.
Table build_table(const std::vector<Record>& recs, int threads_all);
// Disagreement classes against the reference on the sample, summed over kinds and queries.
Table accuracy_table(const std::vector<Record>& recs);
// One row per record, for the terminal.
Table record_table(const std::vector<Record>& recs);
// Wide vs binary on one scene: Mrays/s per width and ISA with the ratio to BVH2 in the same run.
Table width_speed_table(const std::vector<Record>& widths, const std::string& scene);
// Per width: nodes visited and box tests (lanes) per ray, bytes per triangle, collapse time.
Table width_count_table(const std::vector<Record>& widths, const std::string& scene);

}  // namespace simdbvh::lab
