// Closest point queries on the wide trees (issue 15): points/s on BVH4/8/16
// for the same two point sets as bench/bvh2/closest_point_bench.cpp (uniform in
// the bounds grown by 10%, and 1e-4 of the diagonal off the surface), one
// thread, Morton order; counters: nodes visited, triangle lower bounds and
// exact (double) triangle tests per point.
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

#include "simdbvh/bvh8/closest_point.h"
#include "simdbvh/scene/points.h"
#include "traversal_fixture.h"

namespace {

const std::vector<simdbvh::Vec3>& wide_query_points(bool near) {
    static const auto make = [](bool n) {
        const bench::TraversalScene& s = bench::traversal_scene();
        const std::size_t count = 20000;
        if (!n) return simdbvh::scene::random_points(s.mesh.bounds(), count, 9);
        std::vector<simdbvh::Vec3> pts(count);
        const simdbvh::Vec3 e = s.mesh.bounds().extent();
        const float off = 1e-4f * std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
        const auto dirs = simdbvh::scene::random_points(simdbvh::Aabb{{-1, -1, -1}, {1, 1, 1}}, count, 10, 0.0f);
        for (std::size_t i = 0; i < count; ++i)
            pts[i] = s.mesh.positions[(i * 2654435761u) % s.mesh.positions.size()] + dirs[i] * off;
        return pts;
    };
    static const std::vector<simdbvh::Vec3> far = make(false), close = make(true);
    return near ? close : far;
}

template <class Tree>
void run(benchmark::State& st, const Tree& tree, int width, bool near) {
    const auto& pts = wide_query_points(near);
    std::vector<simdbvh::ClosestPoint> out(pts.size());
    simdbvh::PointQueryStats qs;
    simdbvh::PointQueryOptions counted;
    counted.stats = &qs;
    simdbvh::closest_point(tree, pts, out, counted);  // untimed warm-up with counters
    for (auto _ : st) {
        simdbvh::closest_point(tree, pts, out);
        benchmark::DoNotOptimize(out.data());
    }
    const double n = double(pts.size());
    st.counters["points/s"] = benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate);
    st.counters["nodes/point"] = double(qs.nodes_visited) / n;
    st.counters["tri_bounds/point"] = double(qs.triangle_tests) / n;
    st.counters["exact/point"] = double(qs.exact_tests) / n;
    st.SetLabel("bvh" + std::to_string(width) + " closest point, " +
                (near ? "near the surface" : "uniform in the bounds"));
}

void BM_WideClosestPoint(benchmark::State& st, int width, bool near) {
    const bench::TraversalScene& s = bench::traversal_scene();
    if (width == 4) return run(st, s.bvh4, 4, near);
    if (width == 16) return run(st, s.bvh16, 16, near);
    run(st, s.bvh8, 8, near);
}

BENCHMARK_CAPTURE(BM_WideClosestPoint, bvh4_uniform, 4, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WideClosestPoint, bvh8_uniform, 8, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WideClosestPoint, bvh16_uniform, 16, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WideClosestPoint, bvh8_near_surface, 8, true)->Unit(benchmark::kMillisecond);

}  // namespace
