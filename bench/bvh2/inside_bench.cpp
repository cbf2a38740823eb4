// Exact inside/outside on the BVH2 (issue 15): points/s for query points
// uniform in the scene's bounds grown by 10%, one +z ray per point, one thread.
#include <benchmark/benchmark.h>

#include "simdbvh/bvh2/inside.h"
#include "simdbvh/scene/points.h"
#include "traversal_fixture.h"

namespace {

void BM_Inside(benchmark::State& st) {
    const bench::TraversalScene& s = bench::traversal_scene();
    static const auto pts = simdbvh::scene::random_points(s.mesh.bounds(), 100000, 9);
    std::vector<simdbvh::PointSide> out(pts.size());
    simdbvh::classify_points(s.bvh2, pts, out);  // untimed warm-up
    std::size_t inside = 0;
    for (const auto& p : out) inside += p.side == simdbvh::Side::inside;
    for (auto _ : st) {
        simdbvh::classify_points(s.bvh2, pts, out);
        benchmark::DoNotOptimize(out.data());
    }
    st.counters["points/s"] = benchmark::Counter(double(pts.size()), benchmark::Counter::kIsIterationInvariantRate);
    st.counters["inside"] = double(inside) / double(pts.size());
    st.SetLabel("bvh2 exact inside, uniform in the bounds");
}

BENCHMARK(BM_Inside)->Unit(benchmark::kMillisecond);

}  // namespace
