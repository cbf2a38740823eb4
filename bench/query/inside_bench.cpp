// Exact inside/outside on the BVH2: points/s for the point set of
// inside_fixture.h (the wide trees' rows use the same).
#include "inside_fixture.h"

namespace {

void BM_Inside(benchmark::State& st) { bench::run_inside(st, bench::traversal_scene().bvh2, "bvh2"); }

BENCHMARK(BM_Inside)->Unit(benchmark::kMillisecond);

}  // namespace
