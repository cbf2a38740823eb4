// SPDX-License-Identifier: MIT
// simdbvh bench on a scene description, the report: the terminal tables, the
// JSON file (scripts/plot_scene_bench.py reads it), DIR/report.md with the
// charts and a render, and the README's block for this scene (--readme).
#include "lab.h"
#include "scene_desc_bench_report.h"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "report.h"
#include "scene_cmds.h"
#include "simdbvh/reference/embree.h"

namespace simdbvh::lab {

namespace fs = std::filesystem;

namespace {

std::string mb(std::size_t bytes) { return fmt("%.2f", double(bytes) / 1e6); }

Json tally_json(const reference::SceneTally& t) {
    Json j = Json::object();
    for (int i = 0; i < 6; ++i) j[std::string(reference::name(reference::SceneLabel(i)))] = t.count[i];
    j["marginal"] = t.marginal;
    return j;
}

Json results_json(const BenchConfig& c, const SceneDescBenchResults& r) {
    const SceneStats& st = r.stats;
    Json j{{"scene", r.scene},
           {"machine", c.machine},
           {"command", c.command},
           {"reps", c.reps},
           {"build_reps", c.build_reps},
           {"rays_per_kind", r.rays},
           {"geometries", st.geometries},
           {"instances", st.instances},
           {"planes", st.planes},
           {"primitives", st.primitives},
           {"instanced_primitives", st.instanced_primitives},
           {"bytes", st.bytes},
           {"bytes_per_instance", st.bytes_per_instance},
           {"volume_corners", st.volume_corners},
           {"volume_child_corners", st.volume_child_corners},
           {"builds", Json::array()},
           {"speed", Json::array()},
           {"agreement", Json::array()},
           {"tessellation_spheres", r.tessellation_spheres},
           {"tessellation", Json::array()},
           {"planes_in_tree", r.planes_in_tree},
           {"plane_rows", Json::array()},
           {"sphere_precision", sphere_precision_json(r.sphere_precision)}};
    for (const auto& b : r.builds)
        j["builds"].push_back(
            {{"method", b.method}, {"build_ms", b.build_ms}, {"bytes", b.bytes}, {"estimated", b.estimated}});
    for (const auto& s : r.speed)
        j["speed"].push_back(
            {{"method", s.method}, {"rays", s.rays}, {"query", s.query}, {"mrays_per_s", s.mrays_per_s}});
    for (const auto& a : r.agreement)
        j["agreement"].push_back({{"method", a.method},
                                  {"rays", a.rays},
                                  {"count", a.count},
                                  {"same", a.same},
                                  {"same_bits", a.same_bits},
                                  {"other_object", a.other_object},
                                  {"only_ours", a.only_ours},
                                  {"only_theirs", a.only_theirs},
                                  {"differ", a.differ},
                                  {"refereed", a.refereed},
                                  {"ours", tally_json(a.ours)},
                                  {"theirs", tally_json(a.theirs)}});
    for (const auto& t : r.tessellation)
        j["tessellation"].push_back({{"method", t.method},
                                     {"level", t.level},
                                     {"triangles", t.triangles},
                                     {"bytes", t.bytes},
                                     {"mrays_primary", t.mrays_primary},
                                     {"mrays_incoherent", t.mrays_incoherent},
                                     {"same_sphere", t.same_sphere},
                                     {"median_err", t.median_err},
                                     {"max_err", t.max_err}});
    for (const auto& p : r.planes)
        j["plane_rows"].push_back({{"method", p.method},
                                   {"rays", p.rays},
                                   {"mrays_per_s", p.mrays_per_s},
                                   {"count", p.count},
                                   {"same_t", p.same_t}});
    return j;
}

// Mrays/s per method (rows) and ray kind x query (columns), with the ratio to Embree's instanced scene.
Table speed_table(const SceneDescBenchResults& r) {
    std::vector<std::string> methods;
    for (const auto& s : r.speed)
        if (std::find(methods.begin(), methods.end(), s.method) == methods.end()) methods.push_back(s.method);
    auto find = [&](const std::string& m, const std::string& rays, const std::string& q) {
        for (const auto& s : r.speed)
            if (s.method == m && s.rays == rays && s.query == q) return s.mrays_per_s;
        return 0.0;
    };
    Table t({"method", "primary closest", "primary any", "incoherent closest", "incoherent any"});
    for (const std::string& m : methods) {
        std::vector<std::string> row{m};
        for (const char* rays : {"primary", "incoherent"})
            for (const char* q : {"closest", "any"}) {
                const double v = find(m, rays, q), e = find("Embree instanced", rays, q);
                row.push_back(fmt("%.2f", v) +
                              (m != "Embree instanced" && e > 0 ? " (" + fmt("%.2fx", v / e) + ")" : ""));
            }
        t.row(row);
    }
    return t;
}

Table build_table(const SceneDescBenchResults& r) {
    Table t({"method", "build ms", "MB", "bytes per instance"});
    for (const auto& b : r.builds)
        t.row({b.method + (b.estimated ? " (not built: estimated)" : ""), b.estimated ? "-" : fmt("%.1f", b.build_ms),
               mb(b.bytes), r.stats.instances ? fmt("%.0f", double(b.bytes) / double(r.stats.instances)) : "-"});
    return t;
}

Table agreement_table(const SceneDescBenchResults& r) {
    Table t({"against ours (child corners)", "rays", "count", "same object", "same bits", "other object",
             "only ours hit", "only it hit"});
    for (const auto& a : r.agreement)
        t.row({a.method, a.rays, std::to_string(a.count), std::to_string(a.same), std::to_string(a.same_bits),
               std::to_string(a.other_object), std::to_string(a.only_ours), std::to_string(a.only_theirs)});
    return t;
}

std::string labels(const reference::SceneTally& t) {
    std::string s;
    for (int i = 2; i < 6; ++i)
        if (t.count[i])
            s += (s.empty() ? "" : ", ") + std::string(reference::name(reference::SceneLabel(i))) + " " +
                 std::to_string(t.count[i]);
    if (s.empty()) return "none";
    return s + (t.marginal ? " (" + std::to_string(t.marginal) + " marginal)" : "");
}

// The differing rays, both answers classified against the double reference.
Table referee_table(const SceneDescBenchResults& r) {
    Table t({"ours against", "rays", "differ", "refereed", "ours: agree / tie", "ours wrong", "it: agree / tie",
             "it wrong"});
    for (const auto& a : r.agreement) {
        if (a.method == "brute force") continue;
        t.row({a.method, a.rays, std::to_string(a.differ), std::to_string(a.refereed),
               std::to_string(a.ours.count[0]) + " / " + std::to_string(a.ours.count[1]), labels(a.ours),
               std::to_string(a.theirs.count[0]) + " / " + std::to_string(a.theirs.count[1]), labels(a.theirs)});
    }
    return t;
}

Table tessellation_table(const SceneDescBenchResults& r) {
    Table t({"spheres as", "triangles", "MB", "primary Mrays/s", "incoherent Mrays/s", "same sphere as analytic",
             "median rel. error", "max rel. error"});
    for (const auto& x : r.tessellation)
        t.row({x.method, x.triangles ? std::to_string(x.triangles) : "-", mb(x.bytes), fmt("%.2f", x.mrays_primary),
               fmt("%.2f", x.mrays_incoherent), fmt("%.4f", x.same_sphere), fmt("%.2e", x.median_err),
               fmt("%.2e", x.max_err)});
    return t;
}

Table planes_table(const SceneDescBenchResults& r) {
    Table t({"method", "rays", "Mrays/s", "same t as planes out"});
    for (const auto& p : r.planes)
        t.row(
            {p.method, p.rays, fmt("%.2f", p.mrays_per_s), std::to_string(p.same_t) + " / " + std::to_string(p.count)});
    return t;
}

Table precision_table(const SceneDescBenchResults& r) {
    Table t({"distance / radius", "naive: misses", "median err", "robust: misses", "median err", "Embree: misses",
             "median err"});
    for (const auto& p : r.sphere_precision)
        t.row({fmt("%.3g", p.ratio), fmt("%.4f", p.miss_naive), fmt("%.2e", p.median_err_naive),
               fmt("%.4f", p.miss_robust), fmt("%.2e", p.median_err_robust), fmt("%.4f", p.miss_embree),
               fmt("%.2e", p.median_err_embree)});
    return t;
}

// Where each method first misses and its median error at 10^3 and 10^6 radii.
std::string summary(const std::vector<SpherePrecisionRow>& rows) {
    auto first_miss = [&](auto miss) {
        for (const auto& p : rows)
            if (miss(p) > 0) return fmt("%.3g", p.ratio) + " radii";
        return std::string("never");
    };
    auto err_at = [&](double ratio, auto err) {
        const SpherePrecisionRow* best = &rows.front();
        for (const auto& p : rows)
            if (std::fabs(std::log(p.ratio / ratio)) < std::fabs(std::log(best->ratio / ratio))) best = &p;
        return fmt("%.2e", err(*best));
    };
    std::ostringstream s;
    s << "First false miss: naive float quadratic " << first_miss([](const auto& p) { return p.miss_naive; })
      << ", robust " << first_miss([](const auto& p) { return p.miss_robust; }) << ", Embree "
      << first_miss([](const auto& p) { return p.miss_embree; })
      << ". Median relative error at 10^3 / 10^6 radii: naive "
      << err_at(1e3, [](const auto& p) { return p.median_err_naive; }) << " / "
      << err_at(1e6, [](const auto& p) { return p.median_err_naive; }) << ", robust "
      << err_at(1e3, [](const auto& p) { return p.median_err_robust; }) << " / "
      << err_at(1e6, [](const auto& p) { return p.median_err_robust; }) << ", Embree "
      << err_at(1e3, [](const auto& p) { return p.median_err_embree; }) << " / "
      << err_at(1e6, [](const auto& p) { return p.median_err_embree; }) << ".";
    return s.str();
}

const char* kNote =
    "One thread; the same rays for every method: primary = one ray per pixel of the render's camera (inside a "
    "room's walls), incoherent = origins uniform in the scene's bounds and directions uniform on the sphere. "
    "Mrays/s: median of the timed traces after an untimed warm-up, the methods interleaved; builds: median of the "
    "builds after an untimed first one. Ours: the two-level scene (BVH8 bottom levels, an 8-wide top level over "
    "the instances for batches (a BVH2 for single rays), planes outside the tree, tested four rays per vector), "
    "active ISA. Embree: one RTC_GEOMETRY_TYPE_INSTANCE per instance, spheres as RTC_GEOMETRY_TYPE_SPHERE_POINT, "
    "boxes as six quads, planes through the same batched plane pass as ours (Embree has no plane primitive), "
    "2048 rays at a time; its bytes are its device memory "
    "(buffers and BVHs), ours our structures (which hold their own triangle copies). In parentheses: the ratio to "
    "Embree's instanced scene in the same run.";

// The report body; `img` prefixes chart paths (the report folder or docs/results/ from the README).
std::string body(const SceneDescBenchResults& r, const std::string& img, bool charts, bool readme) {
    auto h = [readme](const std::string& title) { return readme ? "**" + title + "**\n\n" : "## " + title + "\n\n"; };
    std::ostringstream md;
    const SceneStats& st = r.stats;
    md << st.geometries << " geometries, " << st.instances << " instances, " << st.planes << " planes; "
       << st.primitives << " primitives (" << st.instanced_primitives << " when every instance is flattened). "
       << "Summed instance box volume: corners " << fmt("%.4g", st.volume_corners) << ", child corners "
       << fmt("%.4g", st.volume_child_corners) << ".\n\n"
       << h("Speed (Mrays/s, " + std::to_string(r.rays) + " rays per kind)") << speed_table(r).markdown() << "\n"
       << h("Builds and memory") << build_table(r).markdown() << "\n"
       << h("Agreement of closest hits") << agreement_table(r).markdown()
       << "\nOurs against brute force must be the same bits on every ray. Every ray where another method differs from "
          "ours (hit/miss, object, or t beyond the reference tolerance) is refereed by the double-precision scene "
          "reference (reference/scene_reference.h: every instance and primitive in double, the inverse transforms in "
          "double), both answers classified (tie: another object within tolerance of the reference's t; marginal: "
          "within float rounding of the reference):\n\n"
       << referee_table(r).markdown() << "\n";
    if (!r.tessellation.empty()) {
        md << h("Analytic against tessellated spheres (" + std::to_string(r.tessellation_spheres) + " spheres)")
           << tessellation_table(r).markdown()
           << "\nError: | |p - c| - r | / r at the reported hit point p = o + t d (double), over the rays each method "
              "hit; \"same sphere\": the same hit/miss and sphere as our analytic test, over both ray sets.\n\n";
        if (charts) md << "![tessellation](" << img << "scene_tessellation.png)\n\n";
    }
    if (!r.sphere_precision.empty()) {
        md << h("Sphere precision: distance against radius");
        if (!readme) md << precision_table(r).markdown() << "\n";  // the README keeps the chart and the summary
        md << summary(r.sphere_precision)
           << "\n\nEach row: rays from a random origin aimed at random points of the disc of radius 0.9 r around the "
              "centre (every one should hit); error | |p - c| - r | / r at the hit point; misses are false misses.\n\n";
        if (charts) md << "![sphere precision](" << img << "sphere_precision.png)\n\n";
    }
    if (!r.planes.empty())
        md << h("Planes kept out of the tree against put in it") << r.planes_in_tree
           << " axis-aligned planes as flat boxes 2000x the scene's size across, in the top-level tree (ours) or as "
              "quads (Embree). \"Same t\": against the same method with the planes kept out (our slab test computes "
              "the plane "
              "test's t; Embree's float quad test does not).\n\n"
           << planes_table(r).markdown() << "\n";
    if (charts) md << "![speed](" << img << "scene_speed.png)\n\n";
    return md.str();
}

std::string slug(const std::string& scene) { return fs::path(scene).stem().string(); }

Block block_of(const std::string& scene) {
    const std::string s = slug(scene);
    return {"<!-- bench-scene:" + s + ":begin -->", "<!-- bench-scene:" + s + ":end -->"};
}

const char* kPictures[] = {"scene_speed.png", "scene_tessellation.png", "sphere_precision.png", "scene_render.png"};

}  // namespace

void add_scene_desc_bench_outputs(const BenchConfig& c, NamedPaths& outputs) {
    if (!c.report_dir.empty())
        for (const char* p : kPictures) outputs.emplace_back("--report", (fs::path(c.report_dir) / p).string());
    std::vector<std::string> pictures;
    for (const char* p : kPictures) pictures.push_back(slug(c.scene) + "_" + p);
    check_results_docs(c.docs, block_of(c.scene), pictures, outputs);
}

void report_scene_desc_bench(const BenchConfig& c, const SceneDescBenchResults& r) {
    std::cout << "\nscene " << r.scene << "; " << c.machine << "\n\nMrays/s, one thread:\n"
              << speed_table(r).text() << "\nbuilds:\n"
              << build_table(r).text() << "\nagreement:\n"
              << agreement_table(r).text() << "\nrefereed in double:\n"
              << referee_table(r).text();
    if (!r.tessellation.empty()) std::cout << "\ntessellation:\n" << tessellation_table(r).text();
    if (!r.sphere_precision.empty()) std::cout << "\nsphere precision:\n" << precision_table(r).text();
    if (!r.planes.empty()) std::cout << "\nplanes:\n" << planes_table(r).text();
    // One set, written at the end (ReportFiles): a failure before then leaves every earlier file as it was.
    Report rep;
    rep.json = results_json(c, r);
    const std::string json = json_text(rep.json);
    ReportFiles set;
    set.add(c.json_file, json);
    if (!c.report_dir.empty()) {
        const fs::path dir = c.report_dir;
        const bool charts = set.add_charts("plot_scene_bench.py", json, fs::path(c.json_file).filename().string(), dir);
        MethodSpec spec;
        spec.method = "bvh8";
        spec.isa = active_isa();
        set.add(dir / "scene_render.png",
                encode_png(render_scene_image(c.scene, spec, InstanceBounds::child_corners, 640, 480)));
        rep.markdown << "# simdbvh bench report: scene " << r.scene << "\n\nMachine: " << c.machine << "\n\nCommand: `"
                     << c.command << "`\n\nEmbree " << reference::EmbreeScene::version() << ". " << kNote << "\n\n"
                     << body(r, "", charts, false) << "![render](scene_render.png)\n";
        set.add(dir / "report.md", rep.markdown.str());
        const std::string s = slug(r.scene);
        std::vector<std::pair<std::string, std::string>> pictures;
        for (const char* p : kPictures) pictures.emplace_back(p, s + "_" + p);
        add_results_docs(
            set, c.docs, block_of(c.scene),
            [&](const std::string& link) {
                std::ostringstream block;
                block << "\n_Generated by `" << c.command << "`; machine: " << c.machine << ". " << kNote << "_\n\n"
                      << body(r, link + s + "_", charts, true) << "![render](" << link << s << "_scene_render.png)\n";
                return block.str();
            },
            dir, pictures);
    }
    set.commit();
    std::cout << "\nwrote " << c.json_file << "\n";
    if (!c.report_dir.empty()) std::cout << "wrote " << (fs::path(c.report_dir) / "report.md").string() << "\n";
    for (const ResultsDoc& d : c.docs) std::cout << "wrote the results block of " << d.file.string() << "\n";
}

}  // namespace simdbvh::lab
