// Embree 3 medium (rtcIntersect1 / rtcOccluded1, one ray at a time, the loop
// our batched traversal also runs) on the traversal benchmarks' scene and
// rays, so BM_Bvh8 and BM_Embree rows of one run compare like with like.
// The Embree scene is built once, untimed, with Embree's default thread count;
// each row runs one untimed pass over the rays first (warm-up).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>
#include <vector>

#include "simdbvh/reference/embree.h"
#include "traversal_fixture.h"

namespace {

using simdbvh::workloads::RayKind;

const simdbvh::reference::EmbreeScene& embree_scene() {
    static const simdbvh::reference::EmbreeScene s(bench::traversal_scene().mesh);
    return s;
}

// Embree's modes on one ray set: 0 rtcIntersect1 / rtcOccluded1 per ray, 1
// the stream (rtcIntersect1M / rtcOccluded1M, default flags), 2 the stream
// flagged coherent (RTC_INTERSECT_CONTEXT_FLAG_COHERENT: Embree's hint that the
// stream's rays are coherent), 3 packets of 8 (rtcIntersect8 / rtcOccluded8).
void run_embree(benchmark::State& st, const std::vector<simdbvh::Ray>& rays, const std::string& what, bool any,
                int mode) {
    const auto& scene = embree_scene();
    std::vector<simdbvh::Hit> hits(rays.size());
    std::vector<std::uint8_t> occ(rays.size());
    auto pass = [&] {
        if (mode == 3) any ? scene.occluded_packets8(rays, occ) : scene.intersect_packets8(rays, hits);
        else if (mode > 0)
            any ? scene.occluded_stream(rays, occ, mode == 2) : scene.intersect_stream(rays, hits, mode == 2);
        else if (any) scene.occluded(rays, occ);
        else scene.intersect(rays, hits);
    };
    pass();  // warm-up
    for (auto _ : st) {
        pass();
        benchmark::DoNotOptimize(hits.data());
        benchmark::DoNotOptimize(occ.data());
    }
    st.counters["rays/s"] = benchmark::Counter(double(rays.size()), benchmark::Counter::kIsIterationInvariantRate);
    static const char* kModes[] = {"embree-medium ", "embree-medium-stream ", "embree-medium-stream-coherent ",
                                   "embree-medium-packets8 "};
    st.SetLabel(std::string(kModes[mode]) + what + (any ? " any" : " closest"));
}

void BM_Embree(benchmark::State& st, RayKind kind, bool any, bool stream) {
    run_embree(st, bench::rays_of(kind), std::string(simdbvh::workloads::name(kind)), any, stream ? 1 : 0);
}

// The 1000 x 1000 camera's rays (primary_hd) beside BM_Bvh8Hd, every mode.
void BM_EmbreeHd(benchmark::State& st, bool any, int mode) {
    run_embree(st, bench::traversal_scene().primary_hd, "primary_hd", any, mode);
}
BENCHMARK_CAPTURE(BM_EmbreeHd, medium_closest, false, 0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmbreeHd, stream_closest, false, 1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmbreeHd, stream_coherent_closest, false, 2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmbreeHd, packets8_closest, false, 3)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmbreeHd, medium_any, true, 0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmbreeHd, stream_any, true, 1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmbreeHd, stream_coherent_any, true, 2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmbreeHd, packets8_any, true, 3)->Unit(benchmark::kMillisecond);

// medium_*: rtcIntersect1 / rtcOccluded1 per ray; stream_*: rtcIntersect1M /
// rtcOccluded1M, 256 rays per call (how Open3D calls Embree), where Embree may
// trace coherent rays as packets: the stronger baseline for primary rays.
#define SIMDBVH_EMBREE_BENCH(kind)                                                                                     \
    BENCHMARK_CAPTURE(BM_Embree, medium_##kind##_closest, RayKind::kind, false, false)->Unit(benchmark::kMillisecond); \
    BENCHMARK_CAPTURE(BM_Embree, medium_##kind##_any, RayKind::kind, true, false)->Unit(benchmark::kMillisecond);      \
    BENCHMARK_CAPTURE(BM_Embree, stream_##kind##_closest, RayKind::kind, false, true)->Unit(benchmark::kMillisecond);  \
    BENCHMARK_CAPTURE(BM_Embree, stream_##kind##_any, RayKind::kind, true, true)->Unit(benchmark::kMillisecond)

SIMDBVH_EMBREE_BENCH(primary);
SIMDBVH_EMBREE_BENCH(incoherent);
SIMDBVH_EMBREE_BENCH(diffuse);
SIMDBVH_EMBREE_BENCH(diffuse_shuffled);
SIMDBVH_EMBREE_BENCH(shadow);
SIMDBVH_EMBREE_BENCH(area_shadow);
SIMDBVH_EMBREE_BENCH(ao);
SIMDBVH_EMBREE_BENCH(lidar);

}  // namespace
