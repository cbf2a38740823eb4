// simdbvh inside: exact inside/outside of query points (one +z ray per point).
#include <chrono>
#include <iostream>

#include "common.h"
#include "point_queries.h"
#include "options.h"
#include "outputs.h"
#include "simdbvh/query/inside.h"
#include "simdbvh/query/inside_wide.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/io/output.h"
#include "simdbvh/io/point_files.h"

namespace simdbvh::cli {

int cmd_inside(const std::vector<std::string>& args) {
    const Options o("inside", args, {"scene", "points", "out", "threads", "rule", "ray", "tree"}, {});
    const std::string scene_name = o.require("scene");
    const std::string points_file = o.require("points");
    const std::string out = o.require("out");
    // The BVH8 by default (with the BVH16 the fastest in
    // bench/query/inside_wide_bench.cpp); every tree gives the same bytes.
    const std::string tree = parse_tree(o, "bvh8");
    InsideOptions io;
    io.threads = int(o.get_int("threads", 1, 1, 1024));
    io.rule = parse_rule(o);
    io.ray = parse_ray(o);
    check_outputs({{"--out", out}}, {.files = {{"--points", points_file}}, .scenes = {{"--scene", scene_name}}});
    const auto points = io::read_points(points_file);
    check_memory("--points " + points_file, std::uint64_t(points.size()) * (sizeof(PointSide) + 1));
    const Mesh mesh = load_scene_with_progress(scene_name);
    report_closure(scene_name, mesh);
    progress("building " + tree + " ...");
    const auto t0 = std::chrono::steady_clock::now();
    const PointTree pt = PointTree::build(mesh, tree);
    const double build_s = seconds_since(t0);
    std::vector<PointSide> sides(points.size());
    const auto t1 = std::chrono::steady_clock::now();
    pt.visit([&](const auto& t) { classify_points(t, points, sides, io); });
    const double query_s = seconds_since(t1);
    io::write_file_atomic(out, io::encode_sides(sides));
    std::size_t count[3] = {0, 0, 0};
    for (const PointSide& s : sides) count[int(s.side)]++;
    std::cout << "method " << tree << "  threads " << io.threads << "  rule " << o.get("rule", "winding") << "  ray "
              << o.get("ray", "shortest") << "\n"
              << "points " << points.size() << "  inside " << count[1] << "  outside " << count[0] << "  surface "
              << count[2] << "\n"
              << "build " << build_s * 1e3 << " ms  query " << query_s * 1e3 << " ms  "
              << (query_s > 0 ? double(points.size()) / query_s / 1e6 : 0.0) << " Mpoints/s\n";
    return 0;
}

}  // namespace simdbvh::cli
