// Closest point queries on the BVH2 (issue 15): points/s for query points
// uniform in the scene's bounds grown by 10% (the hard case: far from the
// surface the pruning ball is large) and points 1e-4 of the bounds' diagonal
// off the surface (the easy case: near a triangle), one thread, Morton order.
#include <benchmark/benchmark.h>

#include <cmath>

#include "simdbvh/bvh2/closest_point.h"
#include "simdbvh/scene/points.h"
#include "traversal_fixture.h"

namespace {

const std::vector<simdbvh::Vec3>& query_points(bool near) {
    static const auto make = [](bool n) {
        const bench::TraversalScene& s = bench::traversal_scene();
        const std::size_t count = 20000;
        if (!n) return simdbvh::scene::random_points(s.mesh.bounds(), count, 9);
        // Vertices pushed off the surface along pseudo-random directions.
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

void BM_ClosestPoint(benchmark::State& st, bool near) {
    const bench::TraversalScene& s = bench::traversal_scene();
    const auto& pts = query_points(near);
    std::vector<simdbvh::ClosestPoint> out(pts.size());
    simdbvh::PointQueryStats qs;
    simdbvh::PointQueryOptions counted;
    counted.stats = &qs;
    simdbvh::closest_point(s.bvh2, pts, out, counted);  // untimed warm-up with counters
    for (auto _ : st) {
        simdbvh::closest_point(s.bvh2, pts, out);
        benchmark::DoNotOptimize(out.data());
    }
    const double n = double(pts.size());
    st.counters["points/s"] = benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate);
    st.counters["nodes/point"] = double(qs.nodes_visited) / n;
    st.counters["exact/point"] = double(qs.exact_tests) / n;
    st.SetLabel(std::string("bvh2 closest point, ") + (near ? "near the surface" : "uniform in the bounds"));
}

BENCHMARK_CAPTURE(BM_ClosestPoint, bvh2_uniform, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ClosestPoint, bvh2_near_surface, true)->Unit(benchmark::kMillisecond);

}  // namespace
