// simdbvh gen-rays and trace: ray and hit files.
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "common.h"
#include "methods.h"
#include "outputs.h"
#include "saved.h"
#include "scene_cmds.h"
#include "trace_crossings.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/workloads/families.h"
#include "simdbvh/io/write_ply.h"
#include "simdbvh/io/load.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/io/ray_files.h"
#include "simdbvh/io/output.h"

namespace simdbvh::cli {

namespace {

// gen-rays --kind <family>: the family's own mesh and rays (one case).
int gen_family_rays(const Options& o, workloads::Family fam) {
    const std::string kind_s = o.require("kind");
    if (o.has("scene") && fam != workloads::Family::random)
        throw UsageError("--kind " + kind_s +
                         " generates its own scene (write it with --mesh-out); --scene is for "
                         "primary, incoherent, diffuse and random");
    workloads::FamilyOptions fo;
    fo.quick = o.has("quick");
    fo.seed = std::uint64_t(o.get_int("seed", 1, 0, (1LL << 62)));
    fo.random_scene = o.get("scene");
    const std::string out = o.require("out");
    NamedPaths outputs;
    if (o.has("mesh-out")) outputs.emplace_back("--mesh-out", o.get("mesh-out"));
    outputs.emplace_back("--out", out);
    // The random family's scene: --scene, else dragon-res4 when cached (family_random.cpp).
    Inputs inputs;
    if (o.has("scene")) inputs.scenes.emplace_back("--scene", o.get("scene"));
    else if (fam == workloads::Family::random) inputs.scenes.emplace_back("--kind random's scene", "dragon-res4");
    check_outputs(outputs, inputs);
    progress("generating the " + kind_s + " family ...");
    auto cases = workloads::make_family(fam, fo);
    const std::string want = o.get("case", cases.front().name);
    const workloads::FamilyCase* c = nullptr;
    std::string names;
    for (const auto& fc : cases) {
        names += (names.empty() ? "" : ", ") + fc.name;
        if (fc.name == want) c = &fc;
    }
    if (!c) throw UsageError("unknown --case '" + want + "' (" + names + ")");
    std::vector<Ray> rays = c->rays;
    if (o.has("count")) rays.resize(std::min(rays.size(), std::size_t(o.get_int("count", 0, 1, 1LL << 31))));
    // Both files or neither: the mesh is not left behind when the rays cannot be written.
    const auto ray_bytes = io::encode_rays(rays);
    std::vector<unsigned char> mesh_bytes;
    std::vector<io::OutputFile> files;
    if (o.has("mesh-out")) {
        mesh_bytes = io::encode_ply(c->mesh);
        files.push_back({o.get("mesh-out"), mesh_bytes});
    }
    files.push_back({out, ray_bytes});
    io::write_files_atomic(files);
    std::cout << "wrote " << rays.size() << " rays of case " << c->name << " (seed " << fo.seed << ") to " << out;
    if (o.has("mesh-out")) std::cout << " and its " << c->mesh.size() << "-triangle mesh to " << o.get("mesh-out");
    std::cout << "\ncases: " << names << "\n";
    return 0;
}

// --drop-invalid: a mesh file loaded with LoadOptions::drop_invalid (triangles
// with a non-finite vertex are dropped and counted on stdout). Named scenes
// are always valid and load as usual.
Mesh load_for_trace(const std::string& name, bool drop_invalid) {
    if (!drop_invalid || !std::filesystem::is_regular_file(name)) return load_scene_with_progress(name);
    io::LoadReport report;
    Mesh m = io::load_mesh(name, io::LoadOptions{.drop_invalid = true}, &report);
    std::cout << "dropped " << report.dropped_triangles << " triangles with non-finite vertices from " << name << "\n";
    return m;
}

}  // namespace

int cmd_gen_rays(const std::vector<std::string>& args) {
    const Options o("gen-rays", args, {"scene", "kind", "count", "seed", "out", "mesh-out", "case"}, {"quick"});
    const std::string kind_s = o.require("kind");
    if (const auto fam = workloads::parse_family(kind_s)) return gen_family_rays(o, *fam);
    if (o.has("mesh-out") || o.has("case") || o.has("quick"))
        throw UsageError("--mesh-out, --case and --quick apply to ray families only (--kind watertight, ...)");
    const std::string scene_name = o.require("scene");
    const auto kind = workloads::parse_ray_kind(kind_s);
    if (!kind)
        throw UsageError("unknown --kind '" + kind_s + "' (" + workloads::ray_kind_names() +
                         ", or a family: watertight, offsets, axis-aligned, "
                         "surface-start, grazing, needles, degenerate, random, direction-scale)");
    const auto count = std::size_t(o.get_int("count", 0, 1, 1LL << 31));
    if (!o.has("count")) throw UsageError("'gen-rays': missing --count");
    const auto seed = std::uint64_t(o.get_int("seed", 1, 0, (1LL << 62)));
    const std::string out = o.require("out");
    check_outputs({{"--out", out}}, {.scenes = {{"--scene", scene_name}}});
    // Rays and their encoded bytes; diffuse rays also hold the primary rays and hits.
    const std::string count_opt = "--count " + std::to_string(count);
    const bool from_hits = workloads::needs_primary_hits(*kind);
    const std::uint64_t per_ray = from_hits ? 32 + 32 + 16 + 32 : 32 + 32;
    check_memory(count_opt, std::uint64_t(count) * per_ray);
    if (is_scene_desc(scene_name) && from_hits)
        throw UsageError("--kind " + kind_s +
                         " needs a mesh scene (scenes: primary, incoherent or lidar, aimed at their bounds)");
    const Mesh mesh = is_scene_desc(scene_name) ? scene_bounds_proxy(scene_name) : load_scene_with_progress(scene_name);
    progress("generating " + std::to_string(count) + " " + kind_s + " rays ...");
    try {
        const auto rays = workloads::generate_rays(mesh, *kind, count, seed);
        // Diffuse rays bounce off primary hits: none when the camera sees no triangle. The user asked for
        // `count` rays, so an empty (or short) file is an error, not a success.
        if (rays.size() < count)
            throw Error(scene_name + ": cannot generate " + std::to_string(count) + " " + kind_s + " rays: got " +
                        std::to_string(rays.size()) + " (the mesh has " + std::to_string(mesh.size()) + " triangles; " +
                        kind_s + " rays need primary rays from the default camera to hit it)");
        // A ray file is for tracing: a zero or non-finite direction (or origin) would miss everything.
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const Vec3 d = rays[i].dir;
            if (!is_finite(rays[i].org) || !is_finite(d) || (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f))
                throw Error(scene_name + ": " + kind_s + " ray " + std::to_string(i) +
                            " has a zero or non-finite direction or origin (the scene's coordinates are beyond what "
                            "float rays can aim at); nothing written");
        }
        io::write_file_atomic(out, io::encode_rays(rays));
    } catch (const std::bad_alloc&) {
        throw Error(count_opt + ": out of memory (needs about " + format_bytes(std::uint64_t(count) * per_ray) +
                    "); ask for fewer rays");
    }
    std::cout << "wrote " << count << " " << kind_s << " rays (seed " << seed << ") to " << out << "\n";
    return 0;
}

