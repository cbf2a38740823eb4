// simdbvh accuracy: every ray family (ACCURACY.md) against every method
// variant: throughput and the classification against the double reference,
// plus each family's own expectation (must hit, must miss, no self-hit).
#include <cstdlib>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "common.h"
#include "methods.h"
#include "outputs.h"
#include "simdbvh/compare/classify.h"
#include "simdbvh/compare/reference.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/parallel.h"
#include "simdbvh/scene/families.h"
#include "simdbvh/scene/rays.h"

namespace simdbvh::cli {
namespace {

namespace fs = std::filesystem;

struct Variant {
    std::string name;  // row label: bvh2/watertight/conservative, bvh8/avx2, embree/robust, ...
    MethodSpec spec;
    bool ours = false;  // a tree traversal of ours: has TraceStats, must be bit-identical to the default
};

std::vector<Variant> variants(bool with_embree) {
    std::vector<Variant> v;
    for (TriangleTest t : {TriangleTest::watertight, TriangleTest::moller})
        for (BoxTest b : {BoxTest::conservative, BoxTest::plain}) {
            Variant x;
            x.spec.method = "bvh2";
            x.spec.test = t;
            x.spec.box = b;
            x.name = std::string("bvh2/") + (t == TriangleTest::watertight ? "watertight" : "moller") + "/" +
                     (b == BoxTest::conservative ? "conservative" : "plain");
            x.ours = true;
            v.push_back(x);
        }
    for (Isa isa : supported_isas()) {
        Variant x;
        x.spec.method = "bvh8";
        x.spec.isa = isa;
        x.name = "bvh8/" + std::string(name(isa)) + "/watertight/conservative";
        x.ours = true;
        v.push_back(x);
    }
    Variant brute;
    brute.spec.method = "brute";
    brute.name = "brute/watertight";
    v.push_back(brute);
    if (with_embree)
        for (bool robust : {false, true}) {
            Variant x;
            x.spec.method = "embree";
            x.spec.robust = robust;
            x.name = robust ? "embree/robust" : "embree/default";
            v.push_back(x);
        }
    return v;
}

struct Row {  // one method on one case (or summed over a family's cases)
    std::string family, case_name, method;
    double offset = 0;
    std::size_t rays = 0, triangles = 0;
    double seconds = 0;  // trace time for `rays` rays (one thread)
    compare::Tally tally;
    std::uint64_t expect_violations = 0;  // must-hit missed, must-miss hit
    std::uint64_t self_hits = 0;          // surface-start: hit the starting triangle
    std::uint64_t nan_outputs = 0;        // a hit with a NaN t, u or v
    std::uint64_t differ_from_default = -1;  // ours: rays not bit-identical to bvh2/watertight/conservative
    double nodes_per_ray = -1;            // ours: TraceStats
    double max_rel_t_error = 0;           // hits on the reference's triangle set: max |t - t_ref| / t_ref
    int depth = 0;

