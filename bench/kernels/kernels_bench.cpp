// Kernel micro-benchmarks: box1, box8, tri1 and tri8 (watertight, Moller) for
// every ISA, with data that fits L1 (/l1) or streams 64 MiB from memory (/mem);
// brute8: the SIMD brute-force loop over 8 MiB or 64 MiB, tiled against per ray.
// items_per_second = box or triangle tests per second.
//   ./simdbvh_bench_kernels --benchmark_min_time=0.2
#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>
#include <vector>

#include "simdbvh/kernels/batch.h"
#include "simdbvh/kernels/testing.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/platform/topology.h"

namespace {

using namespace simdbvh;
using kernels::Tri1;

constexpr std::size_t kMemBytes = std::size_t(64) << 20;

class Rng {
public:
    explicit Rng(std::uint64_t s) : s_(s) {}
    float uniform() {
        std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return float((z ^ (z >> 31)) >> 40) * 0x1p-24f;
    }
    float range(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    Vec3 in_box(float lo, float hi) { return {range(lo, hi), range(lo, hi), range(lo, hi)}; }

private:
    std::uint64_t s_;
};

// Rays from a shell around the unit cube towards points inside it: a mix of
// hits and misses for boxes and triangles placed in [-1, 1]^3.
std::vector<Ray> make_rays(std::size_t n, std::uint64_t seed) {
    Rng rng(seed);
    std::vector<Ray> rays(n);
    for (Ray& r : rays) {
        r.org = rng.in_box(-3, 3);
        r.dir = rng.in_box(-0.5f, 0.5f) - r.org;
    }
    return rays;
}
Aabb make_box(Rng& rng) {
    const Vec3 c = rng.in_box(-1, 1), e = rng.in_box(0.05f, 0.4f);
    return {c - e, c + e};
}
Tri1 make_tri(Rng& rng, std::uint32_t id) {
    const Vec3 c = rng.in_box(-1, 1);
    return {c + rng.in_box(-0.3f, 0.3f), c + rng.in_box(-0.3f, 0.3f), c + rng.in_box(-0.3f, 0.3f), id};
}

bool skip_unsupported(benchmark::State& st, Isa isa) {
    if (supported(isa)) return false;
    st.SkipWithError(("this CPU/OS lacks " + std::string(name(isa))).c_str());
    return true;
}

// box1/scalar: ray i vs box i (one slab test per ray).
void BM_Box1(benchmark::State& st, bool mem) {
    const std::size_t n = mem ? kMemBytes / sizeof(Aabb) : 256;
    Rng rng(1);
    std::vector<Aabb> boxes(n);
    for (Aabb& b : boxes) b = make_box(rng);
    const std::vector<Ray> rays = make_rays(n, 2);
    std::vector<std::uint8_t> hits(n);
    std::vector<float> entries(n);
    for (auto _ : st) {
        kernels::intersect_box1(rays, boxes, hits, entries);
        benchmark::DoNotOptimize(hits.data());
        benchmark::ClobberMemory();
    }
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(n));
}

// box8/<isa>: every ray vs every Box8 block (count of hits).
void BM_Box8(benchmark::State& st, Isa isa, bool mem) {
    if (skip_unsupported(st, isa)) return;
    const std::size_t nblocks = mem ? kMemBytes / sizeof(Box8) : 16;  // l1: 3 KiB of boxes
    const std::size_t nrays = mem ? 2 : 64;
    Rng rng(3);
    std::vector<Box8> blocks(nblocks);
    for (Box8& b : blocks)
        for (int j = 0; j < 8; ++j) b.set(j, make_box(rng));
    const std::vector<Ray> rays = make_rays(nrays, 4);
    std::uint64_t total = 0;
    for (auto _ : st) {
        total += kernels::count_box8_hits(rays, blocks, isa);
        benchmark::DoNotOptimize(total);
    }
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(nrays * nblocks * 8));
    st.counters["hit_rate"] = double(total) / double(st.iterations() * nrays * nblocks * 8);
}

// tri1_<test>/scalar: ray i vs triangle i.
void BM_Tri1(benchmark::State& st, TriangleTest test, bool mem) {
    const std::size_t n = mem ? kMemBytes / sizeof(Tri1) : 256;
    Rng rng(5);
    std::vector<Tri1> tris(n);
    for (std::size_t i = 0; i < n; ++i) tris[i] = make_tri(rng, std::uint32_t(i));
    const std::vector<Ray> rays = make_rays(n, 6);
    std::vector<Hit> hits(n);
    for (auto _ : st) {
        kernels::intersect_tri1(rays, tris, test, hits);
        benchmark::DoNotOptimize(hits.data());
        benchmark::ClobberMemory();
    }
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(n));
}

