// simdbvh bench: the main job. Every method on one scene: build time, memory,
// Mrays/s per ray kind and query with 1 thread and all cores (median of
// repetitions), accuracy against brute force on a sample; a table, a JSON
// file and a Markdown report with charts and pictures.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "accuracy.h"
#include "bench_report.h"
#include "common.h"
#include "image.h"
#include "methods.h"
#include "outputs.h"
#include "simdbvh/kernels/topology.h"
#include "simdbvh/scene/rays.h"

namespace simdbvh::cli {

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

std::string json_escape(const std::string& s) {
    std::string o;
    for (char c : s) {
        if (c == '"' || c == '\\') o += '\\';
        o += c;
    }
    return o;
}

std::string to_json(const std::vector<Record>& recs, const std::string& scene, std::size_t tris,
                    const std::string& machine) {
    std::ostringstream j;
    j.precision(6);
    j << "{\n  \"scene\": \"" << json_escape(scene) << "\",\n  \"triangles\": " << tris << ",\n  \"machine\": \""
      << json_escape(machine) << "\",\n  \"records\": [\n";
    for (std::size_t i = 0; i < recs.size(); ++i) {
        const Record& r = recs[i];
        j << "    {\"method\": \"" << r.method << "\", \"isa\": \"" << r.isa << "\", \"builder\": \"" << r.builder
          << "\", \"ray_kind\": \"" << r.ray_kind << "\", \"query\": \"" << r.query << "\", \"threads\": " << r.threads
          << ", \"mrays_per_s\": " << r.mrays_per_s << ", \"build_ms\": " << r.build_ms
          << ", \"build_ms_all_cores\": " << r.build_ms_all << ", \"bytes_per_triangle\": " << r.bytes_per_triangle
          << ", \"sah_cost\": " << r.sah_cost << ", \"agreement\": " << r.agreement << ", \"rays\": " << r.rays
          << ", \"sample\": " << r.sample << ", \"disagreements\": {\"tie\": " << r.tally.tie
          << ", \"leak\": " << r.tally.leak << ", \"false_hit\": " << r.tally.false_hit
          << ", \"wrong_triangle\": " << r.tally.wrong_triangle << ", \"t_error\": " << r.tally.t_error << "}}"
          << (i + 1 < recs.size() ? ",\n" : "\n");
    }
    j << "  ]\n}\n";
    return j.str();
}

void write_text(const std::string& file, const std::string& text) {
    scene::write_file_atomic(file, std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()));
}

}  // namespace

