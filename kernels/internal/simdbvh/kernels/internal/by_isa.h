#pragma once
// The one switch on the ISA (docs/architecture.md, "Add an ISA"): by_isa turns
// an Isa into one of three kernel sets and calls f.template operator()<Set>().
// Every batched entry point that dispatches goes through it, so adding an ISA
// is one case here and one kernel set per room.
#include "simdbvh/kernels/isa.h"

namespace simdbvh::kernels::detail {

// Refuses an ISA this processor lacks (require), then runs f with its set.
// Off x86 only the scalar set is built (cmake/SimdbvhIsa.cmake) and require()
// refuses the others, so Avx2 and Avx512 are never instantiated there and may
// be declared only.
template <class Scalar, class Avx2, class Avx512, class F>
decltype(auto) by_isa(Isa isa, F&& f) {
    require(isa);
#if defined(__x86_64__)
    switch (isa) {
    case Isa::avx512: return f.template operator()<Avx512>();
    case Isa::avx2: return f.template operator()<Avx2>();
    case Isa::scalar: break;
    }
#endif
    return f.template operator()<Scalar>();
}

}  // namespace simdbvh::kernels::detail
