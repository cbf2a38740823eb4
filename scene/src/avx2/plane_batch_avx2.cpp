// shapes.h's nearest_planes, avx2 build of plane_batch-inl.h: four doubles per ymm register.
#include "plane_batch-inl.h"

SIMDBVH_PLANE_BATCH_INSTANTIATE(avx2)
