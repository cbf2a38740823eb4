// The cost model's coefficients (cost_model.h), one set per ISA, fitted on
// this project's reference machine. Regenerate a set on the machine the
// library will run on, with that ISA forced (the bench fits, checks on held-out
// points and rewrites its own block below):
//
//   SIMDBVH_ISA=<isa> build/release/simdbvh bench --sweep --report out/sweep
//       --model-out accel/src/cost_model_fit.cpp   (one line)
//
// An ISA whose block is empty (fitted = false) uses the nearest narrower
// fitted set (cost_model()).
#include "simdbvh/accel/cost_model.h"

namespace simdbvh {

namespace {

struct FittedSet {
    bool fitted;
    CostModel model;
};

// Order per set: brute, brute8, bvh2, bvh4, bvh8, bvh16; each {build0, build1, call, ray0, ray1, ray2} in ms
// and build_par (cost_model.h); sets fitted before a term existed leave it 0.
// sweep:scalar:begin
// simdbvh bench --sweep --report out/sweep-scalar --model-out accel/src/cost_model_fit.cpp
// AMD EPYC | 2 cores, 2 threads | L1d 32 KiB, L2 512 KiB, L3 32 MiB | ISAs scalar avx2 (active scalar) | hwloc
constexpr FittedSet kScalar{true,
                            {Isa::scalar,
                             {{{0, 0, 6.86868e-05, 2.21012e-05, 1.39917e-05, 0, 0},
                               {0.000134186, 9.3244e-06, 8.48354e-05, 8.89414e-05, 1.2336e-05, 1.28271e-06, 0},
                               {0.000335605, 3.33524e-05, 0.00010053, 7.61087e-06, 1.88254e-05, 0, 0.7148},
                               {0.00154879, 2.90842e-05, 0.000154071, 3.28005e-05, 2.14559e-05, 0, 0.7148},
                               {0.00158286, 2.83632e-05, 0.000135866, 5.10817e-05, 2.21005e-05, 0, 0.7148},
                               {0.00169461, 2.96327e-05, 0.000132368, 7.18012e-05, 2.27612e-05, 0, 0.7148}}}}};
// sweep:scalar:end
// sweep:avx2:begin
// simdbvh bench --sweep --report out/sweep-avx2 --model-out accel/src/cost_model_fit.cpp
// AMD EPYC | 2 cores, 2 threads | L1d 32 KiB, L2 512 KiB, L3 32 MiB | ISAs scalar avx2 (active avx2) | hwloc
constexpr FittedSet kAvx2{true,
                          {Isa::avx2,
                           {{{0, 0, 0.000131983, 2.76699e-05, 1.58629e-05, 0, 0},
                             {0.00019866, 1.17337e-05, 0.000197067, 7.04835e-05, 8.86162e-07, 1.45303e-07, 0},
                             {0.000198016, 3.55999e-05, 0.00014218, 1.2028e-05, 2.16018e-05, 0, 0.6766},
                             {0.00115623, 3.11595e-05, 0.000161103, 2.71343e-05, 1.35106e-05, 0, 0.6766},
                             {0.00112682, 3.17579e-05, 0.000140287, 3.14188e-05, 1.12947e-05, 0, 0.6766},
                             {0.00105212, 3.3089e-05, 0.00013574, 3.53121e-05, 1.00832e-05, 0, 0.6766}}}}};
// sweep:avx2:end
// sweep:avx512:begin
// simdbvh bench --sweep --report out/sweep --model-out accel/src/cost_model_fit.cpp --readme README.md
// AMD EPYC | 2 cores, 2 threads | L1d 32 KiB, L2 1 MiB, L3 32 MiB | ISAs scalar avx2 avx512 (active avx512) | hwloc
constexpr FittedSet kAvx512{true,
                            {Isa::avx512,
                             {{{0, 0, 6.92479e-05, 2.67561e-05, 1.12518e-05, 0, 0},
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
