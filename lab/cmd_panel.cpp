// simdbvh panel: build quality per builder. For each builder (binned SAH at
// 8/16/32/64 bins, sweep SAH, midpoint, median, variance) and seed 002's
// sphere hierarchy: build time with 1 thread and all cores, SAH cost, depth,
// leaf-size histogram, bytes/triangle, BVH2 and BVH8 Mrays/s (one thread,
// closest hit, primary/incoherent/diffuse), nodes visited per ray (counted on
// a sample), the time to trace one 640x480 primary frame with the BVH2 on one
// thread, and agreement of that frame with the binned-SAH reference. A table,
// a JSON file and DIR/panel.md with charts (scripts/plot_panel.py).
// Config (here) -> run (panel_run.cpp) -> report (panel_report.cpp).
#include <algorithm>

#include "lab.h"
#include "common.h"
#include "options.h"
#include "outputs.h"
#include "panel_run.h"
#include "report.h"
#include "simdbvh/platform/topology.h"

namespace simdbvh::lab {

namespace {

PanelConfig parse_panel(const std::vector<std::string>& args) {
    const Options o("panel", args, {"scene", "threads", "json", "report", "reps", "rays", "stats-rays"},
                    {"quick", "no-report"});
    PanelConfig c;
    c.scene = o.has("scene") ? o.get("scene") : default_scene(&c.scene_why);
    c.quick = o.has("quick");
    c.threads_all = int(o.get_int("threads", std::max(1, topology().physical_cores), 1, 1024));
    c.reps = int(o.get_int("reps", c.quick ? 3 : 5, 1, 100));
    c.build_reps = std::min(c.reps, 3);
    c.rays = std::size_t(o.get_int("rays", c.quick ? 65536 : 262144, 1024, 1 << 26));
    c.stats_rays = std::size_t(o.get_int("stats-rays", c.quick ? 8192 : 32768, 256, 1 << 24));
    const std::string dir = o.get("report", "out");
    c.json_file = o.get("json", dir + "/panel.json");
    if (!o.has("no-report")) c.report_dir = dir;
    NamedPaths outputs{{"--json", c.json_file}};
    if (!o.has("no-report"))
        for (const char* f : {"panel.md", "build_vs_trace.png", "sah_vs_mrays.png", "leaf_hist.png"})
            outputs.emplace_back("--report", dir + "/" + f);
    check_outputs(outputs, {.scenes = {{"--scene", c.scene}}}, /*create_parent=*/true);
    c.machine = machine_line();
    c.isa = active_isa();
    c.command = command_line("panel", args);
    return c;
}

}  // namespace

int cmd_panel(const std::vector<std::string>& args) {
    const PanelConfig c = parse_panel(args);
    progress("scene: " + c.scene + (c.scene_why.empty() ? "" : " (" + c.scene_why + ")"), true);
    progress("machine: " + c.machine, true);
    const Mesh mesh = load_scene_with_progress(c.scene);
    report_panel(c, mesh, run_panel(c, mesh));
    return 0;
}

}  // namespace simdbvh::lab
