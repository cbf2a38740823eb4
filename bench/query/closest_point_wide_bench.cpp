// Closest point queries on the wide trees: points/s on BVH4/8/16
// for the two point sets of closest_point_fixture.h (the BVH2's rows use the
// same), one thread, Morton order.
#include "closest_point_fixture.h"

namespace {

void BM_WideClosestPoint(benchmark::State& st, int width, bool near) {
    simdbvh::with_width(width, [&](auto n) {
        constexpr int N = decltype(n)::value;
        bench::run_closest_point(st, bench::traversal_scene().wide<N>(), "bvh" + std::to_string(N), near);
    });
}

BENCHMARK_CAPTURE(BM_WideClosestPoint, bvh4_uniform, 4, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WideClosestPoint, bvh8_uniform, 8, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WideClosestPoint, bvh16_uniform, 16, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WideClosestPoint, bvh8_near_surface, 8, true)->Unit(benchmark::kMillisecond);

}  // namespace