    double mrays() const { return seconds > 0 ? double(rays) / seconds / 1e6 : 0.0; }
    void add(const Row& o) {
        rays += o.rays;
        triangles = std::max(triangles, o.triangles);
        seconds += o.seconds;
        tally += o.tally;
        expect_violations += o.expect_violations;
        self_hits += o.self_hits;
        nan_outputs += o.nan_outputs;
        if (o.differ_from_default != std::uint64_t(-1))
            differ_from_default = (differ_from_default == std::uint64_t(-1) ? 0 : differ_from_default) + o.differ_from_default;
        if (o.nodes_per_ray >= 0)
            nodes_per_ray = nodes_per_ray < 0 ? o.nodes_per_ray : std::max(nodes_per_ray, o.nodes_per_ray);
        max_rel_t_error = std::max(max_rel_t_error, o.max_rel_t_error);
        depth = std::max(depth, o.depth);
    }
};

double time_trace(Tracer& tr, std::span<const Ray> rays, std::span<Hit> hits, double min_seconds) {
    int reps = 0;
    const auto t0 = std::chrono::steady_clock::now();
    double s = 0;
    do {
        tr.trace(rays, hits, false, nullptr);
        ++reps;
        s = seconds_since(t0);
    } while (s < min_seconds && reps < 100);
    return s / reps;
}

Row run_case(const scene::FamilyCase& c, const std::vector<compare::Reference>& refs, const Variant& v,
             std::vector<Hit>& default_hits, double min_seconds) {
    Row r;
    r.family = std::string(scene::name(c.family));
    r.case_name = c.name;
    r.method = v.name;
    r.offset = c.offset;
    r.rays = c.rays.size();
    r.triangles = c.mesh.size();
    auto tracer = make_tracer(c.mesh, v.spec);
    r.depth = tracer->depth;
    std::vector<Hit> hits(c.rays.size());
    r.seconds = time_trace(*tracer, c.rays, hits, min_seconds) ;
    if (v.ours) {
        TraceStats st;
        std::vector<Hit> again(c.rays.size());
        tracer->trace(c.rays, again, false, &st);
        r.nodes_per_ray = st.rays ? double(st.nodes_visited) / double(st.rays) : 0.0;
        if (default_hits.empty()) default_hits = hits;  // the first variant is the default path
        r.differ_from_default = 0;
        for (std::size_t i = 0; i < hits.size(); ++i) r.differ_from_default += !(hits[i] == default_hits[i]) || !(again[i] == hits[i]);
    }
    for (std::size_t i = 0; i < hits.size(); ++i) {
        const Hit& h = hits[i];
        r.tally.add(compare::classify(refs[i], h));
        if (h.hit() && (std::isnan(h.t) || std::isnan(h.u) || std::isnan(h.v))) ++r.nan_outputs;
        const scene::RayExpect& e = c.expect[i];
        if (e.kind == scene::Expect::hit && !h.hit()) ++r.expect_violations;
        if (e.kind == scene::Expect::miss && h.hit()) ++r.expect_violations;
        if (e.kind == scene::Expect::no_self_hit && h.hit() && h.prim == e.source) ++r.self_hits;
        if (h.hit() && refs[i].hit()) {
            const double want = !std::isnan(e.t) ? e.t : refs[i].t;
            if (want > 0) r.max_rel_t_error = std::max(r.max_rel_t_error, std::fabs(double(h.t) - want) / want);
        }
    }
    return r;
}

std::string fmt(double v, int prec = 2) {
    std::ostringstream s;
    s << std::fixed << std::setprecision(prec) << v;
    return s.str();
}
std::string sci(double v) {
    std::ostringstream s;
    s << std::scientific << std::setprecision(1) << v;
    return s.str();
}

const char* kHeader =
    "| method | rays | Mrays/s | agree | tie | leak | false hit | wrong tri | t error | (marginal) | disagree/M | "
    "expect viol. | self-hits | NaN | != default | nodes/ray | max rel t err |\n"
    "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";

std::string table_row(const Row& r) {
    const compare::Tally& t = r.tally;
    std::ostringstream s;
    s << "| " << r.method << " | " << r.rays << " | " << fmt(r.mrays()) << " | " << t.agree << " | " << t.tie << " | "
      << t.leak << " | " << t.false_hit << " | " << t.wrong_triangle << " | " << t.t_error << " | " << t.marginal
      << " | " << fmt(t.disagreements_per_million(), 1) << " | " << r.expect_violations << " | " << r.self_hits
      << " | " << r.nan_outputs << " | "
      << (r.differ_from_default == std::uint64_t(-1) ? std::string("-") : std::to_string(r.differ_from_default))
      << " | " << (r.nodes_per_ray < 0 ? std::string("-") : fmt(r.nodes_per_ray, 1)) << " | "
      << sci(r.max_rel_t_error) << " |\n";
    return s.str();
}

std::string json_escape(const std::string& s) {
    std::string o;
    for (char c : s) {
        if (c == '"' || c == '\\') o += '\\';
        o += c;
    }
    return o;
}

std::string json_row(const Row& r, const char* level) {
    const compare::Tally& t = r.tally;
    std::ostringstream s;
    s << std::setprecision(9) << "{\"level\": \"" << level << "\", \"family\": \"" << json_escape(r.family)
      << "\", \"case\": \"" << json_escape(r.case_name) << "\", \"method\": \"" << json_escape(r.method)
      << "\", \"offset\": " << r.offset << ", \"rays\": " << r.rays << ", \"triangles\": " << r.triangles
      << ", \"seconds\": " << r.seconds << ", \"mrays_per_s\": " << r.mrays() << ", \"agree\": " << t.agree
      << ", \"tie\": " << t.tie << ", \"leak\": " << t.leak << ", \"false_hit\": " << t.false_hit
      << ", \"wrong_triangle\": " << t.wrong_triangle << ", \"t_error\": " << t.t_error
      << ", \"marginal\": " << t.marginal << ", \"disagreements_per_million\": " << t.disagreements_per_million()
      << ", \"expect_violations\": " << r.expect_violations << ", \"self_hits\": " << r.self_hits
      << ", \"nan_outputs\": " << r.nan_outputs << ", \"differ_from_default\": "
      << (r.differ_from_default == std::uint64_t(-1) ? std::string("null") : std::to_string(r.differ_from_default))
      << ", \"nodes_per_ray\": " << (r.nodes_per_ray < 0 ? std::string("null") : fmt(r.nodes_per_ray, 3))
      << ", \"max_rel_t_error\": " << r.max_rel_t_error << ", \"depth\": " << r.depth << "}";
    return s.str();
}

}  // namespace

int cmd_accuracy(const std::vector<std::string>& args) {
    const Options o("accuracy", args, {"report", "json", "seed", "family", "threads", "scene"}, {"quick", "no-embree"});
    const bool quick = o.has("quick");
    scene::FamilyOptions fo;
    fo.quick = quick;
    fo.seed = std::uint64_t(o.get_int("seed", 1, 0, (1LL << 62)));
    fo.random_scene = o.get("scene");
    const int threads = int(o.get_int("threads", 2, 1, 1024));  // the reference only; traces run on one thread
    std::vector<scene::Family> fams;
    if (o.has("family")) {
        std::stringstream ss(o.get("family"));
        std::string f;
        while (std::getline(ss, f, ',')) {
            const auto p = scene::parse_family(f);
            if (!p) throw UsageError("unknown --family '" + f + "' (watertight, offsets, axis-aligned, surface-start, grazing, needles, degenerate, random, direction-scale)");
            fams.push_back(*p);
        }
    } else {
        fams.assign(std::begin(scene::kAllFamilies), std::end(scene::kAllFamilies));
    }
    // Fail on unwritable outputs before the long run.
    NamedPaths outputs;
    if (o.has("json")) outputs.emplace_back("--json", o.get("json"));
    if (o.has("report")) outputs.emplace_back("--report", (fs::path(o.get("report")) / "accuracy.md").string());
    check_outputs(outputs, {{"--scene", o.get("scene")}}, /*create_parent=*/true);
    if (o.has("report")) fs::create_directories(o.get("report"));
    const std::vector<Variant> methods = variants(!o.has("no-embree"));
    const double min_seconds = quick ? 0.01 : 0.05;

    std::vector<Row> case_rows;
    std::map<std::string, std::vector<Row>> family_rows;  // family -> one row per method (summed)
    std::map<std::string, std::map<double, std::vector<Row>>> offset_rows;  // offsets: per offset, per method
    for (scene::Family fam : fams) {
        const std::string fname(scene::name(fam));
        progress("family " + fname + " ...", true);
        const auto cases = scene::make_family(fam, fo);
        std::vector<Row> sum(methods.size());
        for (const scene::FamilyCase& c : cases) {
            std::vector<compare::Reference> refs(c.rays.size());
            parallel_for(c.rays.size(), threads, [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i) refs[i] = compare::reference_intersect(c.mesh, c.rays[i]);
            });
            std::vector<Hit> default_hits;
            for (std::size_t m = 0; m < methods.size(); ++m) {
                Row r = run_case(c, refs, methods[m], default_hits, min_seconds);
                if (sum[m].method.empty()) {
                    sum[m].family = fname;
                    sum[m].case_name = fname;
                    sum[m].method = r.method;
                }
                sum[m].add(r);
                if (fam == scene::Family::offsets) {
                    auto& v = offset_rows[fname][c.offset];
                    if (v.size() <= m) v.resize(methods.size());
                    if (v[m].method.empty()) {
                        v[m] = r;
                        v[m].case_name = fname;
                    } else {
                        v[m].add(r);
                    }
                }
                case_rows.push_back(std::move(r));
            }
        }
        family_rows[fname] = sum;
    }

