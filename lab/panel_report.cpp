// SPDX-License-Identifier: MIT
// simdbvh panel, the report: terminal table, JSON (scripts/plot_panel.py
// reads it) and panel.md with the charts.
#include <iostream>

#include "lab.h"
#include "panel_run.h"
#include "report.h"

namespace simdbvh::lab {

namespace {

std::string three(const std::array<double, 3>& a, const char* f) {
    return fmt(f, a[0]) + " / " + fmt(f, a[1]) + " / " + fmt(f, a[2]);
}

Json json_row(const PanelRow& r) {
    Json j{{"name", r.name}, {"builder", r.builder}, {"bins", r.bins}, {"skipped", r.skipped}, {"note", r.note}};
    if (r.skipped) return j;
    const Json more{{"build_ms_1", r.build_ms_1},
                    {"build_ms_all", r.build_ms_all},
                    {"bvh8_collapse_ms", r.bvh8_ms},
                    {"sah_cost", r.sah},
                    {"sah_cost_bvh8", r.sah_bvh8},
                    {"depth", r.depth},
                    {"nodes", r.nodes},
                    {"leaves", r.leaves},
                    {"leaf_hist", r.leaf_hist},
                    {"bytes_per_triangle", r.bytes_per_tri},
                    {"bytes_per_triangle_bvh8", r.bytes_per_tri_bvh8},
                    {"mrays_bvh2", r.mrays2},
                    {"mrays_bvh8", r.mrays8},
                    {"nodes_per_ray_bvh2", r.nodes_per_ray2},
                    {"nodes_per_ray_bvh8", r.nodes_per_ray8},
                    {"triangles_per_ray_bvh2", r.tris_per_ray2},
                    {"frame_ms", r.frame_ms},
                    {"frame_ms_bvh8", r.frame_ms_bvh8},
                    {"frame_mismatches", r.frame_mismatch}};
    for (const auto& [k, v] : more.items()) j[k] = v;
    return j;
}

Json panel_json(const PanelConfig& c, const Mesh& mesh, const std::vector<PanelRow>& rows) {
    Json j{{"scene", c.scene},
           {"triangles", mesh.size()},
           {"machine", c.machine},
           {"bvh8_isa", std::string(name(c.isa))},
           {"threads_all", c.threads_all},
           {"rays_per_kind", c.rays},
           {"stats_sample", c.stats_rays},
           {"frame", std::to_string(kFrameW) + "x" + std::to_string(kFrameH) + " primary, closest hit, 1 thread"},
           {"command", c.command},
           {"rows", Json::array()},
           {"ray_kinds", {"primary", "incoherent", "diffuse"}},
           {"leaf_buckets", kLeafBuckets}};
    for (const PanelRow& r : rows) j["rows"].push_back(json_row(r));
    return j;
}

Table speed_table(const std::vector<PanelRow>& rows, int threads_all) {
    Table t({"builder", "build ms 1 thr", "build ms " + std::to_string(threads_all) + " thr", "SAH", "depth", "B/tri",
             "BVH2 Mrays/s prim / incoh / diff", "BVH8 Mrays/s prim / incoh / diff",
             "BVH2 nodes/ray prim / incoh / diff", "frame ms BVH2", "frame ms BVH8", "frame diff"});
    for (const PanelRow& r : rows) {
        if (r.skipped) {
            t.row({r.name, "skipped: " + r.note});
            continue;
        }
        const bool sph = r.name == "spheres";
        t.row({r.name, fmt("%.0f", r.build_ms_1), fmt("%.0f", r.build_ms_all), fmt("%.2f", r.sah),
               std::to_string(r.depth), fmt("%.1f", r.bytes_per_tri), three(r.mrays2, "%.3g"),
               sph ? "n/a" : three(r.mrays8, "%.3g"), three(r.nodes_per_ray2, "%.0f"), fmt("%.0f", r.frame_ms),
               sph ? "n/a" : fmt("%.0f", r.frame_ms_bvh8), std::to_string(r.frame_mismatch)});
    }
    return t;
}

Table leaf_table(const std::vector<PanelRow>& rows) {
    std::vector<std::string> head{"builder", "nodes", "leaves"};
    for (const char* b : kLeafBuckets) head.push_back(b);
    Table t(head);
    for (const PanelRow& r : rows) {
        if (r.skipped) continue;
        std::vector<std::string> cells{r.name, std::to_string(r.nodes), std::to_string(r.leaves)};
        for (std::size_t n : r.leaf_hist) cells.push_back(std::to_string(n));
        t.row(cells);
    }
    return t;
}

void panel_markdown(const PanelConfig& c, const Mesh& mesh, const std::vector<PanelRow>& rows, bool charts,
                    std::ostream& md) {
    md << "# Build-quality panel: " << c.scene << "\n\n"
       << mesh.size() << " triangles" << (c.scene_why.empty() ? "" : " (" + c.scene_why + ")")
       << ". Machine: " << c.machine << ".\n\nCommand: `" << c.command << "`\n\n"
       << "Build times (BVH2 only; BVH8 collapse time is in the JSON) with 1 and " << c.threads_all
       << " threads (BuildOptions::threads). Trace: one thread, closest hit, " << c.rays << " rays per kind, best of "
       << c.reps << " runs (builds: best of " << c.build_reps
       << "; the machine is shared, the minimum is the least disturbed figure); BVH8 on " << name(c.isa)
       << ". Nodes visited per ray counted (TraceOptions::stats) on " << c.stats_rays
       << " rays of each kind (every k-th ray). Frame: one " << kFrameW << "x" << kFrameH
       << " primary image from the default camera, closest hit, one thread. SAH: C = sum of Ct*A(n)/A(root) over inner "
          "nodes + Ci*N*A(n)/A(root) over leaves, Ct = Ci = 1 (BVH2).\n\n"
       << speed_table(rows, c.threads_all).markdown() << "\n";
    std::size_t mism = 0;
    for (const PanelRow& r : rows) {
        mism += r.frame_mismatch;
        if (!r.skipped && r.name == "spheres") md << "- spheres: " << r.note << "; no BVH8 for spheres.\n";
    }
    md << "- Every row's frame hits are compared bit for bit with the " << rows[0].name << " row: mismatches " << mism
       << ".\n\n## Leaf sizes (BVH2 leaves by triangle count)\n\n"
       << leaf_table(rows).markdown() << "\n";
    if (charts)
        md << "## Charts\n\n![build time against trace speed](build_vs_trace.png)\n\n"
              "![SAH cost against measured speed](sah_vs_mrays.png)\n\n![leaf sizes](leaf_hist.png)\n";
}

}  // namespace

void report_panel(const PanelConfig& c, const Mesh& mesh, const std::vector<PanelRow>& rows) {
    std::cout << "\nscene " << c.scene << ", " << mesh.size() << " triangles; " << c.machine << "; BVH8 on "
              << name(c.isa) << "; build 1 and " << c.threads_all << " threads; trace 1 thread, closest hit,\n"
              << c.rays << " rays per kind (best of " << c.reps << "; builds best of " << c.build_reps
              << "); nodes/ray on " << c.stats_rays << " evenly spaced rays; frame = " << kFrameW << "x" << kFrameH
              << " primary rays\n"
              << speed_table(rows, c.threads_all).text()
              << "frame diff = frame hits (BVH2 + BVH8) not bit-identical to the " << rows[0].name
              << " row (0 expected)\n";
    // One set, written at the end (ReportFiles).
    Report rep;
    rep.json = panel_json(c, mesh, rows);
    const std::string json = json_text(rep.json);
    ReportFiles set;
    set.add(c.json_file, json);
    const std::filesystem::path md = std::filesystem::path(c.report_dir) / "panel.md";
    if (!c.report_dir.empty()) {
        const bool charts =
            set.add_charts("plot_panel.py", json, std::filesystem::path(c.json_file).filename().string(), c.report_dir);
        panel_markdown(c, mesh, rows, charts, rep.markdown);
        set.add(md, rep.markdown.str());
    }
    set.commit();
    std::cout << "\nwrote " << c.json_file << "\n";
    if (!c.report_dir.empty()) std::cout << "wrote " << md.string() << "\n";
}

}  // namespace simdbvh::lab
