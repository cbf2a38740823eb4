// Closest point queries on the wide trees: points/s on BVH4/8/16
// for the two point sets of closest_point_fixture.h (the BVH2's rows use the
// same), one thread, Morton order.
#include "closest_point_fixture.h"

namespace {

void BM_WideClosestPoint(benchmark::State& st, int width, bool near) {
    const bench::TraversalScene& s = bench::traversal_scene();
    if (width == 4) return bench::run_closest_point(st, s.bvh4, "bvh4", near);
    if (width == 16) return bench::run_closest_point(st, s.bvh16, "bvh16", near);
    bench::run_closest_point(st, s.bvh8, "bvh8", near);
}

BENCHMARK_CAPTURE(BM_WideClosestPoint, bvh4_uniform, 4, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WideClosestPoint, bvh8_uniform, 8, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WideClosestPoint, bvh16_uniform, 16, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WideClosestPoint, bvh8_near_surface, 8, true)->Unit(benchmark::kMillisecond);

}  // namespace
