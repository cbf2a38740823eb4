// Wide traversal of sphere and box sets (N = 4, 8, 16), avx512 build of
// shape_traverse-inl.h: AVX-512: node tests of 4 (xmm), 8 (ymm) and 16 (one zmm) lanes.
#include "simdbvh/bvh8/internal/avx512/kernels_avx512.h"  // bvh8/src
#include "shape_traverse-inl.h"

SIMDBVH_SHAPE_INSTANTIATE(avx512)
