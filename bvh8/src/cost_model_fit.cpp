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

// Order per set: brute, brute8, bvh2, bvh4, bvh8, bvh16; each {build0, build1, call, ray0, ray1, ray2} in ms
// and build_par (cost_model.h); sets fitted before a term existed leave it 0.
// sweep:scalar:begin
// simdbvh bench --sweep --report out/sweep-scalar --model-out bvh8/src/cost_model_fit.cpp
// AMD EPYC | 2 cores, 2 threads | L1d 32 KiB, L2 1 MiB, L3 32 MiB | ISAs scalar avx2 avx512 (active scalar) | hwloc
constexpr FittedSet kScalar{true, {Isa::scalar, {{{0, 0, 6.09148e-05, 1.3696e-05, 9.23574e-06},
    {0.000159874, 7.13266e-06, 8.50016e-05, 7.12718e-05, 8.1216e-06},
    {0.000132104, 2.58273e-05, 8.47929e-05, 5.12027e-06, 1.55767e-05},
    {0.00123173, 3.09527e-05, 9.89637e-05, 2.20265e-05, 1.86517e-05},
    {0.000804997, 3.19017e-05, 0.000113327, 3.24592e-05, 1.99136e-05},
    {0.00106701, 3.39046e-05, 0.000104558, 4.99452e-05, 2.0038e-05}}}}};
// sweep:scalar:end
// sweep:avx2:begin
// simdbvh bench --sweep --report out/sweep-avx2 --model-out bvh8/src/cost_model_fit.cpp
// AMD EPYC | 2 cores, 2 threads | L1d 32 KiB, L2 1 MiB, L3 32 MiB | ISAs scalar avx2 avx512 (active avx2) | hwloc
constexpr FittedSet kAvx2{true, {Isa::avx2, {{{0, 0, 4.29226e-05, 1.03185e-05, 1.06656e-05},
    {0.000252355, 7.2326e-06, 7.43555e-05, 2.14408e-05, 8.45915e-07},
    {0.000135276, 3.05274e-05, 7.59309e-05, 7.10222e-08, 1.61635e-05},
    {0.00117908, 3.6806e-05, 7.95745e-05, 7.19915e-06, 1.19363e-05},
    {0.000790783, 3.87115e-05, 7.71586e-05, 9.0221e-06, 1.02447e-05},
    {0.00102635, 3.93928e-05, 6.73027e-05, 1.58587e-05, 8.92966e-06}}}}};
// sweep:avx2:end
// sweep:avx512:begin
// simdbvh bench --sweep --report out/sweep --model-out bvh8/src/cost_model_fit.cpp --readme README.md
// AMD EPYC | 2 cores, 2 threads | L1d 32 KiB, L2 1 MiB, L3 32 MiB | ISAs scalar avx2 avx512 (active avx512) | hwloc
constexpr FittedSet kAvx512{true, {Isa::avx512, {{{0, 0, 6.92479e-05, 2.67561e-05, 1.12518e-05, 0, 0},
    {0.000119552, 8.43527e-06, 0.000111129, 2.46507e-05, 7.4116e-07, 7.80156e-07, 0.2108},
    {0.000217235, 2.89891e-05, 0.000125053, 8.6078e-06, 1.62562e-05, 0, 0.759},
    {0.00118464, 2.50337e-05, 0.000122427, 1.01892e-05, 1.13242e-05, 0, 0.759},
    {0.00104672, 2.59214e-05, 0.000111909, 1.40123e-05, 9.33911e-06, 0, 0.759},
    {0.00122951, 2.60622e-05, 0.000130848, 1.72348e-05, 8.33582e-06, 0, 0.759}}}}};
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
