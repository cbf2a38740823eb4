#include "bench_report.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "common.h"
#include "image.h"
#include "methods.h"
#include "simdbvh/compare/embree.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/scene/rays.h"

namespace simdbvh::cli {

namespace fs = std::filesystem;

namespace {

const char* kKinds[] = {"primary", "incoherent", "diffuse"};

std::string label(const Record& r) { return is_wide(r.method) ? r.method + "/" + r.isa : r.method; }

const Record* find(const std::vector<Record>& recs, const std::string& lab, const std::string& kind,
                   const std::string& query, int threads) {
    for (const Record& r : recs)
        if (label(r) == lab && r.ray_kind == kind && r.query == query && r.threads == threads) return &r;
    return nullptr;
}

std::vector<std::string> labels(const std::vector<Record>& recs) {
    std::vector<std::string> out;
    for (const Record& r : recs)
        if (std::find(out.begin(), out.end(), label(r)) == out.end()) out.push_back(label(r));
    return out;
}

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

// Mrays/s per method and ray kind, both queries, with the ratio to Embree medium.
std::string speed_table(const std::vector<Record>& recs, int threads) {
    std::ostringstream s;
    const std::string ref = "embree/medium/default";
    s << "| method | build ms | B/tri |";
    for (const char* q : {"closest", "any"})
        for (const char* k : kKinds) s << " " << k << " " << q << " |";
    s << " agreement |\n|---|---:|---:|";
    for (int i = 0; i < 6; ++i) s << "---:|";
    s << "---:|\n";
    for (const std::string& lab : labels(recs)) {
        const Record* first = find(recs, lab, "primary", "closest", threads);
        if (!first) continue;
        s << "| " << lab << " | " << fmt("%.0f", threads == 1 ? first->build_ms : first->build_ms_all) << " | "
          << fmt("%.1f", first->bytes_per_triangle) << " |";
        std::size_t agree_n = 0, total = 0;
        for (const char* q : {"closest", "any"})
            for (const char* k : kKinds) {
                const Record* r = find(recs, lab, k, q, threads);
                const Record* e = find(recs, ref, k, q, threads);
                if (!r) {
                    s << " - |";
                    continue;
                }
                s << " " << fmt("%.3g", r->mrays_per_s);
                if (e && e->mrays_per_s > 0 && lab != ref && lab != "brute") s << " (" << fmt("%.2f", r->mrays_per_s / e->mrays_per_s) << "x)";
                s << " |";
                agree_n += r->tally.agree + r->tally.tie;
                total += r->tally.total();
            }
        s << " " << fmt("%.2f", total ? 100.0 * double(agree_n) / double(total) : 100.0) << "% |\n";
    }
    return s.str();
}

std::string accuracy_table(const std::vector<Record>& recs) {
    std::ostringstream s;
    s << "| method | rays checked | agree | tie | leak | false hit | wrong triangle | t error |\n"
         "|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const std::string& lab : labels(recs)) {
        Tally t;
        for (const Record& r : recs)
            if (label(r) == lab && r.threads == 1) {
                t.agree += r.tally.agree;
                t.tie += r.tally.tie;
                t.leak += r.tally.leak;
                t.false_hit += r.tally.false_hit;
                t.wrong_triangle += r.tally.wrong_triangle;
                t.t_error += r.tally.t_error;
            }
        s << "| " << lab << " | " << t.total() << " | " << t.agree << " | " << t.tie << " | " << t.leak << " | "
          << t.false_hit << " | " << t.wrong_triangle << " | " << t.t_error << " |\n";
    }
    return s.str();
}

void write_text(const fs::path& file, const std::string& text) {
    scene::write_file_atomic(file, std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()));
}

}  // namespace

