// shapes.h's nearest_planes, avx512 build of plane_batch-inl.h: four doubles per ymm register (EVEX encodings).
#include "plane_batch-inl.h"

SIMDBVH_PLANE_BATCH_INSTANTIATE(avx512)
