#pragma once
// The wide traversal of sphere and box sets: the wide BVH's batch loop
// (bvh8/src/traverse-inl.h: rays in flight, the N-wide SIMD node test of the
// ISA, front-to-back order, culling) with a leaf intersector that tests a
// leaf's gathered primitives one at a time through shapes.h's tests (the
// same functions, compiled once without ISA flags, that the brute force
// calls, so every ISA gets the same bits). Included only by the per-ISA
// translation units (src/scalar, src/avx2, src/avx512).
#include "scene_trace-inl.h"
#include "shape_traverse.h"
#include "traverse-inl.h"  // bvh8/src

namespace simdbvh::scene_accel {

// Leaf intersector of a ShapeTree: the leaf s.cur is s.cur.blocks()
// primitives from prims[s.cur.index], tested with the ray's PreparedRay.
template <class Prim>
struct WideShapeLeaf {
    using Keep = PreparedRay;
    ShapeLeaf<Prim> leaf;
    template <class State>
    inline __attribute__((always_inline)) void closest(const State& s, Hit& best, TraceStats* stats) const {
        leaf.closest(s.pr, s.cur.index, s.cur.blocks(), best, stats);
    }
    template <class State>
    inline __attribute__((always_inline)) bool any(const State& s, Hit& best, TraceStats* stats) const {
        return leaf.any(s.pr, s.cur.index, s.cur.blocks(), best, stats);
    }
    // The next node's lines, or the leaf's first primitives.
    template <int N>
    inline __attribute__((always_inline)) void prefetch(const NodeN<N>* nodes, ChildN<N> c) const {
        if (c.is_inner()) {
            const char* p = reinterpret_cast<const char*>(nodes + c.index);
            for (std::size_t l = 0; l < sizeof(NodeN<N>) / 64; ++l) __builtin_prefetch(p + 64 * l);
        } else {
            __builtin_prefetch(leaf.prims + c.index);
        }
    }
};

template <class K, int N, class Prim, class Query>
inline __attribute__((always_inline)) void trace_shapes(const ShapeTree<N>& tree, const Prim* prims,
                                                        const Aabb& bounds, std::span<const Ray> rays,
                                                        std::span<Hit> hits) {
    const WideShapeLeaf<Prim> leaf{{prims, tree.prim_ids.data()}};
    bvh8::detail::trace_span<K, N, WideShapeLeaf<Prim>, Query, false>(
        tree.nodes.data(), tree.nodes.empty() ? nullptr : &bounds, leaf, rays, hits, nullptr);
}

template <class K, int N, class Prim>
void ShapeTraversal<K, N, Prim>::intersect(const ShapeTree<N>& tree, const Prim* prims, const Aabb& bounds,
                                           std::span<const Ray> rays, std::span<Hit> hits) {
    trace_shapes<K, N, Prim, query::ClosestHit>(tree, prims, bounds, rays, hits);
}
template <class K, int N, class Prim>
void ShapeTraversal<K, N, Prim>::occluded(const ShapeTree<N>& tree, const Prim* prims, const Aabb& bounds,
                                          std::span<const Ray> rays, std::span<Hit> hits) {
    trace_shapes<K, N, Prim, query::AnyHit>(tree, prims, bounds, rays, hits);
}

}  // namespace simdbvh::scene_accel

#define SIMDBVH_SHAPE_INSTANTIATE(isa)                                                        \
    namespace simdbvh::scene_accel {                                                          \
    template struct ShapeTraversal<bvh8::isa::Kernels, 4, Sphere>;                            \
    template struct ShapeTraversal<bvh8::isa::Kernels, 8, Sphere>;                            \
    template struct ShapeTraversal<bvh8::isa::Kernels, 16, Sphere>;                           \
    template struct ShapeTraversal<bvh8::isa::Kernels, 4, Aabb>;                              \
    template struct ShapeTraversal<bvh8::isa::Kernels, 8, Aabb>;                              \
    template struct ShapeTraversal<bvh8::isa::Kernels, 16, Aabb>;                             \
    }
