// The traversal benchmarks' scene and main(): context lines name the scene,
// its size, the active ISA and the BVH statistics.
#include "traversal_fixture.h"

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

#include "simdbvh/workloads/scenes.h"

namespace bench {

const TraversalScene& traversal_scene() {
    static const TraversalScene s = [] {
        using namespace simdbvh;
        TraversalScene t;
        const char* env = std::getenv("SIMDBVH_BENCH_SCENE");
        t.name = env && *env ? env : (workloads::is_cached("dragon") ? "dragon" : "terrain");
        t.mesh = workloads::load_scene(t.name);
        t.bvh2 = Bvh2::build(t.mesh);
        t.bvh8 = Bvh8::build(t.bvh2);
        WideOptions g;
        g.collapse = Collapse::greedy;
        t.bvh8_greedy = Bvh8::build(t.bvh2, g);
        t.bvh4 = Bvh4::build(t.bvh2);
        t.bvh16 = Bvh16::build(t.bvh2);
        WideOptions q;
        q.quantized_nodes = true;
        t.bvh8q = Bvh8::build(t.bvh2, q);
        t.bvh16q = Bvh16::build(t.bvh2, q);
        const char* n = std::getenv("SIMDBVH_BENCH_RAYS");
        const std::size_t count = n && *n ? std::strtoull(n, nullptr, 10) : 100000;
        for (workloads::RayKind k : workloads::kRayKinds)
            t.rays[static_cast<int>(k)] = workloads::generate_rays(t.mesh, k, count, /*seed=*/1);
        const char* hd = std::getenv("SIMDBVH_BENCH_HD_SIDE");
        const int side = hd && *hd ? std::atoi(hd) : 1000;
        t.primary_hd = workloads::primary_rays(workloads::default_camera(t.mesh.bounds(), side, side));
        return t;
    }();
    return s;
}

}  // namespace bench

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    const bench::TraversalScene& s = bench::traversal_scene();
    using simdbvh::name;
    benchmark::AddCustomContext("scene", s.name);
    benchmark::AddCustomContext("triangles", std::to_string(s.mesh.size()));
    benchmark::AddCustomContext("rays_per_kind", std::to_string(s.rays[0].size()));
    benchmark::AddCustomContext("primary_hd_rays", std::to_string(s.primary_hd.size()));
    benchmark::AddCustomContext("active_isa", std::string(name(simdbvh::active_isa())));
    std::string supported;
    for (simdbvh::Isa isa : simdbvh::kAllIsas)
        if (simdbvh::supported(isa)) supported += (supported.empty() ? "" : ",") + std::string(name(isa));
    benchmark::AddCustomContext("supported_isas", supported);
    const auto& b2 = s.bvh2.stats();
    benchmark::AddCustomContext("bvh2", "nodes=" + std::to_string(b2.nodes) + " depth=" + std::to_string(b2.depth) +
                                            " sah=" + std::to_string(b2.sah_cost) +
                                            " build_ms=" + std::to_string(b2.build_ms));
    const std::pair<const char*, const simdbvh::WideStats*> wide[] = {
        {"bvh4_sah", &s.bvh4.stats()},   {"bvh8_sah", &s.bvh8.stats()},        {"bvh8_greedy", &s.bvh8_greedy.stats()},
        {"bvh16_sah", &s.bvh16.stats()}, {"bvh8_quantized", &s.bvh8q.stats()}, {"bvh16_quantized", &s.bvh16q.stats()}};
    for (const auto& [label, stats] : wide) {
        const auto& st = *stats;
        benchmark::AddCustomContext(
            label, "nodes=" + std::to_string(st.nodes) + " leaves=" + std::to_string(st.leaves) +
                       " blocks=" + std::to_string(st.blocks) + " depth=" + std::to_string(st.depth) +
                       " sah=" + std::to_string(st.sah_cost) + " fill=" + std::to_string(st.fill_rate) +
                       " block_fill=" + std::to_string(st.block_fill) + " bytes/tri=" +
                       std::to_string(st.bytes_per_triangle) + " build_ms=" + std::to_string(st.build_ms));
    }
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
