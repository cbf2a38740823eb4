// Wide traversal of sphere and box sets (N = 4, 8, 16), avx2 build of
// shape_traverse-inl.h: AVX2 + FMA: node tests of 4 (xmm), 8 (ymm) and 16 (two ymm) lanes.
#include "simdbvh/bvh8/internal/avx2/kernels_avx2.h"  // bvh8/src
#include "shape_traverse-inl.h"

SIMDBVH_SHAPE_INSTANTIATE(avx2)