// tri8_<test>/<isa>: closest hit of every ray over all Tri8 blocks.
void BM_Tri8(benchmark::State& st, TriangleTest test, Isa isa, bool mem) {
    if (skip_unsupported(st, isa)) return;
    const std::size_t nblocks = mem ? kMemBytes / sizeof(Tri8) : 8;  // l1: 2.5 KiB of triangles
    const std::size_t nrays = mem ? 2 : 64;
    Rng rng(7);
    std::vector<Tri8> blocks(nblocks);
    for (std::size_t b = 0; b < nblocks; ++b)
        for (int j = 0; j < 8; ++j) {
            const Tri1 t = make_tri(rng, std::uint32_t(8 * b + j));
            blocks[b].set(j, t.v0, t.v1, t.v2, t.prim);
        }
    const std::vector<Ray> rays = make_rays(nrays, 8);
    std::vector<Hit> hits(nrays);
    for (auto _ : st) {
        kernels::intersect_tri8(rays, blocks, test, hits, isa);
        benchmark::DoNotOptimize(hits.data());
        benchmark::ClobberMemory();
    }
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(nrays * nblocks * 8));
}

// brute8_<tiled|per_ray>/<isa>/<l3|mem>: 64 rays' closest hits over 8 MiB
// (l3: past L2, like dragon-res2's 203k triangles) or 64 MiB (mem) of Tri8
// blocks. tiled is one batched call (the loop walks the blocks in L1-sized
// tiles for 8 rays at a time); per_ray is one call per ray, which streams every
// block once per ray (the loop before tiling). Same answers, same rays.
void BM_Brute8(benchmark::State& st, bool tiled, Isa isa, bool mem) {
    if (skip_unsupported(st, isa)) return;
    const std::size_t nblocks = (mem ? kMemBytes : kMemBytes / 8) / sizeof(Tri8);
    const std::size_t nrays = 64;
    Rng rng(9);
    std::vector<Tri8> blocks(nblocks);
    for (std::size_t b = 0; b < nblocks; ++b)
        for (int j = 0; j < 8; ++j) {
            const Tri1 t = make_tri(rng, std::uint32_t(8 * b + j));
            blocks[b].set(j, t.v0 * 0.05f, t.v1 * 0.05f, t.v2 * 0.05f, t.prim);  // small triangles: few hits
        }
    const std::vector<Ray> rays = make_rays(nrays, 10);
    std::vector<Hit> hits(nrays);
    for (auto _ : st) {
        if (tiled) {
            kernels::intersect_tri8(rays, blocks, TriangleTest::watertight, hits, isa);
        } else {
            for (std::size_t i = 0; i < nrays; ++i)
                kernels::intersect_tri8(std::span<const Ray>(&rays[i], 1), blocks, TriangleTest::watertight,
                                        std::span<Hit>(&hits[i], 1), isa);
        }
        benchmark::DoNotOptimize(hits.data());
        benchmark::ClobberMemory();
    }
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(nrays * nblocks * 8));
}

void register_all() {
    for (bool mem : {false, true})
        for (bool tiled : {true, false})
            for (Isa isa : kAllIsas)
                if (isa != Isa::scalar)
                    benchmark::RegisterBenchmark((std::string(tiled ? "brute8_tiled/" : "brute8_per_ray/") +
                                                  std::string(name(isa)) + (mem ? "/mem" : "/l3"))
                                                     .c_str(),
                                                 BM_Brute8, tiled, isa, mem);
    for (bool mem : {false, true}) {
        const std::string size = mem ? "/mem" : "/l1";
        benchmark::RegisterBenchmark(("box1/scalar" + size).c_str(), BM_Box1, mem);
        for (Isa isa : kAllIsas)
            benchmark::RegisterBenchmark(("box8/" + std::string(name(isa)) + size).c_str(), BM_Box8, isa, mem);
        for (TriangleTest test : {TriangleTest::watertight, TriangleTest::moller}) {
            const std::string tn = test == TriangleTest::watertight ? "watertight" : "moller";
            benchmark::RegisterBenchmark(("tri1_" + tn + "/scalar" + size).c_str(), BM_Tri1, test, mem);
            for (Isa isa : kAllIsas)
                benchmark::RegisterBenchmark(("tri8_" + tn + "/" + std::string(name(isa)) + size).c_str(), BM_Tri8,
                                             test, isa, mem);
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    try {
        benchmark::AddCustomContext("simdbvh_active_isa", std::string(name(active_isa())));
    } catch (const std::exception& e) {
        benchmark::AddCustomContext("simdbvh_active_isa", e.what());
    }
    benchmark::AddCustomContext("simdbvh_machine", machine_line());
    register_all();
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
