// SPDX-License-Identifier: MIT
// simdbvh accuracy, the report: per-family, per-offset and per-case tables
// (stdout and DIR/accuracy.md), the JSON rows (--json, DIR/accuracy.json) and
// the charts (scripts/plot_accuracy.py).
#include <iostream>

#include "lab.h"
#include "accuracy_run.h"
#include "report.h"

namespace simdbvh::lab {

namespace {

namespace fs = std::filesystem;
constexpr std::uint64_t kNone = std::uint64_t(-1);

std::string sci(double v) { return fmt("%.1e", v); }
std::string count(std::uint64_t v) { return std::to_string(v); }

Table family_table() {
    return Table({"method", "rays", "Mrays/s", "agree", "tie", "leak", "false hit", "wrong tri", "t error",
                  "(marginal)", "disagree/M", "expect viol.", "self-hits", "NaN", "!= default", "nodes/ray",
                  "max rel t err"});
}

void family_row(Table& t, const AccuracyRow& r) {
    const reference::Tally& y = r.tally;
    t.row({r.method, count(r.rays), fmt("%.2f", r.mrays()), count(y.agree), count(y.tie), count(y.leak),
           count(y.false_hit), count(y.wrong_triangle), count(y.t_error), count(y.marginal),
           fmt("%.1f", y.disagreements_per_million()), count(r.expect_violations), count(r.self_hits),
           count(r.nan_outputs), r.differ_from_default == kNone ? "-" : count(r.differ_from_default),
           r.nodes_per_ray < 0 ? "-" : fmt("%.1f", r.nodes_per_ray), sci(r.max_rel_t_error)});
}

Json json_row(const AccuracyRow& r, const char* level) {
    const reference::Tally& t = r.tally;
    return Json{{"level", level},
                {"family", r.family},
                {"case", r.case_name},
                {"method", r.method},
                {"offset", r.offset},
                {"rays", r.rays},
                {"triangles", r.triangles},
                {"seconds", r.seconds},
                {"mrays_per_s", r.mrays()},
                {"agree", t.agree},
                {"tie", t.tie},
                {"leak", t.leak},
                {"false_hit", t.false_hit},
                {"wrong_triangle", t.wrong_triangle},
                {"t_error", t.t_error},
                {"marginal", t.marginal},
                {"disagreements_per_million", t.disagreements_per_million()},
                {"expect_violations", r.expect_violations},
                {"self_hits", r.self_hits},
                {"nan_outputs", r.nan_outputs},
                {"differ_from_default", r.differ_from_default == kNone ? Json() : Json(r.differ_from_default)},
                {"nodes_per_ray", r.nodes_per_ray < 0 ? Json() : Json(r.nodes_per_ray)},
                {"max_rel_t_error", r.max_rel_t_error},
                {"depth", r.depth}};
}

void write_markdown_tables(const AccuracyConfig& c, const AccuracyResults& res, std::ostream& md) {
    md << "# simdbvh accuracy\n\nCommand: `" << c.command << "`; seed " << c.families.seed
       << "; traces on one thread; active ISA " << name(active_isa()) << " (" << cpu_name()
       << ").\nClassification against the double-precision watertight reference (docs/accuracy.md): agree/tie are "
          "agreements; leak, false hit, wrong triangle, t error are disagreements ((marginal): those within float "
          "rounding of the reference). expect viol.: the family's own answer (must hit / must miss) violated; "
          "self-hits: surface-start rays hitting their starting triangle; != default: rays not bit-identical to "
          "bvh2/watertight/conservative. BVH8 always uses the conservative box test. In the JSON, non-finite "
          "numbers are null.\n";
    for (workloads::Family fam : c.which) {
        const std::string fname(workloads::name(fam));
        Table t = family_table();
        const auto it = res.families.find(fname);
        if (it != res.families.end())
            for (const AccuracyRow& r : it->second) family_row(t, r);
        md << "\n## " << fname << "\n\n" << t.markdown();
    }
    if (!res.offsets.empty()) {
        Table t({"offset", "method", "rays", "leak", "false hit", "wrong tri", "t error", "max rel t err"}, "rlrrrrrr");
        for (const auto& [off, rows] : res.offsets)
            for (const AccuracyRow& r : rows)
                t.row({sci(off), r.method, count(r.rays), count(r.tally.leak), count(r.tally.false_hit),
                       count(r.tally.wrong_triangle), count(r.tally.t_error), sci(r.max_rel_t_error)});
        md << "\n## offsets, per offset\n\n" << t.markdown();
    }
    Table t({"case", "method", "rays", "triangles", "depth", "leak", "false hit", "wrong tri", "t error",
             "expect viol.", "self-hits"},
            "llrrrrrrrrr");
    for (const AccuracyRow& r : res.cases)
        t.row({r.case_name, r.method, count(r.rays), count(r.triangles), std::to_string(r.depth), count(r.tally.leak),
               count(r.tally.false_hit), count(r.tally.wrong_triangle), count(r.tally.t_error),
               count(r.expect_violations), count(r.self_hits)});
    md << "\n## cases\n\n" << t.markdown();
}

Json json_rows(const AccuracyResults& res) {
    Json rows = Json::array();
    for (const auto& [fname, rs] : res.families)
        for (const AccuracyRow& r : rs) rows.push_back(json_row(r, "family"));
    for (const auto& [off, rs] : res.offsets)
        for (const AccuracyRow& r : rs) rows.push_back(json_row(r, "offset"));
    for (const AccuracyRow& r : res.cases) rows.push_back(json_row(r, "case"));
    return rows;
}

}  // namespace

void report_accuracy(const AccuracyConfig& c, const AccuracyResults& res) {
    Report rep;
    rep.json = Json{{"command", "accuracy"},
                    {"command_line", c.command},
                    {"quick", c.quick},
                    {"seed", c.families.seed},
                    {"isa", std::string(name(active_isa()))},
                    {"rows", json_rows(res)},
                    {"inside", inside_json(res.inside)}};
    write_markdown_tables(c, res, rep.markdown);
    // One set, written at the end (ReportFiles).
    const std::string json = json_text(rep.json);
    ReportFiles set;
    if (!c.json_file.empty()) set.add(c.json_file, json);
    if (c.report_dir.empty()) {
        if (c.inside) rep.markdown << inside_markdown(res.inside, false);
        std::cout << rep.markdown.str();
        set.commit();
        if (!c.json_file.empty()) std::cout << "wrote " << c.json_file << "\n";
        return;
    }
    const fs::path dir = c.report_dir;
    set.add(dir / "accuracy.json", json);
    const bool charts = set.add_charts("plot_accuracy.py", json, "accuracy.json", dir);
    if (c.inside) rep.markdown << inside_markdown(res.inside, charts && !res.inside.empty());
    if (charts)
        rep.markdown << "\n## Charts\n\n![speed against accuracy](speed_vs_accuracy.png)\n\n"
                        "![leak rate and t error against offset](offsets.png)\n";
    std::cout << rep.markdown.str();
    set.add(dir / "accuracy.md", rep.markdown.str());
    set.commit();
    if (!c.json_file.empty()) std::cout << "\nwrote " << c.json_file;
    std::cout << "\nwrote " << (dir / "accuracy.json").string() << "\nwrote " << (dir / "accuracy.md").string() << "\n";
}

}  // namespace simdbvh::lab
