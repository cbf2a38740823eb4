// SPDX-License-Identifier: MIT
// simdbvh bench --sweep: where brute force, the BVH2 and the wide trees each
// win, the cost model fitted to it and auto's check.
// Config (here) -> run (sweep_run.cpp, sweep_fit.cpp) -> report (sweep_report.cpp).
#include <algorithm>

#include "lab.h"
#include "common.h"
#include "options.h"
#include "outputs.h"
#include "report.h"
#include "sweep_run.h"
#include "simdbvh/platform/topology.h"

namespace simdbvh::lab {

int cmd_bench_sweep(const std::vector<std::string>& args) {
    const Options o("bench --sweep", args,
                    {"threads", "json", "report", "reps", "build-reps", "budget-ms", "model-out", "readme", "publish"},
                    {"sweep", "quick", "no-report"});
    SweepConfig c;
    c.quick = o.has("quick");
    c.threads_all = int(o.get_int("threads", std::max(1, topology().physical_cores), 1, 1024));
    c.reps = int(o.get_int("reps", c.quick ? 3 : 5, 1, 100));
    c.build_reps = int(o.get_int("build-reps", 3, 0, 100));
    c.budget_ms = double(o.get_int("budget-ms", 40, 1, 100000));
    c.isa = active_isa();
    const std::string dir = o.get("report", "out");
    c.json_file = o.get("json", dir + "/sweep.json");
    if (!o.has("no-report")) c.report_dir = dir;
    c.model_out = o.get("model-out");
    c.docs = parse_results_docs(o, o.has("no-report"));
    // Every output and every block (--model-out, the docs) is checked before the sweep.
    NamedPaths outputs{{"--json", c.json_file}};
    if (!o.has("no-report")) outputs.emplace_back("--report", dir + "/sweep.md");
    if (o.has("model-out")) outputs.emplace_back("--model-out", c.model_out);
    add_sweep_outputs(c, outputs);
    Inputs inputs;  // the cached meshes among its scenes
    for (const SweepScene& s : sweep_scenes(c.quick)) inputs.scenes.emplace_back("the sweep's scene", s.name);
    check_outputs(outputs, inputs, /*create_parent=*/true);
    c.machine = machine_line();
    c.command = command_line("bench", args);
    progress("sweep on " + c.machine + ", ISA " + std::string(name(c.isa)), true);
    report_sweep(c, run_sweep(c));
    return 0;
}

}  // namespace simdbvh::lab
