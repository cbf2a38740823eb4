// Exact inside/outside on the wide trees: points/s on BVH4/8/16 for
// the point set of inside_fixture.h (the BVH2's row uses the same).
#include "inside_fixture.h"
#include "simdbvh/query/inside_wide.h"

namespace {

void BM_WideInside(benchmark::State& st, int width) {
    const bench::TraversalScene& s = bench::traversal_scene();
    if (width == 4) return bench::run_inside(st, s.bvh4, "bvh4");
    if (width == 16) return bench::run_inside(st, s.bvh16, "bvh16");
    bench::run_inside(st, s.bvh8, "bvh8");
}

BENCHMARK_CAPTURE(BM_WideInside, bvh4, 4)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WideInside, bvh8, 8)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WideInside, bvh16, 16)->Unit(benchmark::kMillisecond);

}  // namespace
