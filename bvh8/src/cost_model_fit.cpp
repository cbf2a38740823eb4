// The cost model's coefficients (cost_model.h), one set per ISA, fitted on
// this project's reference machine. Regenerate a set on the machine the
// library will run on, with that ISA forced (the bench fits, checks on held-out
// points and rewrites its own block below):
//
//   SIMDBVH_CACHE=.cache/scenes SIMDBVH_ISA=<isa> build/release/simdbvh bench --sweep --report out/sweep
//       --model-out bvh8/src/cost_model_fit.cpp   (one line)
//
// An ISA whose block is empty (fitted = false) uses the nearest narrower
// fitted set (cost_model()).
#include "simdbvh/bvh8/cost_model.h"

namespace simdbvh {

namespace {

struct FittedSet {
    bool fitted;
    CostModel model;
};

// Order per set: brute, brute8, bvh2, bvh4, bvh8, bvh16; each {build0, build1, call, ray0, ray1} in ms.
// sweep:scalar:begin
constexpr FittedSet kScalar{true, {Isa::scalar, {{{0, 0, 0.001, 2e-5, 2e-5}, {0.001, 5e-6, 0.001, 2e-5, 1e-5},
                                                 {0.01, 1e-4, 0.001, 1e-4, 1e-4}, {0.01, 1.2e-4, 0.001, 1e-4, 1e-4},
                                                 {0.01, 1.2e-4, 0.001, 1e-4, 1e-4}, {0.01, 1.3e-4, 0.001, 1e-4, 1e-4}}}}};
// sweep:scalar:end
// sweep:avx2:begin
constexpr FittedSet kAvx2{false, {Isa::avx2, {}}};
// sweep:avx2:end
// sweep:avx512:begin
// simdbvh bench --sweep --report out/sweep --model-out bvh8/src/cost_model_fit.cpp --readme README.md
// AMD EPYC | 2 cores, 2 threads | L1d 32 KiB, L2 1 MiB, L3 32 MiB | ISAs scalar avx2 avx512 (active avx512) | hwloc
constexpr FittedSet kAvx512{true, {Isa::avx512, {{{0, 0, 3.84161e-05, 8.09411e-06, 1.18901e-05},
    {0.000193016, 7.55513e-06, 8.48545e-05, 2.07683e-05, 8.21382e-07},
    {0.000252185, 3.13036e-05, 7.9803e-05, 0, 1.5713e-05},
    {0.00143399, 3.70039e-05, 6.95893e-05, 3.67977e-06, 1.22442e-05},
    {0.000820443, 3.75034e-05, 8.05666e-05, 6.2573e-06, 1.08222e-05},
    {0.000992378, 4.08345e-05, 7.95467e-05, 9.8457e-06, 9.88841e-06}}}}};
// sweep:avx512:end

}  // namespace

const CostModel& cost_model(Isa isa) {
    const FittedSet* sets[] = {&kScalar, &kAvx2, &kAvx512};  // kAllIsas order, narrowest first
    for (int i = int(isa); i >= 0; --i)
        if (sets[i]->fitted) return sets[i]->model;
    for (const FittedSet* s : sets)  // nothing narrower fitted: the narrowest fitted set
        if (s->fitted) return s->model;
    return sets[0]->model;
}

}  // namespace simdbvh
