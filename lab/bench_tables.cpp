// SPDX-License-Identifier: MIT
#include "lab.h"
#include "bench_tables.h"

#include <algorithm>

#include "methods.h"

namespace simdbvh::lab {

namespace {

const char* kKinds[] = {"primary", "incoherent", "diffuse"};
const char* kQueries[] = {"closest", "any"};

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

std::vector<Record> of_scene(const std::vector<Record>& recs, const std::string& scene) {
    std::vector<Record> out;
    for (const Record& r : recs)
        if (r.scene == scene) out.push_back(r);
    return out;
}

// The collapse does not depend on the ISA: the median of the width's rows (each a median of warm builds).
double collapse_median(const std::vector<Record>& recs, int width) {
    std::vector<double> v;
    for (const Record& r : recs)
        if (r.width == width && r.ray_kind == "primary" && r.query == "closest" && r.threads == 1)
            v.push_back(r.collapse_ms);
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

std::vector<std::string> kind_query_header(std::vector<std::string> head) {
    for (const char* q : kQueries)
        for (const char* k : kKinds) head.push_back(std::string(k) + " " + q);
    return head;
}

// Mrays/s per kind and query, with the ratio to the `ref` label's row in the same run.
std::vector<std::string> speed_cells(const std::vector<Record>& recs, const std::string& lab, const std::string& ref,
                                     int threads) {
    std::vector<std::string> cells;
    for (const char* q : kQueries)
        for (const char* k : kKinds) {
            const Record* r = find(recs, lab, k, q, threads);
            const Record* e = find(recs, ref, k, q, threads);
            if (!r) {
                cells.push_back("-");
                continue;
            }
            std::string c = fmt("%.3g", r->mrays_per_s);
            if (e && e->mrays_per_s > 0 && lab != ref) c += " (" + fmt("%.2f", r->mrays_per_s / e->mrays_per_s) + "x)";
            cells.push_back(c);
        }
    return cells;
}

}  // namespace

std::string label(const Record& r) { return is_wide(r.method) ? r.method + "/" + r.isa : r.method; }

Table speed_table(const std::vector<Record>& recs, int threads) {
    std::vector<std::string> head = kind_query_header({"method", "build ms (warm)", "B/tri"});
    head.push_back("agreement");
    Table out(head);
    for (const std::string& lab : labels(recs)) {
        const Record* first = find(recs, lab, "primary", "closest", threads);
        if (!first) continue;
        std::vector<std::string> cells{lab, fmt("%.0f", threads == 1 ? first->build_ms_warm : first->build_ms_all_warm),
                                       fmt("%.1f", first->bytes_per_triangle)};
        const std::string ref = lab == "brute" ? lab : "embree/medium/default";
        for (std::string& c : speed_cells(recs, lab, ref, threads)) cells.push_back(std::move(c));
        std::size_t agree = 0, total = 0;
        for (const Record& r : recs)
            if (label(r) == lab && r.threads == threads) {
                agree += r.tally.agree + r.tally.tie;
                total += r.tally.total();
            }
        cells.push_back(fmt("%.2f", total ? 100.0 * double(agree) / double(total) : 100.0) + "%");
        out.row(cells);
    }
    return out;
}

Table build_table(const std::vector<Record>& recs, int threads_all) {
    const std::string n = std::to_string(threads_all);
    Table t({"method", "cold ms 1 thr", "warm ms 1 thr", "cold ms " + n + " thr", "warm ms " + n + " thr",
             "of which collapse ms", "B/tri", "SAH cost"});
    for (const std::string& lab : labels(recs)) {
        const Record* r = find(recs, lab, "primary", "closest", 1);
        if (!r || r->method == "brute") continue;
        t.row({lab, fmt("%.1f", r->build_ms), fmt("%.1f", r->build_ms_warm), fmt("%.1f", r->build_ms_all),
               fmt("%.1f", r->build_ms_all_warm), is_wide(r->method) ? fmt("%.1f", r->collapse_ms) : "-",
               fmt("%.1f", r->bytes_per_triangle), r->sah_cost > 0 ? fmt("%.2f", r->sah_cost) : "-"});
    }
    return t;
}

Table accuracy_table(const std::vector<Record>& recs) {
    Table t({"method", "rays checked", "agree", "tie", "leak", "false hit", "wrong triangle", "t error"});
    for (const std::string& lab : labels(recs)) {
        Tally y;
        for (const Record& r : recs)
            if (label(r) == lab && r.threads == 1) y += r.tally;
        t.row({lab, std::to_string(y.total()), std::to_string(y.agree), std::to_string(y.tie), std::to_string(y.leak),
               std::to_string(y.false_hit), std::to_string(y.wrong_triangle), std::to_string(y.t_error)});
    }
    return t;
}

Table record_table(const std::vector<Record>& recs) {
    Table t({"method", "isa", "rays", "query", "thr", "Mrays/s", "build ms", "warm ms", "B/tri", "SAH", "nodes/ray",
             "agree"},
            "llllrrrrrrrr");
    for (const Record& r : recs)
        t.row({r.method, r.isa, r.ray_kind, r.query, std::to_string(r.threads), fmt("%.4g", r.mrays_per_s),
               fmt("%.1f", r.build_ms), fmt("%.1f", r.build_ms_warm), fmt("%.1f", r.bytes_per_triangle),
               fmt("%.2f", r.sah_cost), r.nodes_per_ray < 0 ? "-" : fmt("%.1f", r.nodes_per_ray),
               fmt("%.2f", 100.0 * r.agreement) + "%"});
    return t;
}

Table width_speed_table(const std::vector<Record>& widths, const std::string& scene) {
    const std::vector<Record> recs = of_scene(widths, scene);
    Table t(kind_query_header({"width", "method"}), "rl");
    for (const std::string& lab : labels(recs)) {
        const Record* r = find(recs, lab, "primary", "closest", 1);
        std::vector<std::string> cells{std::to_string(r ? r->width : 0), lab};
        for (std::string& c : speed_cells(recs, lab, "bvh2", 1)) cells.push_back(std::move(c));
        t.row(cells);
    }
    return t;
}

Table width_count_table(const std::vector<Record>& widths, const std::string& scene) {
    const std::vector<Record> recs = of_scene(widths, scene);
    std::vector<std::string> head{"width", "B/tri", "collapse ms (warm, median over ISAs)"};
    for (const char* q : kQueries)
        for (const char* k : kKinds) head.push_back(std::string(k) + " " + q + " nodes / boxes");
    Table t(head);
    std::vector<int> seen;
    for (const Record& r : recs) {  // the counters do not depend on the ISA: one row per width
        if (std::find(seen.begin(), seen.end(), r.width) != seen.end()) continue;
        seen.push_back(r.width);
        std::vector<std::string> cells{std::to_string(r.width), fmt("%.1f", r.bytes_per_triangle),
                                       r.width > 2 ? fmt("%.1f", collapse_median(recs, r.width)) : "-"};
        for (const char* q : kQueries)
            for (const char* k : kKinds) {
                const Record* x = find(recs, label(r), k, q, 1);
                cells.push_back(x && x->nodes_per_ray >= 0
                                    ? fmt("%.1f", x->nodes_per_ray) + " / " + fmt("%.0f", x->box_tests_per_ray)
                                    : "-");
            }
        t.row(cells);
    }
    return t;
}

}  // namespace simdbvh::lab
