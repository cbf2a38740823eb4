// simdbvh info: the scene, its BVH2 and every wide BVH collapsed from it (4, 8, 16).
#include <cstdio>
#include <iostream>

#include "common.h"
#include "methods.h"
#include "printable.h"
#include "saved.h"
#include "scene_cmds.h"
#include "simdbvh/accel/cost_model.h"

namespace simdbvh::cli {

namespace {

template <int N>
WideStats wide_stats(const Bvh2& bvh2, const MethodSpec& spec) {
    std::string msg = "collapsing to BVH";  // (built with += : GCC 12 warns falsely on "literal" + string)
    msg += std::to_string(N);
    progress(msg + " ...");
    return BvhN<N>::build(bvh2, spec.wide).stats();
}

}  // namespace

int cmd_info(const std::vector<std::string>& args) {
    std::set<std::string> valued{"scene", "expected-rays", "instance-bounds"}, flags;
    add_method_options(valued, flags);
    const Options o("info", args, valued, flags);
    const std::string scene_name = o.require("scene");
    const MethodSpec spec = parse_method(o);
    if (is_saved_scene(scene_name)) return info_saved(scene_name);
    if (is_scene_desc(scene_name)) {
        refuse_mesh_options(o, scene_name);
        return info_scene(scene_name, spec, parse_instance_bounds(o));
    }
    if (o.has("instance-bounds")) throw UsageError("--instance-bounds applies to scenes (room, instances-N, *.json)");
    const Mesh mesh = load_scene_with_progress(scene_name);
    const Aabb b = mesh.bounds();
    std::printf("scene        %s\n", printable(scene_name).c_str());
    std::printf("triangles    %zu\n", mesh.size());
    std::printf("vertices     %zu\n", mesh.positions.size());
    std::printf("bounds       [%g %g %g] - [%g %g %g]\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
    std::printf("isa          %s\n", std::string(name(spec.isa)).c_str());
    const auto expected = std::size_t(o.get_int("expected-rays", 1000000, 1, 1LL << 40));
    std::printf("auto         %s\n",
                describe(choose(cost_model(spec.isa), mesh.size(), expected, spec.threads)).c_str());
    progress("building BVH2 ...");
    const Bvh2 bvh2 = Bvh2::build(mesh, spec.build);
    const BuildStats& s = bvh2.stats();
    std::printf("\nbvh2 (%s, %d bins, %d thread%s)\n", std::string(name(spec.build.builder)).c_str(), spec.build.bins,
                spec.build.threads, spec.build.threads == 1 ? "" : "s");
    std::printf(
        "  build ms        %.1f\n  nodes           %zu\n  leaves          %zu\n  depth           %d\n"
        "  SAH cost        %.3f\n  bytes/triangle  %.1f\n",
        s.build_ms, s.nodes, s.leaves, s.depth, s.sah_cost, s.bytes_per_triangle);
    // Every width from this same BVH2: the detail per width, then one table.
    const WideStats w4 = wide_stats<4>(bvh2, spec), w8 = wide_stats<8>(bvh2, spec), w16 = wide_stats<16>(bvh2, spec);
    for (const WideStats* e : {&w4, &w8, &w16}) {
        std::printf("\nbvh%d (%s collapse)\n", e->width, std::string(name(spec.wide.collapse)).c_str());
        std::printf(
            "  build ms        %.1f (collapse + pack; + %.1f for the BVH2)\n  nodes           %zu\n"
            "  leaves          %zu\n  triangle blocks %zu\n  depth           %d\n  SAH cost        %.3f\n"
            "  bytes/triangle  %.1f\n  fill rate       %.1f%%\n",
            e->build_ms, s.build_ms, e->nodes, e->leaves, e->blocks, e->depth, e->sah_cost, e->bytes_per_triangle,
            100.0 * e->fill_rate);
    }
    std::printf("\nwidths (%s collapse of the BVH2 above; bvh2 for comparison)\n",
                std::string(name(spec.wide.collapse)).c_str());
    std::printf("  %-6s %10s %6s %10s %8s %10s %12s\n", "width", "nodes", "depth", "bytes/tri", "fill", "SAH cost",
                "collapse ms");
    std::printf("  %-6s %10zu %6d %10.1f %8s %10.3f %12s\n", "2", s.nodes, s.depth, s.bytes_per_triangle, "-",
                s.sah_cost, "-");
    for (const WideStats* e : {&w4, &w8, &w16})
        std::printf("  %-6d %10zu %6d %10.1f %7.1f%% %10.3f %12.1f\n", e->width, e->nodes, e->depth,
                    e->bytes_per_triangle, 100.0 * e->fill_rate, e->sah_cost, e->build_ms);
    return 0;
}

}  // namespace simdbvh::cli
