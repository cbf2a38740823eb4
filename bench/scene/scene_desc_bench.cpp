// A scene description (SIMDBVH_BENCH_SCENE: a built-in name or a JSON file;
// default spheres-1000) traced by our two-level scene (child-corner instance
// bounds; BVH8 bottom levels per ISA, and BVH4 and BVH16 rows: the width a
// scene's shape trees pay most for) and by Embree's instanced scene
// (compare/embree_instances.h) on the same rays, one thread: closest and any
// hit, per ISA. Rays: SIMDBVH_BENCH_RAYS (default 100000) interior rays
// (workloads::interior_rays over the world bounds, seed 9: the rays of simdbvh
// bench --scene) and its camera's primary rays (workloads::scene_camera_rays).
// Run with --benchmark_enable_random_interleaving=true and repetitions, so
// ours and Embree's rows alternate.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "simdbvh/reference/embree_instances.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scene_desc.h"

namespace {

using namespace simdbvh;

struct Fixture {
    std::string name;
    SceneDesc desc;
    SceneBvhN<4> scene4;
    SceneBvhN<8> scene;
    SceneBvhN<16> scene16;
    std::unique_ptr<reference::EmbreeInstanceScene> embree;
    std::vector<Ray> rays[2];  // primary, interior
};

const Fixture& fixture() {
    static const Fixture f = [] {
        Fixture x;
        const char* env = std::getenv("SIMDBVH_BENCH_SCENE");
        x.name = env && *env ? env : "spheres-1000";
        x.desc = workloads::load_scene_desc(x.name);
        x.scene4 = SceneBvhN<4>::build(x.desc);
        x.scene = SceneBvhN<8>::build(x.desc);
        x.scene16 = SceneBvhN<16>::build(x.desc);
        x.embree = std::make_unique<reference::EmbreeInstanceScene>(x.desc);
        const char* n = std::getenv("SIMDBVH_BENCH_RAYS");
        const std::size_t count = n && *n ? std::strtoull(n, nullptr, 10) : 100000;
        x.rays[0] = workloads::scene_camera_rays(x.desc, count);
        x.rays[1] = workloads::interior_rays(world_bounds(x.desc), count, 9);
        return x;
    }();
    return f;
}

void rate(benchmark::State& st, std::size_t rays) {
    st.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsIterationInvariantRate);
}

template <int N>
const SceneBvhN<N>& scene_of(const Fixture& f) {
    if constexpr (N == 4) return f.scene4;
    else if constexpr (N == 8) return f.scene;
    else return f.scene16;
}

template <int N>
void trace_rows(benchmark::State& st, Isa isa, int kind, bool any) {
    if (!supported(isa)) return st.SkipWithError("CPU lacks ISA");
    const Fixture& f = fixture();
    const SceneBvhN<N>& scene = scene_of<N>(f);
    std::vector<SceneHit> hits(f.rays[kind].size());
    const std::span<const Ray> rays(f.rays[kind]);
    for (auto _ : st) {
        if (any) occluded(scene, rays, std::span<SceneHit>(hits), {.isa = isa});
        else intersect(scene, rays, std::span<SceneHit>(hits), {.isa = isa});
    }
    rate(st, hits.size());
}
void BM_Ours(benchmark::State& st, Isa isa, int kind, bool any) { trace_rows<8>(st, isa, kind, any); }
void BM_Bvh4(benchmark::State& st, Isa isa, int kind, bool any) { trace_rows<4>(st, isa, kind, any); }
void BM_Bvh16(benchmark::State& st, Isa isa, int kind, bool any) { trace_rows<16>(st, isa, kind, any); }

void BM_Embree(benchmark::State& st, int kind, bool any) {
    const Fixture& f = fixture();
    std::vector<SceneHit> hits(f.rays[kind].size());
    for (auto _ : st) {
        if (any) f.embree->occluded(f.rays[kind], hits);
        else f.embree->intersect(f.rays[kind], hits);
    }
    rate(st, hits.size());
}

}  // namespace

// BM_Ours/<isa>_<kind>_<query> is the BVH8 (the rows of earlier notes);
// BM_Bvh4 and BM_Bvh16 the other widths.
#define SIMDBVH_SCENE_QUERY(kind_name, kind, q, any)                                                              \
    BENCHMARK_CAPTURE(BM_Ours, avx2_##kind_name##_##q, Isa::avx2, kind, any)->Unit(benchmark::kMillisecond);      \
    BENCHMARK_CAPTURE(BM_Ours, avx512_##kind_name##_##q, Isa::avx512, kind, any)->Unit(benchmark::kMillisecond);  \
    BENCHMARK_CAPTURE(BM_Bvh4, avx2_##kind_name##_##q, Isa::avx2, kind, any)->Unit(benchmark::kMillisecond);      \
    BENCHMARK_CAPTURE(BM_Bvh16, avx512_##kind_name##_##q, Isa::avx512, kind, any)->Unit(benchmark::kMillisecond); \
    BENCHMARK_CAPTURE(BM_Embree, kind_name##_##q, kind, any)->Unit(benchmark::kMillisecond);
#define SIMDBVH_SCENE_ROWS(kind_name, kind)              \
    SIMDBVH_SCENE_QUERY(kind_name, kind, closest, false) \
    SIMDBVH_SCENE_QUERY(kind_name, kind, any, true)
SIMDBVH_SCENE_ROWS(primary, 0)
SIMDBVH_SCENE_ROWS(interior, 1)

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    try {
        fixture();
    } catch (const Error& e) {  // an unknown scene, a bad JSON file: say so, exit 2
        std::fprintf(stderr, "simdbvh_bench_scene_desc: %s\n", e.what());
        return 2;
    }
    const Fixture& f = fixture();
    benchmark::AddCustomContext("scene", f.name);
    benchmark::AddCustomContext("rays_per_kind", std::to_string(f.rays[1].size()));
    benchmark::AddCustomContext("active_isa", std::string(name(active_isa())));
    benchmark::AddCustomContext("scene_bytes", std::to_string(f.scene.stats().bytes));
    benchmark::AddCustomContext("embree_bytes", std::to_string(f.embree->bytes()));
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