int cmd_bench(const std::vector<std::string>& args) {
    const Options o("bench", args, {"scene", "threads", "json", "report", "reps", "rays", "sample", "readme"}, {"quick", "no-report"});
    std::string why;
    const std::string scene_name = o.has("scene") ? o.get("scene") : default_scene(&why);
    const bool quick = o.has("quick");
    const Topology& topo = topology();
    const int all = int(o.get_int("threads", std::max(1, topo.physical_cores), 1, 1024));
    const int reps = int(o.get_int("reps", quick ? 3 : 5, 1, 100));
    const auto nrays = std::size_t(o.get_int("rays", quick ? 65536 : 262144, 1024, 1 << 26));
    const auto nsample = std::size_t(o.get_int("sample", quick ? 300 : 1000, 16, 1 << 20));
    const std::string report_dir = o.get("report", "out");
    const std::string json_file = o.get("json", report_dir + "/bench.json");
    // Outputs are checked before the long run; the command creates the report folder.
    NamedPaths outputs{{"--json", json_file}};
    if (!o.has("no-report")) outputs.emplace_back("--report", report_dir + "/report.md");
    if (o.has("readme")) outputs.emplace_back("--readme", o.get("readme"));
    check_outputs(outputs, {{"--scene", scene_name}}, /*create_parent=*/true);
    const std::string machine = machine_line();

    progress("scene: " + scene_name + (why.empty() ? "" : " (" + why + ")"), true);
    progress("machine: " + machine, true);
    const Mesh mesh = load_scene_with_progress(scene_name);

    // Rays: a square primary image, incoherent and diffuse sets of the same size.
    using scene::RayKind;
    const RayKind kinds[] = {RayKind::primary, RayKind::incoherent, RayKind::diffuse};
    std::vector<std::vector<Ray>> rays;
    for (RayKind k : kinds) {
        progress("generating " + std::to_string(nrays) + " " + std::string(scene::name(k)) + " rays", true);
        rays.push_back(scene::generate_rays(mesh, k, nrays, 42));
    }

    // The reference on the accuracy sample: brute force, closest and any hit.
    progress("brute-force reference on " + std::to_string(nsample) + " rays per kind (" + std::to_string(all) +
                 " threads)",
             true);
    MethodSpec brute_spec;
    brute_spec.method = "brute";
    brute_spec.threads = all;
    auto brute = make_tracer(mesh, brute_spec);
    std::vector<std::vector<Hit>> ref_closest(3), ref_any(3);
    for (int k = 0; k < 3; ++k) {
        const std::size_t s = std::min(nsample, rays[k].size());
        ref_closest[k].resize(s);
        ref_any[k].resize(s);
        brute->trace(std::span(rays[k]).first(s), ref_closest[k], false, nullptr);
        brute->trace(std::span(rays[k]).first(s), ref_any[k], true, nullptr);
    }

    std::vector<MethodSpec> methods;
    MethodSpec m;
    m.method = "brute";
    methods.push_back(m);
    m.method = "bvh2";
    methods.push_back(m);
    for (const char* wide : kWideMethods)
        for (Isa isa : kAllIsas) {
            if (!supported(isa)) {
                progress("skipping " + std::string(wide) + "/" + std::string(name(isa)) + ": this CPU lacks it", true);
                continue;
            }
            m.method = wide;
            m.isa = isa;
            methods.push_back(m);
        }
    for (const char* q : {"medium", "high"})
        for (bool robust : {false, true}) {
            m = MethodSpec{};
            m.method = "embree";
            m.quality = q;
            m.robust = robust;
            methods.push_back(m);
        }

    std::vector<Record> records;
    std::vector<Hit> hits(nrays);
    for (const MethodSpec& base : methods) {
        MethodSpec one = base;
        one.threads = 1;
        one.build.threads = 1;
        progress("building " + one.label() + " (1 thread)", true);
        auto tracer = make_tracer(mesh, one);
        double build_all = tracer->build_ms;
        std::unique_ptr<Tracer> tracer_all;
        if (all > 1 && base.method != "brute") {
            MethodSpec many = base;
            many.threads = all;
            many.build.threads = all;
            progress("building " + one.label() + " (" + std::to_string(all) + " threads)", true);
            tracer_all = make_tracer(mesh, many);
            build_all = tracer_all->build_ms;
        }
        for (int k = 0; k < 3; ++k) {
            for (bool any : {false, true}) {
                // Brute force runs on the sample only.
                // Brute force is timed on a small slice of the sample only (it is O(triangles) per ray).
                const std::size_t brute_n = std::min<std::size_t>(ref_closest[k].size(), 100);
                const std::span<const Ray> rs = base.method == "brute" ? std::span<const Ray>(rays[k]).first(brute_n)
                                                                       : std::span<const Ray>(rays[k]);
                const std::span<const Hit> ref = std::span<const Hit>(any ? ref_any[k] : ref_closest[k])
                                                     .first(std::min(rs.size(), ref_closest[k].size()));
                for (int th : {1, all}) {
                    if (th != 1 && th == all && all == 1) continue;
                    Tracer* t = th == 1 ? tracer.get() : (tracer_all ? tracer_all.get() : nullptr);
                    MethodSpec run = base;
                    if (!t) {  // brute: same object, more threads
                        run.threads = th;
                        tracer_all = make_tracer(mesh, run);
                        t = tracer_all.get();
                    }
                    std::vector<double> mr;
                    for (int r = 0; r < (base.method == "brute" ? 1 : reps); ++r) {
                        const auto t0 = std::chrono::steady_clock::now();
                        t->trace(rs, std::span(hits).first(rs.size()), any, nullptr);
                        mr.push_back(double(rs.size()) / seconds_since(t0) / 1e6);
                    }
                    Record rec;
                    rec.method = base.method == "embree" ? base.label() : base.method;
                    rec.isa = base.isa_name();
                    rec.builder = base.builder_name();
                    rec.ray_kind = std::string(scene::name(kinds[k]));
                    rec.query = any ? "any" : "closest";
                    rec.threads = th;
                    rec.mrays_per_s = median(mr);
                    rec.build_ms = tracer->build_ms;
                    rec.build_ms_all = build_all;
                    rec.bytes_per_triangle = tracer->bytes_per_triangle;
                    rec.sah_cost = tracer->sah_cost;
                    rec.rays = rs.size();
                    rec.sample = ref.size();
                    rec.tally = classify_sample(mesh, std::span<const Ray>(rays[k]).first(ref.size()), ref,
                                                std::span<const Hit>(hits).first(ref.size()), any);
                    rec.agreement = rec.tally.agreement_rate();
                    records.push_back(rec);
                }
            }
        }
        progress("done " + one.label(), true);
    }

    // Terminal table.
    std::printf("\nscene %s, %zu triangles; %s\n", scene_name.c_str(), mesh.size(), machine.c_str());
    std::printf("%-22s %-8s %-10s %-7s %3s %9s %9s %9s %7s %9s\n", "method", "isa", "rays", "query", "thr", "Mrays/s",
                "build ms", "B/tri", "SAH", "agree");
    for (const Record& r : records)
        std::printf("%-22s %-8s %-10s %-7s %3d %9.4g %9.1f %9.1f %7.2f %8.2f%%\n", r.method.c_str(), r.isa.c_str(),
                    r.ray_kind.c_str(), r.query.c_str(), r.threads, r.mrays_per_s, r.build_ms, r.bytes_per_triangle,
                    r.sah_cost, 100.0 * r.agreement);

    std::filesystem::create_directories(std::filesystem::path(json_file).parent_path().empty()
                                            ? std::filesystem::path(".")
                                            : std::filesystem::path(json_file).parent_path());
    write_text(json_file, to_json(records, scene_name, mesh.size(), machine));
    std::cout << "\nwrote " << json_file << "\n";
    if (!o.has("no-report")) {
        progress("rendering pictures and charts into " + report_dir, true);
        ReportInputs in{report_dir, json_file, scene_name, why, machine, &mesh, &records, quick, all};
        in.readme = o.get("readme");
        in.command = "simdbvh bench";
        for (const std::string& a : args) in.command += " " + a;
        write_report(in);
        std::cout << "wrote " << report_dir << "/report.md\n";
    }
    return 0;
}

}  // namespace simdbvh::cli
