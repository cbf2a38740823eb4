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
constexpr FittedSet kAvx512{true, {Isa::avx512, {{{0, 0, 0.001, 2e-5, 2e-5}, {0.001, 5e-6, 0.001, 2e-5, 3e-6},
                                                 {0.01, 1e-4, 0.001, 1e-4, 1e-4}, {0.01, 1.2e-4, 0.001, 1e-4, 6e-5},
                                                 {0.01, 1.2e-4, 0.001, 1e-4, 5e-5}, {0.01, 1.3e-4, 0.001, 1e-4, 5e-5}}}}};
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