int cmd_trace(const std::vector<std::string>& args) {
    std::set<std::string> valued{"scene", "rays", "out", "query", "max-hits", "instance-bounds"},
        flags{"any-hit", "stats", "drop-invalid"};
    add_method_options(valued, flags);
    const Options o("trace", args, valued, flags);
    const std::string scene_name = o.require("scene");
    const std::string rays_file = o.require("rays");
    const std::string out = o.require("out");
    MethodSpec spec = parse_method(o, "auto");
    const std::string query = o.get("query", o.has("any-hit") ? "any" : "closest");
    if (query != "closest" && query != "any" && query != "all" && query != "count")
        throw UsageError("unknown --query '" + query + "' (closest, any, all, count)");
    if (o.has("any-hit") && query != "any")
        throw UsageError("--any-hit and --query " + query + " contradict each other");
    const bool crossings = query == "all" || query == "count";
    if (crossings && !o.has("method")) spec.method = "bvh2";  // auto's only tree with crossing queries
    if (crossings && spec.method != "bvh2" && spec.method != "brute")
        throw UsageError("--query " + query + " runs on --method bvh2 or brute (not " + spec.method + ")");
    if (crossings && o.has("stats")) throw UsageError("--stats applies to --query closest and any");
    if (o.has("max-hits") && query != "all") throw UsageError("--max-hits applies to --query all");
    if (is_scene_desc(scene_name)) {
        if (crossings) throw UsageError("scenes take --query closest or any");
        return trace_scene(o, scene_name, rays_file, out, spec, query == "any", parse_instance_bounds(o));
    }
    if (o.has("instance-bounds")) throw UsageError("--instance-bounds applies to scenes (room, instances-N, *.json)");
    check_outputs({{"--out", out}}, {.files = {{"--rays", rays_file}}, .scenes = {{"--scene", scene_name}}});
    // Read the rays first: a bad ray file fails before any expensive work.
    const auto rays = io::read_rays(rays_file);
    const bool saved = is_saved_scene(scene_name);  // a tree saved by `simdbvh build`: loaded, not built
    if (saved && (crossings || o.has("drop-invalid")))
        throw UsageError("--scene " + scene_name + " is a saved tree: it takes --query closest or any");
    const Mesh mesh = saved ? Mesh{} : load_for_trace(scene_name, o.has("drop-invalid"));
    if (crossings) {
        CrossingQuery q;
        q.all = query == "all";
        q.cap = std::size_t(o.get_int("max-hits", 1024, 1, 1LL << 20));
        progress("tracing " + query + " ...");
        trace_crossings(mesh, rays, spec, q, out);
        return 0;
    }
    spec.expected_rays = rays.size();
    progress(saved ? "loading " + scene_name + " ..." : "building " + spec.label() + " ...");
    auto tracer = saved ? load_saved_tracer(scene_name, spec, o.has("method")) : make_tracer(mesh, spec);
    std::vector<Hit> hits(rays.size());
    const bool any = query == "any";
    TraceStats stats;
    const auto t0 = std::chrono::steady_clock::now();
    tracer->trace(rays, hits, any, o.has("stats") ? &stats : nullptr);
    const double secs = seconds_since(t0);
    io::write_hits(out, hits);
    std::size_t n_hit = 0;
    for (const Hit& h : hits) n_hit += h.hit();
    std::cout << "method " << spec.label() << "  isa " << tracer->ran_isa(spec, any) << spec.isa_note(any) << "  query "
              << (any ? "any" : "closest") << "  threads " << spec.threads << "\n"
              << (tracer->chosen.empty() ? "" : "auto chose " + tracer->chosen + "\n") << "rays " << rays.size()
              << "  hits " << n_hit << "  build " << tracer->build_ms << " ms  trace " << secs * 1e3 << " ms  "
              << (secs > 0 ? double(rays.size()) / secs / 1e6 : 0.0) << " Mrays/s\n";
    if (o.has("stats") && stats.rays)
        std::cout << "per ray: nodes visited " << double(stats.nodes_visited) / double(stats.rays) << "  box tests "
                  << double(stats.box_tests) / double(stats.rays) << "  triangle tests "
                  << double(stats.triangle_tests) / double(stats.rays) << "\n";
    std::cout << "wrote " << hits.size() << " hits to " << out << "\n";
    return 0;
}

}  // namespace simdbvh::cli
