// SPDX-License-Identifier: MIT
// simdbvh bench --sweep, the report: the winner maps and crossover tables, the
// fitted coefficients, the auto check on the held-out points; the terminal
// tables, DIR/sweep.json (scripts/plot_sweep.py draws winners.png and
// time_to_answer.png from it), DIR/sweep.md, the fitted block of
// --model-out (cost_model_fit.cpp) and the README's sweep block (--readme).
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>

#include "lab.h"
#include "common.h"
#include "report.h"
#include "simdbvh/kernels/error.h"
#include "sweep_run.h"

namespace simdbvh::lab {

namespace {

namespace fs = std::filesystem;

constexpr double kCheckRatio = 1.25;

bool is_brute(const std::string& m) { return m == "brute" || m == "brute8"; }

// The measured winner (fastest time to answer among auto's candidates) per (triangles, rays) of the fit scenes.
std::map<std::pair<std::size_t, std::size_t>, const SweepRow*> winners(const SweepResults& r, int threads,
                                                                       const std::string& kind) {
    std::map<std::pair<std::size_t, std::size_t>, const SweepRow*> w;
    for (const SweepRow& row : r.rows) {
        if (row.held_out || row.threads != threads || row.ray_kind != kind || row.method == "embree") continue;
        const SweepRow*& best = w[{row.triangles, row.rays}];
        if (!best || row.total_ms() < best->total_ms()) best = &row;
    }
    return w;
}

// Rows: ray counts; columns: triangle counts; cells: the winner.
Table winner_table(const SweepResults& r, int threads, const std::string& kind) {
    const auto w = winners(r, threads, kind);
    std::set<std::size_t> tris, rays;
    for (const auto& [k, row] : w) {
        tris.insert(k.first);
        rays.insert(k.second);
    }
    std::vector<std::string> header{"rays \\ triangles"};
    for (std::size_t n : tris) header.push_back(std::to_string(n));
    Table t(header);
    for (std::size_t n_rays : rays) {
        std::vector<std::string> cells{std::to_string(n_rays)};
        for (std::size_t n : tris) cells.push_back(w.count({n, n_rays}) ? w.at({n, n_rays})->method : "-");
        t.row(cells);
    }
    return t;
}

// Per ray count: the largest mesh up to which a brute force wins on every smaller fit mesh too, and the
// smallest mesh from which a tree wins on every larger one (a lone win among the other kind is not a crossover).
Table crossover_table(const SweepResults& r, int threads, const std::string& kind) {
    const auto w = winners(r, threads, kind);
    std::map<std::size_t, std::vector<std::pair<std::size_t, bool>>> by_rays;  // rays -> (triangles, brute won)
    for (const auto& [k, row] : w) by_rays[k.second].emplace_back(k.first, is_brute(row->method));
    Table t({"rays", "brute force wins up to (triangles)", "a tree wins from (triangles)", "rays per triangle there"});
    for (const auto& [n_rays, wins] : by_rays) {  // wins: ascending triangles (the map's order)
        std::size_t brute_max = 0, tree_min = SIZE_MAX;
        for (const auto& [n, brute] : wins) {
            if (!brute) break;
            brute_max = n;
        }
        for (auto it = wins.rbegin(); it != wins.rend() && !it->second; ++it) tree_min = it->first;
        t.row({std::to_string(n_rays), brute_max ? std::to_string(brute_max) : "-",
               tree_min == SIZE_MAX ? "-" : std::to_string(tree_min),
               tree_min == SIZE_MAX ? "-" : fmt("%.3g", double(n_rays) / double(tree_min))});
    }
    return t;
}

Table check_table(const std::vector<SweepCheck>& checks) {
    Table t({"scene", "triangles", "rays", "threads", "rays kind", "auto", "predicted ms", "auto ms", "best", "best ms",
             "auto/best", "within 1.25x", "embree ms"});
    for (const SweepCheck& c : checks)
        t.row({c.scene, std::to_string(c.triangles), std::to_string(c.rays), std::to_string(c.threads), c.ray_kind,
               c.chosen, fmt("%.3g", c.predicted_ms), fmt("%.3g", c.chosen_ms), c.best, fmt("%.3g", c.best_ms),
               fmt("%.2f", c.ratio()), c.ratio() <= kCheckRatio ? "yes" : "NO", fmt("%.3g", c.embree_ms)});
    return t;
}

std::size_t passed(const std::vector<SweepCheck>& checks) {
    return std::size_t(
        std::count_if(checks.begin(), checks.end(), [](const SweepCheck& c) { return c.ratio() <= kCheckRatio; }));
}

Table model_table(const CostModel& m) {
    Table t({"method", "build0 ms", "build1 ms", "call ms", "ray0 ms", "ray1 ms", "ray2 ms", "build par"});
    for (AccelMethod a : kAccelMethods) {
        const MethodCost& c = m.cost[std::size_t(a)];
        t.row({std::string(name(a)), fmt("%.3g", c.build0), fmt("%.3g", c.build1), fmt("%.3g", c.call),
               fmt("%.3g", c.ray0), fmt("%.3g", c.ray1), fmt("%.3g", c.ray2), fmt("%.2f", c.build_par)});
    }
    return t;
}

Json sweep_json(const SweepConfig& c, const SweepResults& r) {
    Json j;
    j["command"] = c.command;
    j["machine"] = c.machine;
    j["isa"] = std::string(name(c.isa));
    j["threads_all"] = c.threads_all;
    j["reps"] = c.reps;
    j["build_reps"] = c.build_reps;
    j["budget_ms"] = c.budget_ms;
    for (const SweepScene& s : r.scenes)
        j["scenes"].push_back(
            {{"scene", s.name}, {"triangles", s.triangles}, {"held_out", s.held_out}, {"rays", s.rays}});
    for (const SweepRow& row : r.rows)
        j["rows"].push_back({{"scene", row.scene},
                             {"triangles", row.triangles},
                             {"held_out", row.held_out},
                             {"method", row.method},
                             {"threads", row.threads},
                             {"ray_kind", row.ray_kind},
                             {"rays", row.rays},
                             {"traced_rays", row.traced_rays},
                             {"build_ms", row.build_ms},
                             {"trace_ms", row.trace_ms},
                             {"total_ms", row.total_ms()}});
    for (AccelMethod a : kAccelMethods) {
        const MethodCost& mc = r.model.cost[std::size_t(a)];
        j["model"][std::string(name(a))] = {{"build0", mc.build0},      {"build1", mc.build1}, {"call", mc.call},
                                            {"ray0", mc.ray0},          {"ray1", mc.ray1},     {"ray2", mc.ray2},
                                            {"build_par", mc.build_par}};
    }
    for (const SweepCheck& ck : r.checks)
        j["check"].push_back({{"scene", ck.scene},
                              {"triangles", ck.triangles},
                              {"rays", ck.rays},
                              {"threads", ck.threads},
                              {"ray_kind", ck.ray_kind},
                              {"auto", ck.chosen},
                              {"predicted_ms", ck.predicted_ms},
                              {"auto_ms", ck.chosen_ms},
                              {"best", ck.best},
                              {"best_ms", ck.best_ms},
                              {"ratio", ck.ratio()},
                              {"ok", ck.ratio() <= kCheckRatio},
                              {"embree_ms", ck.embree_ms}});
    j["check_passed"] = passed(r.checks);
    j["check_points"] = r.checks.size();
    return j;
}

// The block of --model-out for this ISA: C++ the library compiles (cost_model_fit.cpp).
std::string model_block(const SweepConfig& c, const CostModel& m) {
    const std::string isa(name(c.isa));
    std::string s = "\n// " + c.command + "\n// " + c.machine + "\nconstexpr FittedSet k" +
                    std::string(isa == "scalar" ? "Scalar"
                                : isa == "avx2" ? "Avx2"
                                                : "Avx512") +
                    "{true, {Isa::" + isa + ", {{";
    for (AccelMethod a : kAccelMethods) {
        const MethodCost& mc = m.cost[std::size_t(a)];
        s += std::string(a == kAccelMethods[0] ? "" : ",\n    ") + "{" + fmt("%.6g", mc.build0) + ", " +
             fmt("%.6g", mc.build1) + ", " + fmt("%.6g", mc.call) + ", " + fmt("%.6g", mc.ray0) + ", " +
             fmt("%.6g", mc.ray1) + ", " + fmt("%.6g", mc.ray2) + ", " + fmt("%.4g", mc.build_par) + "}";
    }
    return s + "}}}};\n";
}

// The Markdown shared by sweep.md and the README block; charts under `img`.
std::string sweep_markdown(const SweepConfig& c, const SweepResults& r, const std::string& img, bool charts) {
    std::ostringstream md;
    md << "_Generated by `" << c.command << "`; machine: " << c.machine << "; ISA " << name(c.isa)
       << ". Time to answer = build (median of " << c.build_reps << " warm builds) + trace (median of " << c.reps
       << " after a warm-up, methods interleaved); traces longer than " << c.budget_ms
       << " ms timed on evenly spaced rays and scaled. Fit: soup-N, icosphere-N and dragon-res3 (when cached); held "
          "out: the other scenes._\n\n";
    if (charts)
        md << "![winner map](" << img << "sweep_winners.png)\n![time to answer](" << img << "sweep_time.png)\n\n";
    for (const std::string kind : {"incoherent", "primary"})
        for (int threads : {1, c.threads_all}) {
            if (threads != 1 && c.threads_all == 1) break;
            md << "Crossovers, " << kind << " rays, " << threads << " thread(s):\n\n"
               << crossover_table(r, threads, kind).markdown() << "\n";
        }
    md << "Auto check on the held-out points: " << passed(r.checks) << " of " << r.checks.size()
       << " within 1.25x of the best method measured there (auto's time is the measured time of the method it "
          "chose; Embree, not a candidate, for reference):\n\n"
       << check_table(r.checks).markdown() << "\n";
    return md.str();
}

}  // namespace

namespace {

const char* kSweepPictures[] = {"sweep_winners.png", "sweep_time.png"};
const Block kSweepBlock{"<!-- sweep:begin -->", "<!-- sweep:end -->"};

Block model_block_markers(Isa isa) {
    const std::string i(name(isa));
    return {"// sweep:" + i + ":begin", "// sweep:" + i + ":end"};
}

}  // namespace

void add_sweep_outputs(const SweepConfig& c, NamedPaths& outputs) {
    if (!c.model_out.empty()) {
        const Block m = model_block_markers(c.isa);
        try {
            check_marked_block(c.model_out, m.begin, m.end);
        } catch (const Error& e) {
            throw Error(std::string("--model-out: ") + e.what());
        }
    }
    if (!c.report_dir.empty())
        for (const char* p : kSweepPictures) outputs.emplace_back("--report", (fs::path(c.report_dir) / p).string());
    check_results_docs(c.docs, kSweepBlock, {std::begin(kSweepPictures), std::end(kSweepPictures)}, outputs);
}

void report_sweep(const SweepConfig& c, const SweepResults& r) {
    for (const std::string kind : {"incoherent", "primary"}) {
        std::cout << "\nwinner (time to answer), " << kind << " rays, 1 thread:\n" << winner_table(r, 1, kind).text();
        std::cout << "crossovers:\n" << crossover_table(r, 1, kind).text();
    }
    std::cout << "\nfitted cost model (" << name(c.isa) << "):\n"
              << model_table(r.model).text() << "\nauto check (held-out points): " << passed(r.checks) << " of "
              << r.checks.size() << " within 1.25x of the best\n"
              << check_table(r.checks).text();
    // One set, written at the end (ReportFiles): the --model-out source is not touched unless everything
    // else is written with it.
    Report rep;
    rep.json = sweep_json(c, r);
    const std::string json = json_text(rep.json);
    ReportFiles set;
    set.add(c.json_file, json);
    if (!c.model_out.empty()) {
        const Block m = model_block_markers(c.isa);
        set.add(c.model_out, with_marked_block(c.model_out, m.begin, m.end, model_block(c, r.model)));
    }
    if (!c.report_dir.empty()) {
        const fs::path dir = c.report_dir;
        const bool charts = set.add_charts("plot_sweep.py", json, fs::path(c.json_file).filename().string(), dir);
        rep.markdown << "# simdbvh sweep: where brute force, BVH2 and the wide trees win\n\n"
                     << sweep_markdown(c, r, "", charts) << "Winner maps (fit scenes):\n\n";
        for (const std::string kind : {"incoherent", "primary"})
            for (int threads : {1, c.threads_all}) {
                if (threads != 1 && c.threads_all == 1) break;
                rep.markdown << kind << ", " << threads << " thread(s):\n\n"
                             << winner_table(r, threads, kind).markdown() << "\n";
            }
        rep.markdown << "Fitted cost model (ms; cost_model.h has the formula):\n\n" << model_table(r.model).markdown();
        set.add(dir / "sweep.md", rep.markdown.str());
        std::vector<std::pair<std::string, std::string>> pictures;
        for (const char* p : kSweepPictures) pictures.emplace_back(p, p);
        add_results_docs(
            set, c.docs, kSweepBlock,
            [&](const std::string& link) {
                std::string block(1, '\n');  // (GCC 12 warns falsely on "literal" + string)
                return block += sweep_markdown(c, r, link, charts);
            },
            dir, pictures);
    }
    set.commit();
    std::cout << "wrote " << c.json_file << "\n";
    if (!c.model_out.empty()) std::cout << "wrote the " << name(c.isa) << " coefficients into " << c.model_out << "\n";
    if (!c.report_dir.empty()) std::cout << "wrote " << c.report_dir << "/sweep.md\n";
    for (const ResultsDoc& d : c.docs) std::cout << "wrote the results block of " << d.file.string() << "\n";
}

}  // namespace simdbvh::lab
