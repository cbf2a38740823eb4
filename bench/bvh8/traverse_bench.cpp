// Wide BVH traversal per ISA (scalar reference loops, AVX2, AVX-512): BVH8
// with SAH and greedy collapse, BVH4 and BVH16 (SAH) from the same BVH2.
// rays/s as the rate counter, wide nodes visited per ray; box and triangle
// counters count lanes (N per node, 8 per Tri8 block).
#include <benchmark/benchmark.h>

#include "traversal_fixture.h"

namespace {

using simdbvh::Collapse;
using simdbvh::Isa;
using simdbvh::scene::RayKind;

template <int N>
void run_wide(benchmark::State& st, const simdbvh::BvhN<N>& bvh, Isa isa, Collapse collapse, RayKind kind, bool any) {
    if (!simdbvh::supported(isa)) {
        st.SkipWithError("CPU lacks the ISA");
        return;
    }
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
    st.SetLabel("bvh" + std::to_string(N) + " " + std::string(simdbvh::name(isa)) + " " +
                std::string(simdbvh::name(collapse)) + " " + std::string(simdbvh::scene::name(kind)) +
                (any ? " any" : " closest"));
}

void BM_Bvh8(benchmark::State& st, Isa isa, Collapse collapse, RayKind kind, bool any) {
    const bench::TraversalScene& s = bench::traversal_scene();
    run_wide<8>(st, collapse == Collapse::sah ? s.bvh8 : s.bvh8_greedy, isa, collapse, kind, any);
}
void BM_Bvh4(benchmark::State& st, Isa isa, Collapse collapse, RayKind kind, bool any) {
    run_wide<4>(st, bench::traversal_scene().bvh4, isa, collapse, kind, any);
}
void BM_Bvh16(benchmark::State& st, Isa isa, Collapse collapse, RayKind kind, bool any) {
    run_wide<16>(st, bench::traversal_scene().bvh16, isa, collapse, kind, any);
}

#define SIMDBVH_WIDE_BENCH(fn, isa, collapse)                                                                      \
    BENCHMARK_CAPTURE(fn, isa##_##collapse##_primary_closest, Isa::isa, Collapse::collapse, RayKind::primary, false)    \
        ->Unit(benchmark::kMillisecond);                                                                            \
    BENCHMARK_CAPTURE(fn, isa##_##collapse##_incoherent_closest, Isa::isa, Collapse::collapse, RayKind::incoherent,    \
                      false)                                                                                        \
        ->Unit(benchmark::kMillisecond);                                                                            \
    BENCHMARK_CAPTURE(fn, isa##_##collapse##_diffuse_closest, Isa::isa, Collapse::collapse, RayKind::diffuse, false)    \
        ->Unit(benchmark::kMillisecond);                                                                            \
    BENCHMARK_CAPTURE(fn, isa##_##collapse##_primary_any, Isa::isa, Collapse::collapse, RayKind::primary, true)         \
        ->Unit(benchmark::kMillisecond);                                                                            \
    BENCHMARK_CAPTURE(fn, isa##_##collapse##_incoherent_any, Isa::isa, Collapse::collapse, RayKind::incoherent, true)   \
        ->Unit(benchmark::kMillisecond);                                                                            \
    BENCHMARK_CAPTURE(fn, isa##_##collapse##_diffuse_any, Isa::isa, Collapse::collapse, RayKind::diffuse, true)         \
        ->Unit(benchmark::kMillisecond)

SIMDBVH_WIDE_BENCH(BM_Bvh8, scalar, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh8, avx2, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh8, avx512, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh8, avx2, greedy);
// The same BVH2 collapsed 4 and 16 wide (SAH), beside BM_Bvh8.
SIMDBVH_WIDE_BENCH(BM_Bvh4, scalar, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh4, avx2, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh4, avx512, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh16, scalar, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh16, avx2, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh16, avx512, sah);

}  // namespace
