// Wide BVH traversal per ISA (scalar reference loops, AVX2, AVX-512): BVH8
// with SAH and greedy collapse, BVH4 and BVH16 (SAH) from the same BVH2, BVH8 and BVH16 with quantized nodes
// (BM_Bvh8Quantized, BM_Bvh16Quantized), BVH8
// with the rays in flight forced (BM_Bvh8InFlight: 1 or 8 against the size rule), BVH8 with the
// Moller-Trumbore triangle test instead of the watertight one (BM_Bvh8Moller).
// rays/s as the rate counter, wide nodes visited per ray; box and triangle
// counters count lanes (N per node, 8 per Tri8 block).
#include <benchmark/benchmark.h>

#include <sstream>
#include <string>
#include <vector>

#include "simdbvh/bvh8/internal/isa_choice.h"
#include "simdbvh/workloads/rays.h"
#include "traversal_fixture.h"

namespace {

using simdbvh::Collapse;
using simdbvh::Isa;
using simdbvh::workloads::RayKind;

template <int N>
void run_wide(benchmark::State& st, const simdbvh::BvhN<N>& bvh, Isa isa, Collapse collapse, RayKind kind, bool any,
              const simdbvh::TraceOptions& timed = {}) {
    if (!simdbvh::supported(isa)) {
        st.SkipWithError("CPU lacks the ISA");
        return;
    }
    const auto& rays = bench::rays_of(kind);
    std::vector<simdbvh::Hit> hits(rays.size());
    simdbvh::TraceStats ts;
    simdbvh::TraceOptions counted;
    counted.stats = &ts;
    counted.test = timed.test;
    if (any) simdbvh::occluded(bvh, rays, hits, with_isa(counted, isa));
    else simdbvh::intersect(bvh, rays, hits, with_isa(counted, isa));
    for (auto _ : st) {
        if (any) simdbvh::occluded(bvh, rays, hits, with_isa(timed, isa));
        else simdbvh::intersect(bvh, rays, hits, with_isa(timed, isa));
        benchmark::DoNotOptimize(hits.data());
    }
    const double n = double(rays.size());
    st.counters["rays/s"] = benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate);
    st.counters["nodes/ray"] = double(ts.nodes_visited) / n;
    st.counters["boxes/ray"] = double(ts.box_tests) / n;
    st.counters["tris/ray"] = double(ts.triangle_tests) / n;
    st.SetLabel("bvh" + std::to_string(N) + (bvh.qnodes().empty() ? "" : " quantized") + " " +
                std::string(simdbvh::name(isa)) + " " + std::string(simdbvh::name(collapse)) + " " +
                std::string(simdbvh::workloads::name(kind)) + (any ? " any" : " closest") +
                (timed.test == simdbvh::TriangleTest::moller ? " moller" : "") +
                (timed.in_flight != 0 ? " in_flight " + std::to_string(timed.in_flight) : std::string()) +
                (timed.reorder == simdbvh::Reorder::off  ? " caller's order"
                 : timed.reorder == simdbvh::Reorder::on ? " sorted"
                                                         : ""));
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

// The same trees with quantized nodes (qnode.h), beside BM_Bvh8 and BM_Bvh16.
void BM_Bvh8Quantized(benchmark::State& st, Isa isa, Collapse collapse, RayKind kind, bool any) {
    run_wide<8>(st, bench::traversal_scene().bvh8q, isa, collapse, kind, any);
}
void BM_Bvh16Quantized(benchmark::State& st, Isa isa, Collapse collapse, RayKind kind, bool any) {
    run_wide<16>(st, bench::traversal_scene().bvh16q, isa, collapse, kind, any);
}

// BVH8 (SAH) with the rays in flight forced (TraceOptions::in_flight: by
// default 1 for trees of at most 2 MiB, else 8), beside BM_Bvh8's default.
void BM_Bvh8InFlight(benchmark::State& st, Isa isa, int flight, RayKind kind, bool any) {
    simdbvh::TraceOptions o;
    o.in_flight = flight;
    run_wide<8>(st, bench::traversal_scene().bvh8, isa, Collapse::sah, kind, any, o);
}
// BVH8 and BVH16 (SAH) traced in the caller's order (TraceOptions::reorder
// off) or always sorted (on), beside BM_Bvh8's and BM_Bvh16's default
// (automatic: sorted when the batch is scattered, ray_order.h).
void BM_Bvh8Order(benchmark::State& st, Isa isa, simdbvh::Reorder r, RayKind kind, bool any) {
    simdbvh::TraceOptions o;
    o.reorder = r;
    run_wide<8>(st, bench::traversal_scene().bvh8, isa, Collapse::sah, kind, any, o);
}
void BM_Bvh16Order(benchmark::State& st, Isa isa, simdbvh::Reorder r, RayKind kind, bool any) {
    simdbvh::TraceOptions o;
    o.reorder = r;
    run_wide<16>(st, bench::traversal_scene().bvh16, isa, Collapse::sah, kind, any, o);
}
#define SIMDBVH_ORDER_BENCH(fn, isa, order)                                                                            \
    BENCHMARK_CAPTURE(fn, isa##_##order##_primary_closest, Isa::isa, simdbvh::Reorder::order, RayKind::primary, false) \
        ->Unit(benchmark::kMillisecond);                                                                               \
    BENCHMARK_CAPTURE(fn, isa##_##order##_incoherent_closest, Isa::isa, simdbvh::Reorder::order, RayKind::incoherent,  \
                      false)                                                                                           \
        ->Unit(benchmark::kMillisecond);                                                                               \
    BENCHMARK_CAPTURE(fn, isa##_##order##_diffuse_closest, Isa::isa, simdbvh::Reorder::order, RayKind::diffuse, false) \
        ->Unit(benchmark::kMillisecond);                                                                               \
    BENCHMARK_CAPTURE(fn, isa##_##order##_primary_any, Isa::isa, simdbvh::Reorder::order, RayKind::primary, true)      \
        ->Unit(benchmark::kMillisecond);                                                                               \
    BENCHMARK_CAPTURE(fn, isa##_##order##_incoherent_any, Isa::isa, simdbvh::Reorder::order, RayKind::incoherent,      \
                      true)                                                                                            \
        ->Unit(benchmark::kMillisecond);                                                                               \
    BENCHMARK_CAPTURE(fn, isa##_##order##_diffuse_any, Isa::isa, simdbvh::Reorder::order, RayKind::diffuse, true)      \
        ->Unit(benchmark::kMillisecond)
// The distributions whose order the automatic rule decides beyond the three above: shadow rays in pixel order
// (kept by the rule before shadow rays were sorted, sorted since), LiDAR (kept: one origin).
#define SIMDBVH_ORDER_KIND(isa, order, kind)                                                                        \
    BENCHMARK_CAPTURE(BM_Bvh8Order, isa##_##order##_##kind##_closest, Isa::isa, simdbvh::Reorder::order,            \
                      RayKind::kind, false)                                                                         \
        ->Unit(benchmark::kMillisecond);                                                                            \
    BENCHMARK_CAPTURE(BM_Bvh8Order, isa##_##order##_##kind##_any, Isa::isa, simdbvh::Reorder::order, RayKind::kind, \
                      true)                                                                                         \
        ->Unit(benchmark::kMillisecond)
SIMDBVH_ORDER_KIND(avx512, off, shadow);
SIMDBVH_ORDER_KIND(avx512, on, shadow);
SIMDBVH_ORDER_KIND(avx512, off, area_shadow);
SIMDBVH_ORDER_KIND(avx512, on, area_shadow);
SIMDBVH_ORDER_KIND(avx512, off, lidar);
SIMDBVH_ORDER_KIND(avx512, on, lidar);
SIMDBVH_ORDER_KIND(avx2, off, shadow);
SIMDBVH_ORDER_KIND(avx2, on, shadow);
SIMDBVH_ORDER_BENCH(BM_Bvh8Order, avx512, off);
SIMDBVH_ORDER_BENCH(BM_Bvh8Order, avx512, on);
SIMDBVH_ORDER_BENCH(BM_Bvh16Order, avx512, off);
SIMDBVH_ORDER_BENCH(BM_Bvh16Order, avx512, on);
SIMDBVH_ORDER_BENCH(BM_Bvh8Order, avx2, off);

// BVH8 (SAH) with the Moller-Trumbore triangle test (TraceOptions::test, the
// kind of test Embree's default leaves run; not watertight), beside BM_Bvh8's
// watertight test: what watertightness costs per ray.
void BM_Bvh8Moller(benchmark::State& st, Isa isa, Collapse collapse, RayKind kind, bool any) {
    simdbvh::TraceOptions o;
    o.test = simdbvh::TriangleTest::moller;
    run_wide<8>(st, bench::traversal_scene().bvh8, isa, collapse, kind, any, o);
}
#define SIMDBVH_FLIGHT_BENCH(isa, flight)                                                                             \
    BENCHMARK_CAPTURE(BM_Bvh8InFlight, isa##_in_flight##flight##_primary_closest, Isa::isa, flight, RayKind::primary, \
                      false)                                                                                          \
        ->Unit(benchmark::kMillisecond);                                                                              \
    BENCHMARK_CAPTURE(BM_Bvh8InFlight, isa##_in_flight##flight##_incoherent_closest, Isa::isa, flight,                \
                      RayKind::incoherent, false)                                                                     \
        ->Unit(benchmark::kMillisecond);                                                                              \
    BENCHMARK_CAPTURE(BM_Bvh8InFlight, isa##_in_flight##flight##_diffuse_closest, Isa::isa, flight, RayKind::diffuse, \
                      false)                                                                                          \
        ->Unit(benchmark::kMillisecond);                                                                              \
    BENCHMARK_CAPTURE(BM_Bvh8InFlight, isa##_in_flight##flight##_primary_any, Isa::isa, flight, RayKind::primary,     \
                      true)                                                                                           \
        ->Unit(benchmark::kMillisecond);                                                                              \
    BENCHMARK_CAPTURE(BM_Bvh8InFlight, isa##_in_flight##flight##_incoherent_any, Isa::isa, flight,                    \
                      RayKind::incoherent, true)                                                                      \
        ->Unit(benchmark::kMillisecond);                                                                              \
    BENCHMARK_CAPTURE(BM_Bvh8InFlight, isa##_in_flight##flight##_diffuse_any, Isa::isa, flight, RayKind::diffuse,     \
                      true)                                                                                           \
        ->Unit(benchmark::kMillisecond)

// A 1000 x 1000 camera's primary rays in image order (the fixture's
// primary_hd), BVH8 and BVH16 (SAH) with streams of 32 rays
// (TraceOptions::packets automatic, the default) and without (off), beside BM_EmbreeHd.
template <int N>
void run_hd(benchmark::State& st, const simdbvh::BvhN<N>& bvh, Isa isa, bool any, simdbvh::Packets packets) {
    if (!simdbvh::supported(isa)) return st.SkipWithError("CPU lacks the ISA");
    const auto& rays = bench::traversal_scene().primary_hd;
    std::vector<simdbvh::Hit> hits(rays.size());
    simdbvh::TraceOptions o;
    o.packets = packets;
    auto pass = [&] {
        if (any) simdbvh::occluded(bvh, rays, hits, with_isa(o, isa));
        else simdbvh::intersect(bvh, rays, hits, with_isa(o, isa));
    };
    pass();  // warm-up
    for (auto _ : st) {
        pass();
        benchmark::DoNotOptimize(hits.data());
    }
    st.counters["rays/s"] = benchmark::Counter(double(rays.size()), benchmark::Counter::kIsIterationInvariantRate);
    st.SetLabel("bvh" + std::to_string(N) + " " + std::string(simdbvh::name(isa)) + " primary_hd " +
                (packets == simdbvh::Packets::off ? "single rays" : "streams auto") + (any ? " any" : " closest"));
}
void BM_Bvh8Hd(benchmark::State& st, Isa isa, bool any, simdbvh::Packets packets) {
    run_hd<8>(st, bench::traversal_scene().bvh8, isa, any, packets);
}
void BM_Bvh16Hd(benchmark::State& st, Isa isa, bool any, simdbvh::Packets packets) {
    run_hd<16>(st, bench::traversal_scene().bvh16, isa, any, packets);
}
#define SIMDBVH_HD_BENCH(fn, isa)                                                              \
    BENCHMARK_CAPTURE(fn, isa##_streams_closest, Isa::isa, false, simdbvh::Packets::automatic) \
        ->Unit(benchmark::kMillisecond);                                                       \
    BENCHMARK_CAPTURE(fn, isa##_single_closest, Isa::isa, false, simdbvh::Packets::off)        \
        ->Unit(benchmark::kMillisecond);                                                       \
    BENCHMARK_CAPTURE(fn, isa##_streams_any, Isa::isa, true, simdbvh::Packets::automatic)      \
        ->Unit(benchmark::kMillisecond);                                                       \
    BENCHMARK_CAPTURE(fn, isa##_single_any, Isa::isa, true, simdbvh::Packets::off)->Unit(benchmark::kMillisecond)
SIMDBVH_HD_BENCH(BM_Bvh8Hd, avx2);
SIMDBVH_HD_BENCH(BM_Bvh8Hd, avx512);
SIMDBVH_HD_BENCH(BM_Bvh16Hd, avx512);

#define SIMDBVH_WIDE_BENCH(fn, isa, collapse)                                                                         \
    BENCHMARK_CAPTURE(fn, isa##_##collapse##_primary_closest, Isa::isa, Collapse::collapse, RayKind::primary, false)  \
        ->Unit(benchmark::kMillisecond);                                                                              \
    BENCHMARK_CAPTURE(fn, isa##_##collapse##_incoherent_closest, Isa::isa, Collapse::collapse, RayKind::incoherent,   \
                      false)                                                                                          \
        ->Unit(benchmark::kMillisecond);                                                                              \
    BENCHMARK_CAPTURE(fn, isa##_##collapse##_diffuse_closest, Isa::isa, Collapse::collapse, RayKind::diffuse, false)  \
        ->Unit(benchmark::kMillisecond);                                                                              \
    BENCHMARK_CAPTURE(fn, isa##_##collapse##_primary_any, Isa::isa, Collapse::collapse, RayKind::primary, true)       \
        ->Unit(benchmark::kMillisecond);                                                                              \
    BENCHMARK_CAPTURE(fn, isa##_##collapse##_incoherent_any, Isa::isa, Collapse::collapse, RayKind::incoherent, true) \
        ->Unit(benchmark::kMillisecond);                                                                              \
    BENCHMARK_CAPTURE(fn, isa##_##collapse##_diffuse_any, Isa::isa, Collapse::collapse, RayKind::diffuse, true)       \
        ->Unit(benchmark::kMillisecond)

// Without an explicit ISA: the choice by speed (bvh8.h, traversal_isa_choice;
// the untimed warm-up's batch calibrates it when it is the process's first).
void BM_Bvh8Auto(benchmark::State& st, RayKind kind, bool any) {
    const auto& bvh = bench::traversal_scene().bvh8;
    const auto& rays = bench::rays_of(kind);
    std::vector<simdbvh::Hit> hits(rays.size());
    auto pass = [&] {
        if (any) simdbvh::occluded(bvh, rays, hits);
        else simdbvh::intersect(bvh, rays, hits);
    };
    pass();
    for (auto _ : st) {
        pass();
        benchmark::DoNotOptimize(hits.data());
    }
    st.counters["rays/s"] = benchmark::Counter(double(rays.size()), benchmark::Counter::kIsIterationInvariantRate);
    const simdbvh::TraversalIsaChoice c = simdbvh::traversal_isa_choice(8, any);
    std::ostringstream label;
    label << "bvh8 auto->" << simdbvh::name(c.isa) << " ("
          << (c.forced ? "forced" : (c.calibrated ? "calibrated" : "detected"));
    for (Isa isa : simdbvh::kAllIsas)
        if (c.ns_per_ray[int(isa)] > 0)
            label << " " << simdbvh::name(isa) << "=" << int(c.ns_per_ray[int(isa)]) << "ns";
    label << ") " << simdbvh::workloads::name(kind) << (any ? " any" : " closest");
    st.SetLabel(label.str());
}
#define SIMDBVH_AUTO_BENCH(kind)                                                                                    \
    BENCHMARK_CAPTURE(BM_Bvh8Auto, auto_sah_##kind##_closest, RayKind::kind, false)->Unit(benchmark::kMillisecond); \
    BENCHMARK_CAPTURE(BM_Bvh8Auto, auto_sah_##kind##_any, RayKind::kind, true)->Unit(benchmark::kMillisecond)
SIMDBVH_AUTO_BENCH(primary);
SIMDBVH_AUTO_BENCH(incoherent);
SIMDBVH_AUTO_BENCH(diffuse);
// The distributions the defaults were not tuned on (workloads/rays.h), with every ISA forced beside the
// automatic choice; BM_Embree has the same rows (bench/reference/embree_trace_bench.cpp).
SIMDBVH_AUTO_BENCH(diffuse_shuffled);
SIMDBVH_AUTO_BENCH(shadow);
SIMDBVH_AUTO_BENCH(area_shadow);
SIMDBVH_AUTO_BENCH(ao);
SIMDBVH_AUTO_BENCH(lidar);
#define SIMDBVH_FORCED_BENCH(isa, kind)                                                                   \
    BENCHMARK_CAPTURE(BM_Bvh8, isa##_sah_##kind##_closest, Isa::isa, Collapse::sah, RayKind::kind, false) \
        ->Unit(benchmark::kMillisecond);                                                                  \
    BENCHMARK_CAPTURE(BM_Bvh8, isa##_sah_##kind##_any, Isa::isa, Collapse::sah, RayKind::kind, true)      \
        ->Unit(benchmark::kMillisecond)
#define SIMDBVH_FORCED_KINDS(isa)                \
    SIMDBVH_FORCED_BENCH(isa, diffuse_shuffled); \
    SIMDBVH_FORCED_BENCH(isa, shadow);           \
    SIMDBVH_FORCED_BENCH(isa, area_shadow);      \
    SIMDBVH_FORCED_BENCH(isa, ao);               \
    SIMDBVH_FORCED_BENCH(isa, lidar)
SIMDBVH_FORCED_KINDS(avx2);
SIMDBVH_FORCED_KINDS(avx512);

// A 256 x 256 camera's 65,536 primary rays in image order, BVH8 built from
// the mesh (Bvh8::build(mesh), the tree a user builds), threads 1 and 2:
// with each ISA given (BM_Bvh8Camera64k), without one after the choice is
// made (BM_Bvh8Camera64kAuto: the chosen ISA's speed), and without one on
// the batch that calibrates (BM_Bvh8Camera64kCalibrating: the choice
// forgotten before each iteration, untimed; the tree and rays are as warm as
// in the others, so it shows what the calibration costs its batch).
struct Camera64k {
    simdbvh::Bvh8 bvh;
    std::vector<simdbvh::Ray> rays;
};
const Camera64k& camera64k() {
    static const Camera64k c = [] {
        const auto& s = bench::traversal_scene();
        return Camera64k{simdbvh::Bvh8::build(s.mesh),
                         simdbvh::workloads::generate_rays(s.mesh, RayKind::primary, 65536, /*seed=*/1)};
    }();
    return c;
}
enum class Camera64kIsa { given, chosen, calibrating };
void run_camera64k(benchmark::State& st, Camera64kIsa mode, Isa isa) {
    if (mode == Camera64kIsa::given && !simdbvh::supported(isa)) return st.SkipWithError("CPU lacks the ISA");
    const Camera64k& c = camera64k();
    std::vector<simdbvh::Hit> hits(c.rays.size());
    simdbvh::TraceOptions o;
    o.threads = int(st.range(0));
    auto pass = [&] {
        if (mode == Camera64kIsa::given) simdbvh::intersect(c.bvh, c.rays, hits, with_isa(o, isa));
        else simdbvh::intersect(c.bvh, c.rays, hits, o);
    };
    pass();  // warm-up (and, without an ISA, the choice)
    for (auto _ : st) {
        if (mode == Camera64kIsa::calibrating) {
            st.PauseTiming();
            simdbvh::bvh8::detail::forget_choice(8, false);
            st.ResumeTiming();
        }
        pass();
        benchmark::DoNotOptimize(hits.data());
    }
    st.counters["rays/s"] = benchmark::Counter(double(c.rays.size()), benchmark::Counter::kIsIterationInvariantRate);
    const simdbvh::TraversalIsaChoice ch = simdbvh::traversal_isa_choice(8, false);
    std::ostringstream label;
    label << "bvh8 camera 256x256 threads " << o.threads << " ";
    if (mode == Camera64kIsa::given) label << simdbvh::name(isa) << " given";
    else label << (mode == Camera64kIsa::chosen ? "auto->" : "calibrating->") << simdbvh::name(ch.isa);
    st.SetLabel(label.str());
}
void BM_Bvh8Camera64k(benchmark::State& st, Isa isa) { run_camera64k(st, Camera64kIsa::given, isa); }
void BM_Bvh8Camera64kAuto(benchmark::State& st) { run_camera64k(st, Camera64kIsa::chosen, Isa::scalar); }
void BM_Bvh8Camera64kCalibrating(benchmark::State& st) { run_camera64k(st, Camera64kIsa::calibrating, Isa::scalar); }
BENCHMARK_CAPTURE(BM_Bvh8Camera64k, avx2, Isa::avx2)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Bvh8Camera64k, avx512, Isa::avx512)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Bvh8Camera64kAuto)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Bvh8Camera64kCalibrating)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

SIMDBVH_WIDE_BENCH(BM_Bvh8, scalar, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh8, avx2, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh8, avx512, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh8, avx2, greedy);
SIMDBVH_WIDE_BENCH(BM_Bvh8Moller, avx2, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh8Moller, avx512, sah);
SIMDBVH_FLIGHT_BENCH(avx2, 1);
SIMDBVH_FLIGHT_BENCH(avx2, 8);
SIMDBVH_FLIGHT_BENCH(avx512, 1);
SIMDBVH_FLIGHT_BENCH(avx512, 8);
// The same BVH2 collapsed 4 and 16 wide (SAH), beside BM_Bvh8.
SIMDBVH_WIDE_BENCH(BM_Bvh4, scalar, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh4, avx2, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh4, avx512, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh16, scalar, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh16, avx2, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh16, avx512, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh8Quantized, scalar, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh8Quantized, avx2, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh8Quantized, avx512, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh16Quantized, avx2, sah);
SIMDBVH_WIDE_BENCH(BM_Bvh16Quantized, avx512, sah);

}  // namespace
