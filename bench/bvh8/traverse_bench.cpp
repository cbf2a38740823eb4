// BVH8 traversal per ISA (scalar reference loops, AVX2, AVX-512), SAH and
// greedy collapse: rays/s as the rate counter, Node8s visited per ray.
// Box and triangle counters count SIMD lanes (8 per Node8, 8 per Tri8 block).
#include <benchmark/benchmark.h>

#include "traversal_fixture.h"

namespace {

using simdbvh::Collapse;
using simdbvh::Isa;
using simdbvh::scene::RayKind;

void BM_Bvh8(benchmark::State& st, Isa isa, Collapse collapse, RayKind kind, bool any) {
    if (!simdbvh::supported(isa)) {
        st.SkipWithError("CPU lacks the ISA");
        return;
    }
    const bench::TraversalScene& s = bench::traversal_scene();
    const simdbvh::Bvh8& bvh = collapse == Collapse::sah ? s.bvh8 : s.bvh8_greedy;
    const auto& rays = bench::rays_of(kind);
    std::vector<simdbvh::Hit> hits(rays.size());
    simdbvh::TraceStats ts;
    simdbvh::TraceOptions counted;
    counted.stats = &ts;
    if (any) simdbvh::occluded(bvh, rays, hits, counted, isa);
    else simdbvh::intersect(bvh, rays, hits, counted, isa);
    for (auto _ : st) {
        if (any) simdbvh::occluded(bvh, rays, hits, {}, isa);
        else simdbvh::intersect(bvh, rays, hits, {}, isa);
        benchmark::DoNotOptimize(hits.data());
    }
    const double n = double(rays.size());
    st.counters["rays/s"] = benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate);
    st.counters["nodes/ray"] = double(ts.nodes_visited) / n;
    st.counters["boxes/ray"] = double(ts.box_tests) / n;
    st.counters["tris/ray"] = double(ts.triangle_tests) / n;
    st.SetLabel("bvh8 " + std::string(simdbvh::name(isa)) + " " + std::string(simdbvh::name(collapse)) + " " +
                std::string(simdbvh::scene::name(kind)) + (any ? " any" : " closest"));
}

#define SIMDBVH_BVH8_BENCH(isa, collapse)                                                                        \
    BENCHMARK_CAPTURE(BM_Bvh8, isa##_##collapse##_primary_closest, Isa::isa, Collapse::collapse, RayKind::primary, false) \
        ->Unit(benchmark::kMillisecond);                                                                         \
    BENCHMARK_CAPTURE(BM_Bvh8, isa##_##collapse##_incoherent_closest, Isa::isa, Collapse::collapse, RayKind::incoherent, \
                      false)                                                                                     \
        ->Unit(benchmark::kMillisecond);                                                                         \
    BENCHMARK_CAPTURE(BM_Bvh8, isa##_##collapse##_diffuse_closest, Isa::isa, Collapse::collapse, RayKind::diffuse, false) \
        ->Unit(benchmark::kMillisecond);                                                                         \
    BENCHMARK_CAPTURE(BM_Bvh8, isa##_##collapse##_primary_any, Isa::isa, Collapse::collapse, RayKind::primary, true)    \
        ->Unit(benchmark::kMillisecond);                                                                         \
    BENCHMARK_CAPTURE(BM_Bvh8, isa##_##collapse##_incoherent_any, Isa::isa, Collapse::collapse, RayKind::incoherent, true) \
        ->Unit(benchmark::kMillisecond);                                                                         \
    BENCHMARK_CAPTURE(BM_Bvh8, isa##_##collapse##_diffuse_any, Isa::isa, Collapse::collapse, RayKind::diffuse, true)    \
        ->Unit(benchmark::kMillisecond)

SIMDBVH_BVH8_BENCH(scalar, sah);
SIMDBVH_BVH8_BENCH(avx2, sah);
SIMDBVH_BVH8_BENCH(avx512, sah);
SIMDBVH_BVH8_BENCH(avx2, greedy);

}  // namespace
