#include "lab.h"
#include "bench_report.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "bench_pictures.h"
#include "bench_tables.h"
#include "common.h"
#include "simdbvh/reference/embree.h"
#include "simdbvh/kernels/error.h"

namespace simdbvh::lab {

namespace fs = std::filesystem;

namespace {

// -1 marks "not counted": null in the JSON.
Json counted(double v) { return v < 0 ? Json() : Json(v); }

Json json_record(const Record& r) {
    return Json{{"scene", r.scene},
                {"method", r.method},
                {"isa", r.isa},
                {"builder", r.builder},
                {"width", r.width},
                {"ray_kind", r.ray_kind},
                {"query", r.query},
                {"threads", r.threads},
                {"mrays_per_s", r.mrays_per_s},
                {"build_ms", r.build_ms},
                {"build_ms_all_cores", r.build_ms_all},
                {"build_ms_warm", r.build_ms_warm},
                {"build_ms_all_cores_warm", r.build_ms_all_warm},
                {"collapse_ms", r.collapse_ms},
                {"bytes_per_triangle", r.bytes_per_triangle},
                {"sah_cost", r.sah_cost},
                {"nodes_per_ray", counted(r.nodes_per_ray)},
                {"box_tests_per_ray", counted(r.box_tests_per_ray)},
                {"agreement", r.agreement},
                {"rays", r.rays},
                {"sample", r.sample},
                {"disagreements",
                 {{"tie", r.tally.tie},
                  {"leak", r.tally.leak},
                  {"false_hit", r.tally.false_hit},
                  {"wrong_triangle", r.tally.wrong_triangle},
                  {"t_error", r.tally.t_error}}}};
}

std::uint64_t hard_disagreements(const reference::Tally& t) {
    return t.leak + t.false_hit + t.wrong_triangle + t.t_error;
}

Json bench_json(const BenchConfig& c, const Mesh& mesh, const BenchResults& res) {
    Json j{{"scene", c.scene},           {"triangles", mesh.size()},      {"machine", c.machine},
           {"command", c.command},       {"threads_all", c.threads_all},  {"reps", c.reps},
           {"build_reps", c.build_reps}, {"rays_per_kind", c.rays},       {"stats_rays", c.stats_rays},
           {"records", Json::array()},   {"width_scenes", Json::array()}, {"widths", Json::array()}};
    for (const Record& r : res.records) j["records"].push_back(json_record(r));
    for (const auto& [s, n] : res.width_scene_sizes) j["width_scenes"].push_back({{"scene", s}, {"triangles", n}});
    for (const Record& r : res.widths) j["widths"].push_back(json_record(r));
    j["refit"] = refit_json(res.refit);
    // Per method: the hard families' disagreements (ties at equal t excluded, as in the agreement table).
    Json hard{{"families", Json::array()}, {"methods", Json::array()}};
    for (workloads::Family f : kHardFamilies) hard["families"].push_back(std::string(workloads::name(f)));
    std::map<std::string, Json> per_method;
    std::vector<std::string> order;
    for (const auto& [fam, rows] : res.hard)
        for (const AccuracyRow& a : rows) {
            if (!per_method.count(a.method)) {
                order.push_back(a.method);
                const std::string lab = bench_label_of(a.method);
                per_method[a.method] = Json{{"method", a.method},
                                            {"bench_label", lab.empty() ? Json() : Json(lab)},
                                            {"rays", 0},
                                            {"disagreements", 0},
                                            {"per_family", Json::object()}};
            }
            Json& m = per_method[a.method];
            const std::uint64_t d = hard_disagreements(a.tally);
            m["rays"] = m["rays"].get<std::uint64_t>() + a.rays;
            m["disagreements"] = m["disagreements"].get<std::uint64_t>() + d;
            m["per_family"][fam] = Json{{"rays", a.rays}, {"disagreements", d}};
        }
    for (const std::string& name : order) hard["methods"].push_back(per_method[name]);
    j["hard_families"] = hard;
    return j;
}

const char* kMethodNote =
    "Mrays/s: median of the timed traces after one untimed warm-up, the methods interleaved, the same rays and "
    "mesh for every method. "
    "Builds: cold = the first build of that method in the process, warm = the median of the further builds.";

// The wide-vs-binary tables per scene; `heading` starts each scene's title line ("### " in the report,
// "**" in the README block, whose headings are above it).
std::string width_section(const BenchConfig& c, const BenchResults& res, const std::string& img_dir, bool chart,
                          const std::string& heading) {
    std::ostringstream s;
    s << "Trees from the same BVH2 (binned SAH); width 2 is the BVH2 (scalar), 4/8/16 the collapsed BVHs per ISA. "
         "One thread. In parentheses the ratio to the BVH2 in the same run. nodes / boxes: wide nodes visited and "
         "box tests per ray (TraceStats on "
      << c.stats_rays << " evenly spaced rays of each set; a wide node test counts all N lanes, empty ones too).\n\n";
    const std::string end = heading == "**" ? "**" : "";
    for (const auto& [scene, n] : res.width_scene_sizes)
        s << heading << scene << " (" << n << " triangles)" << end << "\n\n"
          << width_speed_table(res.widths, scene).markdown() << "\n"
          << width_count_table(res.widths, scene).markdown() << "\n";
    if (chart) s << "![wide vs binary](" << img_dir << "widths.png)\n\n";
    return s.str();
}

void bench_markdown(const BenchConfig& c, const Mesh& mesh, const BenchResults& res, const Pictures& p, bool charts,
                    std::ostream& md) {
    const std::vector<Record>& recs = res.records;
    md << "# simdbvh bench report\n\nScene **" << c.scene << "** (" << mesh.size() << " triangles)"
       << (c.scene_why.empty() ? "" : ": " + c.scene_why) << ".\n\nMachine: " << c.machine << "\n\nCommand: `"
       << c.command << "`\n\nEmbree " << reference::EmbreeScene::version()
       << " (Debian libembree3): the one-thread rows use a device configured with `threads=1`, the all-core rows "
          "`threads="
       << c.threads_all << "`; rays are traced with rtcIntersect1/rtcOccluded1 from our own threads.\n\n"
       << kMethodNote << " Median of " << c.reps << " traces, " << c.build_reps << " warm builds. "
       << "Ratios in parentheses are against `embree/medium/default` in the same run; `brute` runs on the accuracy "
          "sample only.\n\n## One thread\n\n"
       << speed_table(recs, 1).markdown() << "\n";
    if (c.threads_all > 1)
        md << "## All cores (" << c.threads_all << " threads, pinned)\n\n"
           << speed_table(recs, c.threads_all).markdown() << "\n";
    md << "## Builds\n\n"
       << build_table(recs, c.threads_all).markdown() << "\n"
       << (res.refit.empty() ? "" : "## Refit against rebuild\n\n" + refit_markdown(res.refit, "", charts))
       << "## Wide vs binary\n\n"
       << width_section(c, res, "", charts, "### ")
       << "## Accuracy against the brute-force reference (sample, all ray kinds and queries, one thread)\n\n"
       << accuracy_table(recs).markdown()
       << "\nOur paths are compared bit for bit with the float brute force; differences (and all of Embree's) are "
          "classified against the double-precision reference.\n\n";
    if (charts)
        md << "## Charts\n\n![Mrays/s](mrays.png)\n\n![speed against accuracy](speed_accuracy.png)\n\n"
              "Speed against accuracy: the x axis counts disagreements with the double reference on the hard "
              "accuracy families (`simdbvh accuracy --quick --family watertight,grazing,offsets,direction-scale`; "
              "ties excluded), where the bench's own rays agree everywhere.\n\n"
              "![BVH8 over BVH2](speedup.png)\n\n![build](build.png)\n\n";
    md << "## Pictures (" << p.width << "x" << p.height << " primary rays)\n\n"
       << "| BVH8 render | BVH2 nodes visited | BVH8 nodes visited |\n|---|---|---|\n"
       << "| ![render](render_bvh8.png) | ![bvh2](heat_bvh2.png) | ![bvh8](heat_bvh8.png) |\n\n"
       << "Disagreement pixels (red): BVH2 vs BVH8 " << p.differ_bvh2_bvh8 << ", BVH8 vs Embree "
       << p.differ_bvh8_embree << ".\n\n| BVH2 vs BVH8 | BVH8 vs Embree |\n|---|---|\n"
       << "| ![](disagree_bvh2_bvh8.png) | ![](disagree_bvh8_embree.png) |\n";
}

// The results block (--readme, --publish): `link` is the pictures' folder as the doc sees it.
std::string results_block(const BenchConfig& c, const Mesh& mesh, const BenchResults& res, bool charts,
                          const std::string& link) {
    const std::vector<Record>& recs = res.records;
    std::ostringstream block;
    block << "\n_Generated by `" << c.command << "` on " << c.scene << " (" << mesh.size()
          << " triangles); machine: " << c.machine << ". " << kMethodNote
          << " In parentheses the ratio to Embree 3 medium in the same run._\n\nOne thread:\n\n"
          << speed_table(recs, 1).markdown() << "\n";
    if (c.threads_all > 1)
        block << "All cores (" << c.threads_all << " threads):\n\n"
              << speed_table(recs, c.threads_all).markdown() << "\n";
    block << "Builds:\n\n"
          << build_table(recs, c.threads_all).markdown() << "\n"
          << (res.refit.empty() ? "" : "Refit against rebuild:\n\n" + refit_markdown(res.refit, link, charts))
          << "Wide vs binary:\n\n"
          << width_section(c, res, link, charts, "**") << "Accuracy on the sample, all ray kinds and queries:\n\n"
          << accuracy_table(recs).markdown() << "\n";
    if (charts)
        block << "![Mrays/s](" << link << "mrays.png)\n![speed against accuracy](" << link << "speed_accuracy.png)\n";
    block << "![render](" << link << "render_bvh8.png) ![BVH2 nodes](" << link << "heat_bvh2.png) "
          << "![BVH8 nodes](" << link << "heat_bvh8.png)\n";
    return block.str();
}

// The headline: per ray kind and query, one thread, our fastest row against Embree medium.
void print_summary(const BenchConfig& c, const BenchResults& res) {
    std::cout << "\nsummary (" << c.scene << ", 1 thread, Mrays/s):\n";
    for (const char* query : {"closest", "any"})
        for (const char* kind : {"primary", "incoherent", "diffuse"}) {
            const Record* best = nullptr;
            const Record* embree = nullptr;
            for (const Record& r : res.records) {
                if (r.threads != 1 || r.ray_kind != kind || r.query != query) continue;
                if (label(r) == "embree/medium/default") embree = &r;
                else if (r.method != "brute" && r.method.rfind("embree", 0) != 0 &&
                         (!best || r.mrays_per_s > best->mrays_per_s))
                    best = &r;
            }
            if (!best) continue;
            std::cout << "  " << query << " " << kind << ": " << label(*best) << " " << fmt("%.1f", best->mrays_per_s);
            if (embree && embree->mrays_per_s > 0)
                std::cout << ", embree " << fmt("%.1f", embree->mrays_per_s) << " (x"
                          << fmt("%.2f", best->mrays_per_s / embree->mrays_per_s) << ")";
            std::cout << "\n";
        }
    if (!c.report_dir.empty()) std::cout << "report: " << c.report_dir << "/report.md\n";
    else std::cout << "report: " << c.json_file << " (--no-report)\n";
}

const char* kCharts[] = {"mrays.png", "speed_accuracy.png", "speedup.png", "build.png", "widths.png", "refit.png"};
const char* kDocPictures[] = {"mrays.png", "speed_accuracy.png", "speedup.png",   "build.png",    "widths.png",
                              "refit.png", "render_bvh8.png",    "heat_bvh2.png", "heat_bvh8.png"};

}  // namespace

const Block kBenchBlock{"<!-- bench:begin -->", "<!-- bench:end -->"};

void add_bench_outputs(const BenchConfig& c, NamedPaths& outputs) {
    if (!c.report_dir.empty()) {
        for (const char* p : kBenchPictures) outputs.emplace_back("--report", (fs::path(c.report_dir) / p).string());
        for (const char* p : kCharts) outputs.emplace_back("--report", (fs::path(c.report_dir) / p).string());
    }
    check_results_docs(c.docs, kBenchBlock, {std::begin(kDocPictures), std::end(kDocPictures)}, outputs);
}

void report_bench(const BenchConfig& c, const Mesh& mesh, const BenchResults& res) {
    std::cout << "\nscene " << c.scene << ", " << mesh.size() << " triangles; " << c.machine << "\n"
              << record_table(res.records).text();
    for (const auto& [scene, n] : res.width_scene_sizes)
        std::cout << "\nwide vs binary, " << scene << " (" << n << " triangles), one thread, Mrays/s:\n"
                  << width_speed_table(res.widths, scene).text() << "nodes visited / box tests per ray:\n"
                  << width_count_table(res.widths, scene).text();
    // Everything is made first and written at the end as one set: a failure or a signal before then leaves
    // every earlier file (an older report, its pictures, the docs) as it was.
    Report rep;
    rep.json = bench_json(c, mesh, res);
    const std::string json = json_text(rep.json);
    ReportFiles set;
    set.add(c.json_file, json);
    if (!c.report_dir.empty()) {
        const fs::path dir = c.report_dir;
        progress("rendering pictures and charts for " + c.report_dir, true);
        const Pictures p = render_pictures(mesh, c.quick, c.threads_all);
        for (const auto& [name, bytes] : p.png) set.add(dir / name, bytes);
        const bool charts = set.add_charts("plot_bench.py", json, fs::path(c.json_file).filename().string(), dir);
        bench_markdown(c, mesh, res, p, charts, rep.markdown);
        set.add(dir / "report.md", rep.markdown.str());
        std::vector<std::pair<std::string, std::string>> pictures;
        for (const char* name : kDocPictures) pictures.emplace_back(name, name);
        add_results_docs(
            set, c.docs, kBenchBlock,
            [&](const std::string& link) { return results_block(c, mesh, res, charts, link); }, dir, pictures);
    }
    set.commit();
    std::cout << "\nwrote " << c.json_file << "\n";
    if (!c.report_dir.empty()) std::cout << "wrote " << c.report_dir << "/report.md\n";
    for (const ResultsDoc& d : c.docs) std::cout << "wrote the results block of " << d.file.string() << "\n";
    print_summary(c, res);
}

}  // namespace simdbvh::lab
