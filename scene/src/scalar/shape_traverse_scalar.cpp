// Wide traversal of sphere and box sets (N = 4, 8, 16), scalar build of
// shape_traverse-inl.h: baseline x86-64 (no AVX, no xsimd): the scalar node test, one lane at a time.
#include "simdbvh/bvh8/internal/scalar/kernels_scalar.h"  // bvh8/src
#include "shape_traverse-inl.h"

SIMDBVH_SHAPE_INSTANTIATE(scalar)
