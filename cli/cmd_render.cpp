// simdbvh render: eye-light picture or node heat map through any method.
#include <iostream>

#include "common.h"
#include "image.h"
#include "methods.h"
#include "outputs.h"
#include "scene_cmds.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/workloads/rays.h"

namespace simdbvh::cli {

namespace {

void render(const Mesh& mesh, Tracer& tracer, int w, int h, bool heat, const std::string& out) {
    const auto rays = workloads::primary_rays(workloads::default_camera(mesh.bounds(), w, h));
    std::vector<Hit> hits(rays.size());
    if (heat) {
        std::vector<std::uint32_t> counts(rays.size());
        for (std::size_t i = 0; i < rays.size(); ++i) {
            TraceStats st;
            tracer.trace(std::span(&rays[i], 1), std::span(&hits[i], 1), false, &st);
            counts[i] = std::uint32_t(st.nodes_visited);
        }
        write_png(out, heat_map(counts, w, h));
    } else {
        tracer.trace(rays, hits, false, nullptr);
        write_png(out, shade_eye_light(mesh, rays, hits, w, h));
    }
}

}  // namespace

int cmd_render(const std::vector<std::string>& args) {
    std::set<std::string> valued{"scene", "out", "width", "height", "instance-bounds"}, flags{"heatmap"};
    add_method_options(valued, flags);
    const Options o("render", args, valued, flags);
    const std::string scene_name = o.require("scene");
    const std::string out = o.require("out");
    MethodSpec spec = parse_method(o);
    if (!o.has("method")) spec.method = "bvh8";
    const int w = int(o.get_int("width", 640, 1, 16384)), h = int(o.get_int("height", 480, 1, 16384));
    const bool heat = o.has("heatmap");
    if (heat && spec.method != "bvh2" && !is_wide(spec.method))
        throw UsageError(
            "--heatmap needs --method bvh2, bvh4, bvh8 or bvh16 (nodes visited are counted by our traversals)");
    check_outputs({{"--out", out}}, {.scenes = {{"--scene", scene_name}}});
    // Per pixel: a ray (32 bytes), a hit (16), a count (4), the picture (3) and its PNG (about 3).
    const std::string size_opt = "--width " + std::to_string(w) + " --height " + std::to_string(h);
    const std::uint64_t bytes = std::uint64_t(w) * std::uint64_t(h) * (32 + 16 + 4 + 3 + 3);
    check_memory(size_opt, bytes);
    if (is_scene_desc(scene_name)) {
        refuse_mesh_options(o, scene_name);
        return render_scene(scene_name, spec, parse_instance_bounds(o), w, h, out);
    }
    if (o.has("instance-bounds")) throw UsageError("--instance-bounds applies to scenes (room, instances-N, *.json)");
    const Mesh mesh = load_scene_with_progress(scene_name);
    auto tracer = make_tracer(mesh, spec);
    try {
        render(mesh, *tracer, w, h, heat, out);
    } catch (const std::bad_alloc&) {
        throw Error(size_opt + ": out of memory (needs about " + format_bytes(bytes) + "); ask for a smaller image");
    }
    std::cout << "method " << spec.label() << "  isa " << tracer->ran_isa(spec, false) << "  wrote " << w << "x" << h
              << " " << (heat ? "heat map" : "render") << " to " << out << "\n";
    return 0;
}

}  // namespace simdbvh::cli
