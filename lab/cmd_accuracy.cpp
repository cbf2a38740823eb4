// simdbvh accuracy: every ray family (docs/accuracy.md) against every method
// variant: throughput and the classification against the double reference,
// plus each family's own expectation (must hit, must miss, no self-hit).
// Config (here) -> run (accuracy_run.cpp) -> report (accuracy_report.cpp).
#include <algorithm>
#include <filesystem>
#include <sstream>

#include "lab.h"
#include "accuracy_run.h"
#include "common.h"
#include "options.h"
#include "outputs.h"
#include "report.h"

namespace simdbvh::lab {

namespace {

std::vector<workloads::Family> parse_families(const Options& o) {
    if (!o.has("family")) return {std::begin(workloads::kAllFamilies), std::end(workloads::kAllFamilies)};
    std::vector<workloads::Family> fams;
    std::stringstream ss(o.get("family"));
    std::string f;
    while (std::getline(ss, f, ',')) {
        const auto p = workloads::parse_family(f);
        if (!p)
            throw UsageError("unknown --family '" + f +
                             "' (watertight, offsets, axis-aligned, surface-start, grazing, "
                             "needles, degenerate, random, direction-scale)");
        fams.push_back(*p);
    }
    return fams;
}

AccuracyConfig parse_accuracy(const std::vector<std::string>& args) {
    const Options o("accuracy", args, {"report", "json", "seed", "family", "threads", "scene"},
                    {"quick", "no-embree", "no-open3d", "inside"});
    AccuracyConfig c;
    c.quick = o.has("quick");
    c.embree = !o.has("no-embree");
    c.open3d = !o.has("no-open3d");
    c.inside = !o.has("family") || o.has("inside");
    c.families.quick = c.quick;
    c.families.seed = std::uint64_t(o.get_int("seed", 1, 0, (1LL << 62)));
    c.families.random_scene = o.get("scene");
    c.threads = int(o.get_int("threads", 2, 1, 1024));
    c.which = parse_families(o);
    c.json_file = o.get("json");
    c.report_dir = o.get("report");
    c.command = command_line("accuracy", args);
    // Fail on unwritable outputs before the long run.
    NamedPaths outputs;
    if (o.has("json")) outputs.emplace_back("--json", c.json_file);
    if (o.has("report"))
        for (const char* f :
             {"accuracy.md", "accuracy.json", "speed_vs_accuracy.png", "offsets.png", "inside_outside.png"})
            outputs.emplace_back("--report", (std::filesystem::path(c.report_dir) / f).string());
    // The random family's scene: --scene, else dragon-res4 when cached (family_random.cpp).
    const bool random = std::find(c.which.begin(), c.which.end(), workloads::Family::random) != c.which.end();
    Inputs inputs;
    if (!c.families.random_scene.empty()) inputs.scenes.emplace_back("--scene", c.families.random_scene);
    else if (random) inputs.scenes.emplace_back("the random family's scene", "dragon-res4");
    check_outputs(outputs, inputs, /*create_parent=*/true);
    return c;
}

}  // namespace

int cmd_accuracy(const std::vector<std::string>& args) {
    const AccuracyConfig c = parse_accuracy(args);
    AccuracyResults res = run_accuracy(c);
    if (c.inside) res.inside = run_inside_panel(c.quick, c.embree, c.open3d);
    report_accuracy(c, res);
    return 0;
}

}  // namespace simdbvh::lab
