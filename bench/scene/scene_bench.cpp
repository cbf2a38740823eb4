// Instanced scene (N copies of the dragon, one bottom-level BVH8, a top-level
// BVH2 over the instances) against the same instances flattened into one
// world-space mesh and one BVH8, on the same rays, one thread, per ISA.
// Context: the bytes of each, and of instances-1000 against one dragon.
// SIMDBVH_BENCH_SCENE (default dragon), SIMDBVH_BENCH_INSTANCES (default 16),
// SIMDBVH_BENCH_RAYS (default 100000 per kind).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "simdbvh/reference/embree.h"
#include "simdbvh/reference/embree_instances.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scene_desc.h"
#include "simdbvh/workloads/scenes.h"

namespace {

using namespace simdbvh;

std::size_t env_size(const char* var, std::size_t fallback) {
    const char* v = std::getenv(var);
    return v && *v ? std::strtoull(v, nullptr, 10) : fallback;
}

Mesh flatten(const SceneDesc& d) {
    Mesh flat;
    for (const Instance& in : d.instances) {
        const Mesh& m = std::get<Mesh>(d.geometries[in.geometry]);
        const auto base = std::uint32_t(flat.positions.size());
        for (const Vec3& p : m.positions) flat.positions.push_back(transform_point(in.transform, p));
        for (const Triangle& t : m.triangles) flat.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    return flat;
}

std::size_t wide_bytes(const Bvh8& b) {
    return b.nodes().size() * sizeof(Bvh8::Node) + b.blocks().size() * sizeof(Tri8);
}

struct Fixture {
    std::string name;
    std::size_t n = 0;
    SceneDesc desc;
    SceneBvhN<8> corners, child_corners;
    Bvh8 flat;
    std::unique_ptr<reference::EmbreeInstanceScene> embree_instanced;
    std::unique_ptr<reference::EmbreeScene> embree_flat;
    std::size_t flat_triangles = 0;
    std::vector<Ray> rays[2];  // primary, incoherent (generated on the flattened mesh)
};

const Fixture& fixture() {
    static const Fixture f = [] {
        Fixture x;
        const char* env = std::getenv("SIMDBVH_BENCH_SCENE");
        x.name = env && *env ? env : "dragon";
        x.n = env_size("SIMDBVH_BENCH_INSTANCES", 16);
        x.desc = workloads::instances_scene(workloads::load_scene(x.name), x.n);
        SceneOptions o;
        o.bounds = InstanceBounds::corners;
        x.corners = SceneBvhN<8>::build(x.desc, o);
        o.bounds = InstanceBounds::child_corners;
        x.child_corners = SceneBvhN<8>::build(x.desc, o);
        const Mesh flat = flatten(x.desc);
        x.flat_triangles = flat.size();
        x.flat = Bvh8::build(flat);
        x.embree_instanced = std::make_unique<reference::EmbreeInstanceScene>(x.desc);
        x.embree_flat = std::make_unique<reference::EmbreeScene>(flat);
        const std::size_t count = env_size("SIMDBVH_BENCH_RAYS", 100000);
        x.rays[0] = workloads::generate_rays(flat, workloads::RayKind::primary, count, 1);
        x.rays[1] = workloads::generate_rays(flat, workloads::RayKind::incoherent, count, 1);
        return x;
    }();
    return f;
}

void rate(benchmark::State& st, std::size_t rays) {
    st.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Flattened(benchmark::State& st, Isa isa, int kind) {
    if (!supported(isa)) return st.SkipWithError("CPU lacks ISA");
    const Fixture& f = fixture();
    std::vector<Hit> hits(f.rays[kind].size());
    for (auto _ : st) intersect(f.flat, f.rays[kind], hits, with_isa(TraceOptions{}, isa));
    rate(st, hits.size());
}

void BM_Instanced(benchmark::State& st, Isa isa, int kind, InstanceBounds bounds) {
    if (!supported(isa)) return st.SkipWithError("CPU lacks ISA");
    const Fixture& f = fixture();
    const SceneBvhN<8>& s = bounds == InstanceBounds::corners ? f.corners : f.child_corners;
    std::vector<SceneHit> hits(f.rays[kind].size());
    for (auto _ : st) intersect(s, std::span<const Ray>(f.rays[kind]), std::span<SceneHit>(hits), {.isa = isa});
    rate(st, hits.size());
}

void BM_EmbreeInstanced(benchmark::State& st, int kind) {
    const Fixture& f = fixture();
    std::vector<SceneHit> hits(f.rays[kind].size());
    for (auto _ : st) f.embree_instanced->intersect(f.rays[kind], hits);
    rate(st, hits.size());
}

void BM_EmbreeFlattened(benchmark::State& st, int kind) {
    const Fixture& f = fixture();
    std::vector<Hit> hits(f.rays[kind].size());
    for (auto _ : st) f.embree_flat->intersect(f.rays[kind], hits);
    rate(st, hits.size());
}

constexpr auto kCorners = InstanceBounds::corners, kChild = InstanceBounds::child_corners;

}  // namespace

BENCHMARK_CAPTURE(BM_Flattened, avx2_primary, Isa::avx2, 0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Instanced, avx2_primary_corners, Isa::avx2, 0, kCorners)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Instanced, avx2_primary_child_corners, Isa::avx2, 0, kChild)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Flattened, avx2_incoherent, Isa::avx2, 1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Instanced, avx2_incoherent_corners, Isa::avx2, 1, kCorners)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Instanced, avx2_incoherent_child_corners, Isa::avx2, 1, kChild)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Flattened, avx512_incoherent, Isa::avx512, 1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Instanced, avx512_incoherent_child_corners, Isa::avx512, 1, kChild)->Unit(benchmark::kMillisecond);

BENCHMARK_CAPTURE(BM_EmbreeFlattened, primary, 0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmbreeInstanced, primary, 0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmbreeFlattened, incoherent, 1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmbreeInstanced, incoherent, 1)->Unit(benchmark::kMillisecond);

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    const Fixture& f = fixture();
    benchmark::AddCustomContext("scene", "instances-" + std::to_string(f.n) + " of " + f.name);
    benchmark::AddCustomContext("rays_per_kind", std::to_string(f.rays[0].size()));
    benchmark::AddCustomContext("active_isa", std::string(name(active_isa())));
    const SceneStats& s = f.child_corners.stats();
    benchmark::AddCustomContext("instanced_bytes", std::to_string(s.bytes));
    benchmark::AddCustomContext("flattened_bvh8_bytes", std::to_string(wide_bytes(f.flat)) + " (" +
                                                            std::to_string(f.flat_triangles) + " triangles)");
    benchmark::AddCustomContext("box_volume", "corners=" + std::to_string(s.volume_corners) +
                                                  " child_corners=" + std::to_string(s.volume_child_corners));
    // instances-1000 against one dragon.
    const Bvh8 one = Bvh8::build(std::get<Mesh>(f.desc.geometries[0]));
    const SceneBvhN<8> k = SceneBvhN<8>::build(workloads::instances_scene(std::get<Mesh>(f.desc.geometries[0]), 1000));
    benchmark::AddCustomContext("one_bvh8_bytes", std::to_string(wide_bytes(one)));
    benchmark::AddCustomContext(
        "instances1000_bytes",
        std::to_string(k.stats().bytes) + " (" + std::to_string(k.stats().bytes_per_instance) + " per instance)");
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
