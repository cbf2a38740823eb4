#pragma once
// Internal: the SIMD forms of shapes.h's nearest_planes. PlaneBatch<Tag> is
// defined once (plane_batch-inl.h, GCC vector types: four rays per vector of
// doubles) and instantiated in src/avx2 and src/avx512 with each ISA's flags;
// nearest_planes (shapes.cpp) is the one switch on the ISA, and its scalar
// ISA calls nearest_plane per ray.
#include <span>

#include "simdbvh/scene/shapes.h"

namespace simdbvh::scene::detail {

namespace avx2 {
struct PlaneTag;
}
namespace avx512 {
struct PlaneTag;
}

template <class Tag>
struct PlaneBatch {
    [[gnu::flatten]] static void nearest(std::span<const Ray> rays, std::span<const Plane> planes, bool any, int* plane,
                                         float* t);
};
#if defined(__x86_64__)
extern template struct PlaneBatch<avx2::PlaneTag>;
extern template struct PlaneBatch<avx512::PlaneTag>;
#endif

}  // namespace simdbvh::scene::detail
