// Exact inside/outside on the wide trees: points/s on BVH4/8/16 for
// the point set of inside_fixture.h (the BVH2's row uses the same).
#include "inside_fixture.h"
#include "simdbvh/query/inside_wide.h"

namespace {

void BM_WideInside(benchmark::State& st, int width) {
    simdbvh::with_width(width, [&](auto n) {
        constexpr int N = decltype(n)::value;
        bench::run_inside(st, bench::traversal_scene().wide<N>(), "bvh" + std::to_string(N));
    });
}

BENCHMARK_CAPTURE(BM_WideInside, bvh4, 4)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WideInside, bvh8, 8)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WideInside, bvh16, 16)->Unit(benchmark::kMillisecond);

}  // namespace
