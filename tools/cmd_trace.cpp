// simdbvh gen-rays and trace: ray and hit files.
#include <iostream>

#include "common.h"
#include "methods.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/scene/rays.h"

namespace simdbvh::cli {

int cmd_gen_rays(const std::vector<std::string>& args) {
    const Options o("gen-rays", args, {"scene", "kind", "count", "seed", "out"}, {});
    const std::string scene_name = o.require("scene");
    const std::string kind_s = o.require("kind");
    const auto kind = scene::parse_ray_kind(kind_s);
    if (!kind) throw UsageError("unknown --kind '" + kind_s + "' (primary, incoherent, diffuse)");
    const auto count = std::size_t(o.get_int("count", 0, 1, 1LL << 31));
    if (!o.has("count")) throw UsageError("'gen-rays': missing --count");
    const auto seed = std::uint64_t(o.get_int("seed", 1, 0, (1LL << 62)));
    const std::string out = o.require("out");
    const Mesh mesh = load_scene_with_progress(scene_name);
    progress("generating " + std::to_string(count) + " " + kind_s + " rays ...");
    const auto rays = scene::generate_rays(mesh, *kind, count, seed);
    scene::write_rays(out, rays);
    std::cout << "wrote " << rays.size() << " " << kind_s << " rays (seed " << seed << ") to " << out << "\n";
    return 0;
}

int cmd_trace(const std::vector<std::string>& args) {
    std::set<std::string> valued{"scene", "rays", "out"}, flags{"any-hit", "stats"};
    add_method_options(valued, flags);
    const Options o("trace", args, valued, flags);
    const std::string scene_name = o.require("scene");
    const std::string rays_file = o.require("rays");
    const std::string out = o.require("out");
    const MethodSpec spec = parse_method(o);
    // Read the rays first: a bad ray file fails before any expensive work.
    const auto rays = scene::read_rays(rays_file);
    const Mesh mesh = load_scene_with_progress(scene_name);
    progress("building " + spec.label() + " ...");
    auto tracer = make_tracer(mesh, spec);
    std::vector<Hit> hits(rays.size());
    const bool any = o.has("any-hit");
    TraceStats stats;
    const auto t0 = std::chrono::steady_clock::now();
    tracer->trace(rays, hits, any, o.has("stats") ? &stats : nullptr);
    const double secs = seconds_since(t0);
    scene::write_hits(out, hits);
    std::size_t n_hit = 0;
    for (const Hit& h : hits) n_hit += h.hit();
    std::cout << "method " << spec.label() << "  isa " << spec.isa_name() << "  query " << (any ? "any" : "closest")
              << "  threads " << spec.threads << "\n"
              << "rays " << rays.size() << "  hits " << n_hit << "  build " << tracer->build_ms << " ms  trace "
              << secs * 1e3 << " ms  " << (secs > 0 ? double(rays.size()) / secs / 1e6 : 0.0) << " Mrays/s\n";
    if (o.has("stats") && stats.rays)
        std::cout << "per ray: nodes visited " << double(stats.nodes_visited) / double(stats.rays) << "  box tests "
                  << double(stats.box_tests) / double(stats.rays) << "  triangle tests "
                  << double(stats.triangle_tests) / double(stats.rays) << "\n";
    std::cout << "wrote " << hits.size() << " hits to " << out << "\n";
    return 0;
}

}  // namespace simdbvh::cli
