// shapes.h's nearest_planes, avx512 build of plane_batch-inl.h: four doubles per ymm register (EVEX encodings).
#include "plane_batch-inl.h"

namespace simdbvh::scene_accel {
namespace avx512 {
struct PlaneTag {};
}  // namespace avx512
template struct PlaneBatch<avx512::PlaneTag>;
}  // namespace simdbvh::scene_accel
