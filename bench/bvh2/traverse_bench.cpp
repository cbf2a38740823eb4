// BVH2 traversal (scalar), the baseline the BVH8 rows are compared with:
// rays/s as the rate counter, nodes visited per ray.
#include <benchmark/benchmark.h>

#include "traversal_fixture.h"

namespace {

using simdbvh::workloads::RayKind;

void BM_Bvh2(benchmark::State& st, RayKind kind, bool any) {
    const bench::TraversalScene& s = bench::traversal_scene();
    const auto& rays = bench::rays_of(kind);
    std::vector<simdbvh::Hit> hits(rays.size());
    simdbvh::TraceStats ts;
    simdbvh::TraceOptions counted;
    counted.stats = &ts;
    if (any) simdbvh::occluded(s.bvh2, rays, hits, counted);
    else simdbvh::intersect(s.bvh2, rays, hits, counted);
    for (auto _ : st) {
        if (any) simdbvh::occluded(s.bvh2, rays, hits);
        else simdbvh::intersect(s.bvh2, rays, hits);
        benchmark::DoNotOptimize(hits.data());
    }
    const double n = double(rays.size());
    st.counters["rays/s"] = benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate);
    st.counters["nodes/ray"] = double(ts.nodes_visited) / n;
    st.counters["boxes/ray"] = double(ts.box_tests) / n;
    st.counters["tris/ray"] = double(ts.triangle_tests) / n;
    st.SetLabel("bvh2 scalar " + std::string(simdbvh::workloads::name(kind)) + (any ? " any" : " closest"));
}

BENCHMARK_CAPTURE(BM_Bvh2, scalar_primary_closest, RayKind::primary, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Bvh2, scalar_incoherent_closest, RayKind::incoherent, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Bvh2, scalar_diffuse_closest, RayKind::diffuse, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Bvh2, scalar_primary_any, RayKind::primary, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Bvh2, scalar_incoherent_any, RayKind::incoherent, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Bvh2, scalar_diffuse_any, RayKind::diffuse, true)->Unit(benchmark::kMillisecond);

}  // namespace
