// Closest point queries on the BVH2: points/s for the two point
// sets of closest_point_fixture.h, one thread, Morton order.
#include "closest_point_fixture.h"

namespace {

void BM_ClosestPoint(benchmark::State& st, bool near) {
    bench::run_closest_point(st, bench::traversal_scene().bvh2, "bvh2", near);
}

BENCHMARK_CAPTURE(BM_ClosestPoint, bvh2_uniform, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ClosestPoint, bvh2_near_surface, true)->Unit(benchmark::kMillisecond);

}  // namespace
