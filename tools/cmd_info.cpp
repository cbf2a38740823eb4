// simdbvh info: the scene and both trees.
#include <cstdio>
#include <iostream>

#include "common.h"
#include "methods.h"

namespace simdbvh::cli {

int cmd_info(const std::vector<std::string>& args) {
    std::set<std::string> valued{"scene"}, flags;
    add_method_options(valued, flags);
    const Options o("info", args, valued, flags);
    const std::string scene_name = o.require("scene");
    const MethodSpec spec = parse_method(o);
    const Mesh mesh = load_scene_with_progress(scene_name);
    const Aabb b = mesh.bounds();
    std::printf("scene        %s\n", scene_name.c_str());
    std::printf("triangles    %zu\n", mesh.size());
    std::printf("vertices     %zu\n", mesh.positions.size());
    std::printf("bounds       [%g %g %g] - [%g %g %g]\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
    std::printf("isa          %s\n", std::string(name(spec.isa)).c_str());
    progress("building BVH2 ...");
    const Bvh2 bvh2 = Bvh2::build(mesh, spec.build);
    const BuildStats& s = bvh2.stats();
    std::printf("\nbvh2 (%s, %d bins, %d thread%s)\n", std::string(name(spec.build.builder)).c_str(), spec.build.bins,
                spec.build.threads, spec.build.threads == 1 ? "" : "s");
    std::printf("  build ms        %.1f\n  nodes           %zu\n  leaves          %zu\n  depth           %d\n"
                "  SAH cost        %.3f\n  bytes/triangle  %.1f\n",
                s.build_ms, s.nodes, s.leaves, s.depth, s.sah_cost, s.bytes_per_triangle);
    progress("collapsing to BVH8 ...");
    const Bvh8 bvh8 = Bvh8::build(bvh2, spec.bvh8);
    const Bvh8Stats& e = bvh8.stats();
    std::printf("\nbvh8 (%s collapse)\n", std::string(name(spec.bvh8.collapse)).c_str());
    std::printf("  build ms        %.1f (collapse + pack; + %.1f for the BVH2)\n  nodes           %zu\n"
                "  leaves          %zu\n  triangle blocks %zu\n  depth           %d\n  SAH cost        %.3f\n"
                "  bytes/triangle  %.1f\n  fill rate       %.1f%%\n",
                e.build_ms, s.build_ms, e.nodes, e.leaves, e.blocks, e.depth, e.sah_cost, e.bytes_per_triangle,
                100.0 * e.fill_rate);
    return 0;
}

}  // namespace simdbvh::cli
