#pragma once
// Internal: the per-ISA wide traversals of sphere and box sets (ShapeTree).
// ShapeTraversal<K, N, Prim> is defined once (shape_traverse-inl.h) and
// instantiated per ISA in src/scalar, src/avx2 and src/avx512, each with the
// wide BVH's kernels of its ISA (bvh8/src/<isa>/kernels_<isa>.h);
// shape_fn() (scene_trace-inl.h) is the one switch on the ISA.
#include <span>

#include "simdbvh/scene/scene.h"
#include "simdbvh/bvh8/internal/traverse.h"  // bvh8/src: the ISA kernel types

namespace simdbvh::scene::detail {

// Hits in the bottom level's own parameter (as BvhN's traversal): primitive
// ids are the set's, u and v those of shapes.h.
template <class K, int N, class Prim>
struct ShapeTraversal {
    [[gnu::flatten]] static void intersect(const ShapeTree<N>& tree, const Prim* prims, const Aabb& bounds,
                                           std::span<const Ray> rays, std::span<Hit> hits);
    [[gnu::flatten]] static void occluded(const ShapeTree<N>& tree, const Prim* prims, const Aabb& bounds,
                                          std::span<const Ray> rays, std::span<Hit> hits);
};

#define SIMDBVH_SHAPE_ISA(isa)                                             \
    extern template struct ShapeTraversal<bvh8::isa::Kernels, 4, Sphere>;  \
    extern template struct ShapeTraversal<bvh8::isa::Kernels, 8, Sphere>;  \
    extern template struct ShapeTraversal<bvh8::isa::Kernels, 16, Sphere>; \
    extern template struct ShapeTraversal<bvh8::isa::Kernels, 4, Aabb>;    \
    extern template struct ShapeTraversal<bvh8::isa::Kernels, 8, Aabb>;    \
    extern template struct ShapeTraversal<bvh8::isa::Kernels, 16, Aabb>;
SIMDBVH_SHAPE_ISA(scalar)
#if defined(__x86_64__)
SIMDBVH_SHAPE_ISA(avx2)
SIMDBVH_SHAPE_ISA(avx512)
#endif
#undef SIMDBVH_SHAPE_ISA

}  // namespace simdbvh::scene::detail
