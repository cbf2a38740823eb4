// simdbvh bench: the main job. Every method on one scene: build time (cold and
// warm), memory, Mrays/s per ray kind and query with 1 thread and all cores
// (median of repetitions after a warm-up), accuracy against brute force on a
// sample; the wide-vs-binary comparison (width 2, 4, 8, 16 per ISA) on that
// scene and the width scenes; a table, a JSON file and a Markdown report with
// charts and pictures.
// On a scene description (room, instances-N, spheres-N, FILE.json): the scene
// bench instead (scene_desc_bench_run.h).
// Config (here) -> run (bench_run.cpp, scene_desc_bench_run.cpp) -> report
// (bench_report.cpp, scene_desc_bench_report.cpp).
#include <algorithm>
#include <chrono>
#include <iostream>
#include <sstream>

#include <unistd.h>

#include "lab.h"
#include "bench_report.h"
#include "common.h"
#include "options.h"
#include "outputs.h"
#include "report.h"
#include "scene_cmds.h"
#include "scene_desc_bench_report.h"
#include "simdbvh/workloads/scene_desc.h"
#include "simdbvh/platform/parallel.h"
#include "simdbvh/platform/topology.h"

namespace simdbvh::lab {

namespace {

// --width-scenes A,B (none: only the bench scene); default: the terrain with --full (unless it is the
// bench scene), else none.
std::vector<std::string> width_scenes(const Options& o, const BenchConfig& c) {
    std::vector<std::string> out;
    if (!o.has("width-scenes")) {
        if (c.full && c.scene != "terrain" && !is_scene_desc(c.scene)) out.push_back("terrain");
        return out;
    }
    std::stringstream ss(o.get("width-scenes"));
    std::string s;
    while (std::getline(ss, s, ','))
        if (!s.empty() && s != "none" && s != c.scene) out.push_back(s);
    return out;
}

BenchConfig parse_bench(const std::vector<std::string>& args) {
    const Options o("bench", args,
                    {"scene", "threads", "json", "report", "reps", "build-reps", "rays", "sample", "stats-rays",
                     "readme", "publish", "width-scenes", "refit-frames"},
                    {"quick", "full", "no-report"});
    BenchConfig c;
    c.scene = o.has("scene") ? o.get("scene") : default_scene(&c.scene_why);
    if (is_scene_desc(c.scene))  // the scene bench runs one thread, on that scene, without the refit sequence
        for (const char* opt : {"threads", "width-scenes", "refit-frames", "stats-rays"})
            if (o.has(opt))
                throw UsageError(std::string("--") + opt + " does not apply to a scene description (" + c.scene +
                                 "): the scene bench runs one thread on that scene");
    // Three sizes: --quick (a smoke run), the default (the main job, minutes on two cores), --full (the
    // published results: twice the rays, the long refit sequence, the terrain's width rows).
    c.quick = o.has("quick");
    c.full = o.has("full");
    if (c.quick && c.full) throw UsageError("--quick and --full are two sizes of the run: give one");
    c.width_scenes = width_scenes(o, c);
    c.threads_all = int(o.get_int("threads", std::max(1, topology().physical_cores), 1, 1024));
    c.reps = int(o.get_int("reps", c.quick ? 3 : 5, 1, 100));
    c.build_reps = int(o.get_int("build-reps", 3, 0, 100));
    c.refit_frames = int(o.get_int("refit-frames", c.quick ? 3 : (c.full ? 20 : 5), 0, 1000));
    c.rays = std::size_t(o.get_int("rays", c.quick ? 65536 : (c.full ? 262144 : 131072), 1024, 1 << 26));
    c.sample = std::size_t(o.get_int("sample", c.quick ? 300 : 1000, 16, 1 << 20));
    c.stats_rays = std::size_t(o.get_int("stats-rays", c.quick ? 4096 : 16384, 16, 1 << 24));
    const std::string dir = o.get("report", "out");
    c.json_file = o.get("json", dir + "/bench.json");
    if (!o.has("no-report")) c.report_dir = dir;
    c.docs = parse_results_docs(o, o.has("no-report"));
    // Every output (and every doc's block) is checked before the long run; the command creates the folders.
    NamedPaths outputs{{"--json", c.json_file}};
    if (!o.has("no-report")) outputs.emplace_back("--report", dir + "/report.md");
    if (is_scene_desc(c.scene)) add_scene_desc_bench_outputs(c, outputs);
    else add_bench_outputs(c, outputs);
    Inputs inputs{.scenes = {{"--scene", c.scene}}};
    for (const std::string& s : c.width_scenes) inputs.scenes.emplace_back("--width-scenes", s);
    check_outputs(outputs, inputs, /*create_parent=*/true);
    c.machine = machine_line();
    c.command = command_line("bench", args);
    return c;
}

// On a terminal, which step of the main job runs and how long it has run (the trace step, the longest,
// estimates what it has left as it goes: SceneBench::run).
void bench_step(int i, int n, const std::string& what) {
    static const auto t0 = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (::isatty(2))
        std::cerr << "[" << i << "/" << n << "] " << what << " (" << int(s) / 60 << " min " << int(s) % 60
                  << " s so far)\n"
                  << std::flush;
}

}  // namespace

int cmd_bench(const std::vector<std::string>& args) {
    if (std::find(args.begin(), args.end(), "--sweep") != args.end()) return cmd_bench_sweep(args);
    const BenchConfig c = parse_bench(args);
    if (is_scene_desc(c.scene)) {  // room, instances-N, spheres-N, FILE.json: the scene bench
        progress("scene: " + c.scene + " (scene description)", true);
        progress("machine: " + c.machine, true);
        const SceneDesc desc = workloads::load_scene_desc(c.scene);
        report_scene_desc_bench(c, run_scene_desc_bench(c, desc));
        return 0;
    }
    set_thread_pinning(true);  // the all-core rows: one worker per core (the library's default is unpinned)
    progress("scene: " + c.scene + (c.scene_why.empty() ? "" : " (" + c.scene_why + ")"), true);
    progress("machine: " + c.machine, true);
    const Mesh mesh = load_scene_with_progress(c.scene);
    std::vector<NamedMesh> width_meshes;
    for (const std::string& s : c.width_scenes) width_meshes.push_back({s, load_scene_with_progress(s)});
    bench_step(1, 4, "trace speed and agreement, " + c.scene);
    BenchResults res = run_bench(c, mesh, width_meshes);
    bench_step(2, 4, "refit sequence, " + c.scene);
    res.refit = run_refit(c, mesh);
    bench_step(3, 4, "hard accuracy families (watertight, grazing, offsets, direction-scale)");
    res.hard = run_hard_families(c.threads_all);
    bench_step(4, 4, "report");
    report_bench(c, mesh, res);
    return 0;
}

}  // namespace simdbvh::lab
