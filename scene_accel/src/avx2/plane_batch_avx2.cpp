// shapes.h's nearest_planes, avx2 build of plane_batch-inl.h: four doubles per ymm register.
#include "plane_batch-inl.h"

namespace simdbvh::scene_accel {
namespace avx2 {
struct PlaneTag {};
}  // namespace avx2
template struct PlaneBatch<avx2::PlaneTag>;
}  // namespace simdbvh::scene_accel
