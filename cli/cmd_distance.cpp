// simdbvh gen-points and distance: query points and their closest points.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <new>

#include "common.h"
#include "point_queries.h"
#include "options.h"
#include "outputs.h"
#include "simdbvh/query/closest_point.h"
#include "simdbvh/query/inside.h"
#include "simdbvh/query/closest_point_wide.h"
#include "simdbvh/query/inside_wide.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/io/output.h"
#include "simdbvh/workloads/points.h"
#include "simdbvh/io/point_files.h"

namespace simdbvh::cli {

namespace {

float parse_max_distance(const Options& o) {
    if (!o.has("max-distance")) return PointQueryOptions{}.max_distance;
    const std::optional<float> v = o.get_float("max-distance");
    if (!v || !(*v >= 0.0f))
        throw UsageError("--max-distance '" + o.get("max-distance") + "': expected a number >= 0 (inf for no limit)");
    return *v;
}

}  // namespace

int cmd_gen_points(const std::vector<std::string>& args) {
    const Options o("gen-points", args, {"scene", "count", "seed", "out"}, {});
    const std::string scene_name = o.require("scene");
    if (!o.has("count")) throw UsageError("'gen-points': missing --count");
    const auto count = std::size_t(o.get_int("count", 0, 1, 1LL << 31));
    const auto seed = std::uint64_t(o.get_int("seed", 1, 0, (1LL << 62)));
    const std::string out = o.require("out");
    check_outputs({{"--out", out}}, {.scenes = {{"--scene", scene_name}}});
    check_memory("--count " + std::to_string(count), std::uint64_t(count) * 24);
    const Mesh mesh = load_scene_with_progress(scene_name);
    if (mesh.size() == 0) throw Error(scene_name + ": has no triangles: no bounds to place query points in");
    const auto points = workloads::random_points(mesh.bounds(), count, seed);
    io::write_file_atomic(out, io::encode_points(points));
    std::cout << "wrote " << count << " points (uniform in the bounds grown by 10% per side, seed " << seed << ") to "
              << out << "\n";
    return 0;
}

int cmd_distance(const std::vector<std::string>& args) {
    const Options o("distance", args, {"scene", "points", "out", "threads", "max-distance", "rule", "ray", "tree"},
                    {"stats", "unsigned"});
    // The tree of the closest point and the sign: the BVH4 by default (the
    // fastest closest point on the dragon in bench/query/closest_point_wide_bench.cpp,
    // within 15% of the fastest inside test); every tree gives the same records.
    const std::string tree = parse_tree(o, "bvh4");
    const std::string scene_name = o.require("scene");
    const std::string points_file = o.require("points");
    const std::string out = o.require("out");
    PointQueryOptions q;
    q.threads = int(o.get_int("threads", 1, 1, 1024));
    q.max_distance = parse_max_distance(o);
    PointQueryStats stats;
    if (o.has("stats")) q.stats = &stats;
    check_outputs({{"--out", out}}, {.files = {{"--points", points_file}}, .scenes = {{"--scene", scene_name}}});
    const auto points = io::read_points(points_file);  // a bad points file fails before the build
    check_memory("--points " + points_file, std::uint64_t(points.size()) * (sizeof(ClosestPoint) + 20));
    InsideOptions io;
    io.threads = q.threads;
    io.rule = parse_rule(o);
    io.ray = parse_ray(o);
    const bool is_signed = !o.has("unsigned");
    const Mesh mesh = load_scene_with_progress(scene_name);
    if (is_signed) report_closure(scene_name, mesh);
    progress("building " + tree + " ...");
    const auto t0 = std::chrono::steady_clock::now();
    const PointTree pt = PointTree::build(mesh, tree);
    const double build_s = seconds_since(t0);
    std::vector<ClosestPoint> results(points.size());
    const auto t1 = std::chrono::steady_clock::now();
    pt.visit([&](const auto& t) { closest_point(t, points, results, q); });
    std::size_t inside = 0;
    if (is_signed) {  // the sign from the exact inside test
        std::vector<PointSide> sides(points.size());
        pt.visit([&](const auto& t) { classify_points(t, points, sides, io); });
        for (std::size_t i = 0; i < points.size(); ++i) {
            if (!results[i].found()) continue;
            if (sides[i].side == Side::surface) results[i].distance = 0.0f;
            if (sides[i].side == Side::inside) {
                results[i].distance = -results[i].distance;
                ++inside;
            }
        }
    }
    const double query_s = seconds_since(t1);
    io::write_file_atomic(out, io::encode_distances(results));
    std::size_t found = 0;
    double sum = 0, worst = 0;
    for (const ClosestPoint& c : results)
        if (c.found()) {
            ++found;
            sum += std::fabs(c.distance);
            worst = std::max(worst, double(std::fabs(c.distance)));
        }
    std::cout << "method " << tree << "  threads " << q.threads << "  max-distance " << q.max_distance << "  "
              << (is_signed ? "signed" : "unsigned") << "\n"
              << "points " << points.size() << "  found " << found << "  inside " << inside << "  mean |distance| "
              << (found ? sum / double(found) : 0.0) << "  max " << worst << "\n"
              << "build " << build_s * 1e3 << " ms  query " << query_s * 1e3 << " ms  "
              << (query_s > 0 ? double(points.size()) / query_s / 1e6 : 0.0) << " Mpoints/s\n";
    if (q.stats) {
        const double n = double(std::max<std::uint64_t>(stats.points, 1));
        std::cout << "per point: nodes " << double(stats.nodes_visited) / n << "  triangle boxes "
                  << double(stats.triangle_tests) / n << "  exact triangle tests " << double(stats.exact_tests) / n
                  << "\n";
    }
    return 0;
}

}  // namespace simdbvh::cli
