#pragma once
// Shared by bench/query/closest_point_bench.cpp and bench/query/closest_point_wide_bench.cpp:
// the two query point sets on the traversal scene (uniform in the bounds grown
// by 10%: far from the surface the pruning ball is large; 1e-4 of the
// diagonal off the surface: near a triangle), and the timed loop with its
// counters, for any tree with a batched closest_point overload.
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

#include "simdbvh/query/closest_point.h"
#include "simdbvh/query/closest_point_wide.h"
#include "simdbvh/workloads/points.h"
#include "traversal_fixture.h"

namespace bench {

inline const std::vector<simdbvh::Vec3>& closest_point_queries(bool near) {
    static const auto make = [](bool n) {
        const TraversalScene& s = traversal_scene();
        const std::size_t count = 20000;
        if (!n) return simdbvh::workloads::random_points(s.mesh.bounds(), count, 9);
        // Vertices pushed off the surface along pseudo-random directions.
        std::vector<simdbvh::Vec3> pts(count);
        const simdbvh::Vec3 e = s.mesh.bounds().extent();
        const float off = 1e-4f * std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
        const auto dirs = simdbvh::workloads::random_points(simdbvh::Aabb{{-1, -1, -1}, {1, 1, 1}}, count, 10, 0.0f);
        for (std::size_t i = 0; i < count; ++i)
            pts[i] = s.mesh.positions[(i * 2654435761u) % s.mesh.positions.size()] + dirs[i] * off;
        return pts;
    };
    static const std::vector<simdbvh::Vec3> far = make(false), close = make(true);
    return near ? close : far;
}

// One thread, Morton order (the batched entry); an untimed warm-up collects
// the counters: nodes visited, triangle bounds and exact (double) tests per point.
template <class Tree>
void run_closest_point(benchmark::State& st, const Tree& tree, const std::string& tree_name, bool near) {
    const auto& pts = closest_point_queries(near);
    std::vector<simdbvh::ClosestPoint> out(pts.size());
    simdbvh::PointQueryStats qs;
    simdbvh::PointQueryOptions counted;
    counted.stats = &qs;
    simdbvh::closest_point(tree, pts, out, counted);
    for (auto _ : st) {
        simdbvh::closest_point(tree, pts, out);
        benchmark::DoNotOptimize(out.data());
    }
    const double n = double(pts.size());
    st.counters["points/s"] = benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate);
    st.counters["nodes/point"] = double(qs.nodes_visited) / n;
    st.counters["tri_bounds/point"] = double(qs.triangle_tests) / n;
    st.counters["exact/point"] = double(qs.exact_tests) / n;
    st.SetLabel(tree_name + " closest point, " + (near ? "near the surface" : "uniform in the bounds"));
}

}  // namespace bench
