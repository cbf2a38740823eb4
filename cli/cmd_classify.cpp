// SPDX-License-Identifier: MIT
// simdbvh classify: any method's closest hits (a hit file, e.g. another
// library's answers written in simdbvh's format) classified ray by ray against
// the double-precision reference, with the labels of `simdbvh accuracy`.
#include <cstdint>
#include <iostream>
#include <mutex>

#include "common.h"
#include "options.h"
#include "outputs.h"
#include "report.h"
#include "simdbvh/reference/classify.h"
#include "simdbvh/reference/reference.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/platform/parallel.h"
#include "simdbvh/io/ray_files.h"

namespace simdbvh::cli {

namespace {
// The reference is O(triangles) per ray: refuse what would take hours.
constexpr double kMaxRayTriangles = 2e10;
}  // namespace

int cmd_classify(const std::vector<std::string>& args) {
    const Options o("classify", args, {"scene", "rays", "hits", "threads", "json"}, {});
    const std::string scene_name = o.require("scene");
    const std::string rays_file = o.require("rays");
    const std::string hits_file = o.require("hits");
    const int threads = int(o.get_int("threads", 1, 1, 1024));
    const std::string json = o.get("json", "");
    if (!json.empty())
        check_outputs({{"--json", json}},
                      {.files = {{"--rays", rays_file}, {"--hits", hits_file}}, .scenes = {{"--scene", scene_name}}});
    const std::vector<Ray> rays = io::read_rays(rays_file);
    const std::vector<Hit> hits = io::read_hits(hits_file);
    if (hits.size() != rays.size())
        throw Error(hits_file + ": " + std::to_string(hits.size()) + " hits for " + std::to_string(rays.size()) +
                    " rays in " + rays_file);
    const Mesh mesh = load_scene_with_progress(scene_name);
    for (std::size_t i = 0; i < hits.size(); ++i)
        if (hits[i].hit() && hits[i].prim >= mesh.size())
            throw Error(hits_file + ": hit " + std::to_string(i) + " names triangle " + std::to_string(hits[i].prim) +
                        " of " + std::to_string(mesh.size()) + " in " + scene_name);
    if (double(rays.size()) * double(mesh.size()) > kMaxRayTriangles)
        throw Error("classify: " + std::to_string(rays.size()) + " rays x " + std::to_string(mesh.size()) +
                    " triangles is too much for the O(triangles) reference (at most 2e10); sample the rays");
    reference::Tally total;
    std::mutex m;
    ParallelOptions po;
    po.grain = 256;
    parallel_for(
        rays.size(), threads,
        [&](std::size_t b, std::size_t e) {
            reference::Tally t;
            for (std::size_t i = b; i < e; ++i)
                t.add(reference::classify(reference::reference_intersect(mesh, rays[i]), hits[i]));
            const std::lock_guard<std::mutex> lock(m);
            total += t;
        },
        po);
    std::cout << "rays " << rays.size() << "  triangles " << mesh.size() << "\n" << reference::to_string(total) << "\n";
    if (!json.empty()) {
        Report r;
        r.json["command"] = command_line("classify", args);
        r.json["scene"] = scene_name;
        r.json["rays"] = rays.size();
        r.json["triangles"] = mesh.size();
        r.json["agree"] = total.agree;
        r.json["tie"] = total.tie;
        r.json["leak"] = total.leak;
        r.json["false_hit"] = total.false_hit;
        r.json["wrong_triangle"] = total.wrong_triangle;
        r.json["t_error"] = total.t_error;
        r.json["marginal"] = total.marginal;
        r.json["invalid_rays"] = total.invalid_rays;
        r.save_json(json);
    }
    return 0;
}

}  // namespace simdbvh::cli