void write_report(const ReportInputs& in) {
    const fs::path dir = in.dir;
    fs::create_directories(dir);
    const Mesh& mesh = *in.mesh;
    const std::vector<Record>& recs = *in.records;

    // Pictures through the BVH8 on the best ISA, heat maps, disagreements.
    const int w = in.quick ? 320 : 640, h = in.quick ? 240 : 480;
    const auto rays = scene::primary_rays(scene::default_camera(mesh.bounds(), w, h));
    MethodSpec b8;
    b8.method = "bvh8";
    b8.isa = active_isa();
    b8.threads = in.threads_all;
    MethodSpec b2 = b8;
    b2.method = "bvh2";
    MethodSpec em = b8;
    em.method = "embree";
    auto t8 = make_tracer(mesh, b8);
    auto t2 = make_tracer(mesh, b2);
    auto te = make_tracer(mesh, em);
    std::vector<Hit> h8(rays.size()), h2(rays.size()), he(rays.size());
    t8->trace(rays, h8, false, nullptr);
    t2->trace(rays, h2, false, nullptr);
    te->trace(rays, he, false, nullptr);
    write_png((dir / "render_bvh8.png").string(), shade_eye_light(mesh, rays, h8, w, h));
    std::vector<std::uint32_t> c2(rays.size()), c8(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        TraceStats s2, s8;
        Hit tmp;
        t2->trace(std::span(&rays[i], 1), std::span(&tmp, 1), false, &s2);
        t8->trace(std::span(&rays[i], 1), std::span(&tmp, 1), false, &s8);
        c2[i] = std::uint32_t(s2.nodes_visited);
        c8[i] = std::uint32_t(s8.nodes_visited);
    }
    std::uint32_t cmax = 1;
    for (std::uint32_t c : c2) cmax = std::max(cmax, c);
    write_png((dir / "heat_bvh2.png").string(), heat_map(c2, w, h, cmax));
    write_png((dir / "heat_bvh8.png").string(), heat_map(c8, w, h, cmax));
    std::size_t diff_ours = 0, diff_embree = 0;
    const Image d_ours = disagreement(h2, h8, w, h, &diff_ours);
    write_png((dir / "disagree_bvh2_bvh8.png").string(), d_ours);
    write_png((dir / "disagree_bvh8_embree.png").string(), disagreement(h8, he, w, h, &diff_embree));

    // Charts.
    std::string py = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    const std::string cmd = py + " '" SIMDBVH_SOURCE_DIR "/scripts/plot_bench.py' '" + in.json_file + "' '" +
                            dir.string() + "'";
    const bool charts = std::system(cmd.c_str()) == 0;
    if (!charts) progress("warning: chart script failed (" + cmd + "); the report has tables only", true);

    std::ostringstream md;
    md << "# simdbvh bench report\n\nScene **" << in.scene << "** (" << mesh.size() << " triangles)"
       << (in.scene_why.empty() ? "" : ": " + in.scene_why) << ".\n\nMachine: " << in.machine
       << "\n\nCommand: `" << in.command << "`\n\nEmbree " << compare::EmbreeScene::version()
       << " (Debian libembree3): the one-thread rows use a device configured with `threads=1`, the all-core rows "
          "`threads=" << in.threads_all << "`; rays are traced with rtcIntersect1/rtcOccluded1 from our own threads."
       << "\n\nRatios in parentheses are against `embree/medium/default` in the same run. Mrays/s are medians of "
          "repetitions; `brute` runs on the accuracy sample only.\n\n## One thread\n\n"
       << speed_table(recs, 1) << "\n";
    if (in.threads_all > 1) md << "## All cores (" << in.threads_all << " threads, pinned)\n\n" << speed_table(recs, in.threads_all) << "\n";
    md << "## Accuracy against the brute-force reference (sample, all ray kinds and queries, one thread)\n\n"
       << accuracy_table(recs)
       << "\nOur paths are compared bit for bit with the float brute force; differences (and all of Embree's) are "
          "classified against the double-precision reference.\n\n";
    if (charts)
        md << "## Charts\n\n![Mrays/s](mrays.png)\n\n![speed against accuracy](speed_accuracy.png)\n\n"
              "![BVH8 over BVH2](speedup.png)\n\n![build](build.png)\n\n";
    md << "## Pictures (" << w << "x" << h << " primary rays)\n\n"
       << "| BVH8 render | BVH2 nodes visited | BVH8 nodes visited |\n|---|---|---|\n"
       << "| ![render](render_bvh8.png) | ![bvh2](heat_bvh2.png) | ![bvh8](heat_bvh8.png) |\n\n"
       << "Disagreement pixels (red): BVH2 vs BVH8 " << diff_ours << ", BVH8 vs Embree " << diff_embree
       << ".\n\n| BVH2 vs BVH8 | BVH8 vs Embree |\n|---|---|\n"
       << "| ![](disagree_bvh2_bvh8.png) | ![](disagree_bvh8_embree.png) |\n";
    write_text(dir / "report.md", md.str());

    if (!in.readme.empty()) {
        std::ifstream f(in.readme);
        if (!f) throw Error(in.readme + ": cannot read");
        std::stringstream ss;
        ss << f.rdbuf();
        std::string text = ss.str();
        const std::string b = "<!-- bench:begin -->", e = "<!-- bench:end -->";
        const auto pb = text.find(b), pe = text.find(e);
        if (pb == std::string::npos || pe == std::string::npos || pe < pb)
            throw Error(in.readme + ": no '" + b + "' ... '" + e + "' block");
        const fs::path docs = fs::path(in.readme).parent_path() / "docs" / "results";
        fs::create_directories(docs);
        for (const char* img : {"mrays.png", "speed_accuracy.png", "speedup.png", "build.png", "render_bvh8.png",
                                "heat_bvh2.png", "heat_bvh8.png"})
            if (fs::exists(dir / img)) fs::copy_file(dir / img, docs / img, fs::copy_options::overwrite_existing);
        std::ostringstream block;
        block << b << "\n_Generated by `" << in.command << "` on " << in.scene << " (" << mesh.size()
              << " triangles); machine: " << in.machine
              << ". Mrays/s, medians of repetitions; in parentheses the ratio to Embree 3 medium in the same run._\n\n"
              << "One thread:\n\n" << speed_table(recs, 1) << "\n";
        if (in.threads_all > 1)
            block << "All cores (" << in.threads_all << " threads):\n\n" << speed_table(recs, in.threads_all) << "\n";
        block << "Accuracy on the sample, all ray kinds and queries:\n\n" << accuracy_table(recs) << "\n"
              << "![Mrays/s](docs/results/mrays.png)\n![speed against accuracy](docs/results/speed_accuracy.png)\n"
              << "![render](docs/results/render_bvh8.png) ![BVH2 nodes](docs/results/heat_bvh2.png) "
                 "![BVH8 nodes](docs/results/heat_bvh8.png)\n";
        text = text.substr(0, pb) + block.str() + text.substr(pe);
        write_text(in.readme, text);
    }
}

}  // namespace simdbvh::cli
