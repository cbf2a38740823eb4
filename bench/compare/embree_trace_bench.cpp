// Embree 3 medium (rtcIntersect1 / rtcOccluded1, one ray at a time, the loop
// our batched traversal also runs) on the traversal benchmarks' scene and
// rays, so BM_Bvh8 and BM_Embree rows of one run compare like with like.
// The Embree scene is built once, untimed, with Embree's default thread count;
// each row runs one untimed pass over the rays first (warm-up).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "simdbvh/compare/embree.h"
#include "traversal_fixture.h"

namespace {

using simdbvh::scene::RayKind;

const simdbvh::compare::EmbreeScene& embree_scene() {
    static const simdbvh::compare::EmbreeScene s(bench::traversal_scene().mesh);
    return s;
}

void BM_Embree(benchmark::State& st, RayKind kind, bool any, bool stream) {
    const auto& scene = embree_scene();
    const auto& rays = bench::rays_of(kind);
    std::vector<simdbvh::Hit> hits(rays.size());
    std::vector<std::uint8_t> occ(rays.size());
    auto pass = [&] {
        if (stream) any ? scene.occluded_stream(rays, occ) : scene.intersect_stream(rays, hits);
        else if (any) scene.occluded(rays, occ);
        else scene.intersect(rays, hits);
    };
    pass();  // warm-up
    for (auto _ : st) {
        pass();
        benchmark::DoNotOptimize(hits.data());
        benchmark::DoNotOptimize(occ.data());
    }
    st.counters["rays/s"] =
        benchmark::Counter(double(rays.size()), benchmark::Counter::kIsIterationInvariantRate);
    st.SetLabel(std::string(stream ? "embree-medium-stream " : "embree-medium ") +
                std::string(simdbvh::scene::name(kind)) + (any ? " any" : " closest"));
}

// medium_*: rtcIntersect1 / rtcOccluded1 per ray; stream_*: rtcIntersect1M /
// rtcOccluded1M, 256 rays per call (how Open3D calls Embree), where Embree may
// trace coherent rays as packets: the stronger baseline for primary rays.
#define SIMDBVH_EMBREE_BENCH(kind)                                                                                      \
    BENCHMARK_CAPTURE(BM_Embree, medium_##kind##_closest, RayKind::kind, false, false)->Unit(benchmark::kMillisecond); \
    BENCHMARK_CAPTURE(BM_Embree, medium_##kind##_any, RayKind::kind, true, false)->Unit(benchmark::kMillisecond);      \
    BENCHMARK_CAPTURE(BM_Embree, stream_##kind##_closest, RayKind::kind, false, true)->Unit(benchmark::kMillisecond);  \
    BENCHMARK_CAPTURE(BM_Embree, stream_##kind##_any, RayKind::kind, true, true)->Unit(benchmark::kMillisecond)

SIMDBVH_EMBREE_BENCH(primary);
SIMDBVH_EMBREE_BENCH(incoherent);
SIMDBVH_EMBREE_BENCH(diffuse);

}  // namespace
