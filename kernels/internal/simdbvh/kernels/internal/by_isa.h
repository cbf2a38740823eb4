#pragma once
// The one switch on the ISA (docs/architecture.md, "Add an ISA"): by_isa turns
// an Isa into one of three kernel sets and calls f.template operator()<Set>().
// Every batched entry point that dispatches goes through it, so adding an ISA
// is one case here and one kernel set per room.
#include "simdbvh/kernels/isa.h"

namespace simdbvh::kernels::detail {

// Refuses an ISA this processor lacks (require), then runs f with its set.
// Off x86 the three sets are one (the avx2 and avx512 names alias scalar).
template <class Scalar, class Avx2, class Avx512, class F>
decltype(auto) by_isa(Isa isa, F&& f) {
    require(isa);
    switch (isa) {
    case Isa::avx512: return f.template operator()<Avx512>();
    case Isa::avx2: return f.template operator()<Avx2>();
    case Isa::scalar: break;
    }
    return f.template operator()<Scalar>();
}

}  // namespace simdbvh::kernels::detail