    // Output: per family tables (stdout, accuracy.md), per-offset table, JSON.
    std::ostringstream md;
    md << "# simdbvh accuracy\n\nCommand: `simdbvh accuracy" << (quick ? " --quick" : "")
       << "`; seed " << fo.seed << "; traces on one thread; active ISA " << name(active_isa()) << " (" << cpu_name()
       << ").\nClassification against the double-precision watertight reference (ACCURACY.md): agree/tie are "
          "agreements; leak, false hit, wrong triangle, t error are disagreements ((marginal): those within float "
          "rounding of the reference). expect viol.: the family's own answer (must hit / must miss) violated; "
          "self-hits: surface-start rays hitting their starting triangle; != default: rays not bit-identical to "
          "bvh2/watertight/conservative. BVH8 always uses the conservative box test.\n";
    for (scene::Family fam : fams) {
        const std::string fname(scene::name(fam));
        md << "\n## " << fname << "\n\n" << kHeader;
        for (const Row& r : family_rows[fname]) md << table_row(r);
    }
    for (auto& [fname, by_off] : offset_rows) {
        md << "\n## offsets, per offset\n\n| offset | method | rays | leak | false hit | wrong tri | t error | max rel t err |\n"
              "|---:|---|---:|---:|---:|---:|---:|---:|\n";
        for (auto& [off, rows] : by_off)
            for (const Row& r : rows)
                md << "| " << sci(off) << " | " << r.method << " | " << r.rays << " | " << r.tally.leak << " | "
                   << r.tally.false_hit << " | " << r.tally.wrong_triangle << " | " << r.tally.t_error << " | "
                   << sci(r.max_rel_t_error) << " |\n";
    }
    md << "\n## cases\n\n| case | method | rays | triangles | depth | leak | false hit | wrong tri | t error | expect viol. | self-hits |\n"
          "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const Row& r : case_rows)
        md << "| " << r.case_name << " | " << r.method << " | " << r.rays << " | " << r.triangles << " | " << r.depth
           << " | " << r.tally.leak << " | " << r.tally.false_hit << " | " << r.tally.wrong_triangle << " | "
           << r.tally.t_error << " | " << r.expect_violations << " | " << r.self_hits << " |\n";
    std::ostringstream js;
    js << "{\n  \"command\": \"accuracy\", \"quick\": " << (quick ? "true" : "false") << ", \"seed\": " << fo.seed
       << ", \"isa\": \"" << name(active_isa()) << "\",\n  \"rows\": [\n";
    bool first = true;
    auto emit = [&](const Row& r, const char* level) {
        js << (first ? "    " : ",\n    ") << json_row(r, level);
        first = false;
    };
    for (auto& [fname, rows] : family_rows)
        for (const Row& r : rows) emit(r, "family");
    for (auto& [fname, by_off] : offset_rows)
        for (auto& [off, rows] : by_off)
            for (const Row& r : rows) emit(r, "offset");
    for (const Row& r : case_rows) emit(r, "case");
    js << "\n  ]\n}\n";
    const std::string jtext = js.str();
    auto write_json = [&](const fs::path& p) {
        if (p.has_parent_path()) fs::create_directories(p.parent_path());
        scene::write_file_atomic(p, std::span(reinterpret_cast<const unsigned char*>(jtext.data()), jtext.size()));
        std::cout << "wrote " << p.string() << "\n";
    };
    if (o.has("json")) write_json(o.get("json"));
    if (o.has("report")) write_json(fs::path(o.get("report")) / "accuracy.json");
    // Charts (scripts/plot_accuracy.py, matplotlib) next to the report.
    bool charts = false;
    if (o.has("report")) {
        const fs::path dir = o.get("report");
        const std::string py = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
        const std::string cmd = py + " '" SIMDBVH_SOURCE_DIR "/scripts/plot_accuracy.py' '" +
                                (dir / "accuracy.json").string() + "' '" + dir.string() + "' >/dev/null";
        charts = std::system(cmd.c_str()) == 0;
        if (!charts) progress("warning: chart script failed (" + cmd + "); the report has tables only", true);
    }
    if (charts)
        md << "\n## Charts\n\n![speed against accuracy](speed_vs_accuracy.png)\n\n"
              "![leak rate and t error against offset](offsets.png)\n";
    const std::string text = md.str();
    std::cout << text;
    if (o.has("report")) {
        const fs::path dir = o.get("report");
        const std::string& t = text;
        scene::write_file_atomic(dir / "accuracy.md", std::span(reinterpret_cast<const unsigned char*>(t.data()), t.size()));
        std::cout << "\nwrote " << (dir / "accuracy.md").string() << "\n";
    }
    return 0;
}

}  // namespace simdbvh::cli
