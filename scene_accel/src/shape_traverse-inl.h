#pragma once
// The wide traversal of sphere and box sets: the wide BVH's batch loop
// (bvh8/src/traverse-inl.h: rays in flight, the N-wide SIMD node test of the
// ISA, front-to-back order, culling) with a leaf intersector that tests a
// leaf's gathered primitives one at a time through shapes.h's tests (the
// same functions, compiled once without ISA flags, that the brute force
// calls, so every ISA gets the same bits); sphere leaves first drop, four at
// a time, the spheres hit_sphere would reject at its discriminant. Included only by the per-ISA
// translation units (src/scalar, src/avx2, src/avx512).
#include <cstring>
#include <type_traits>

#include "scene_trace-inl.h"
#include "shape_traverse.h"
#include "traverse-inl.h"  // bvh8/src

namespace simdbvh::scene_accel {

// The next node's lines, or the leaf's first primitives.
template <int N, class Prim>
inline __attribute__((always_inline)) void prefetch_shape_child(const NodeN<N>* nodes, const Prim* prims,
                                                                ChildN<N> c) {
    if (c.is_inner()) {
        const char* p = reinterpret_cast<const char*>(nodes + c.index);
        for (std::size_t l = 0; l < sizeof(NodeN<N>) / 64; ++l) __builtin_prefetch(p + 64 * l);
    } else {
        __builtin_prefetch(prims + c.index);
    }
}

// Spheres, four at a time: the discriminant of hit_sphere (shapes.cpp) for
// four spheres in one pass of double-precision vector arithmetic, the same
// operations in the same order (the build has -ffp-contract=off: no fused
// multiply-add here or there), so each lane's value is the bits hit_sphere
// computes. Lanes whose discriminant is negative or NaN are exactly the
// spheres hit_sphere rejects at its first test; the others go to hit_sphere
// itself, in the leaf's order, so `best` evolves as in ShapeLeaf's loop.
// Returns the candidates: bit k for sphere k (bits >= count are 0).
typedef double Double4 __attribute__((vector_size(32)));
typedef float Float4 __attribute__((vector_size(16)));
inline __attribute__((always_inline)) std::uint32_t sphere_candidates(const PreparedRay& r, const Sphere* sp,
                                                                      std::uint32_t count) {
    // Four spheres (x y z r each; lanes >= count repeat the first) transposed to x4 y4 z4 r4.
    Float4 s0, s1, s2, s3;
    std::memcpy(&s0, &sp[0], 16);
    std::memcpy(&s1, &sp[count > 1 ? 1 : 0], 16);
    std::memcpy(&s2, &sp[count > 2 ? 2 : 0], 16);
    std::memcpy(&s3, &sp[count > 3 ? 3 : 0], 16);
    const Float4 t0 = __builtin_shufflevector(s0, s1, 0, 4, 1, 5), t1 = __builtin_shufflevector(s2, s3, 0, 4, 1, 5);
    const Float4 t2 = __builtin_shufflevector(s0, s1, 2, 6, 3, 7), t3 = __builtin_shufflevector(s2, s3, 2, 6, 3, 7);
    const Double4 cx = __builtin_convertvector(__builtin_shufflevector(t0, t1, 0, 1, 4, 5), Double4);
    const Double4 cy = __builtin_convertvector(__builtin_shufflevector(t0, t1, 2, 3, 6, 7), Double4);
    const Double4 cz = __builtin_convertvector(__builtin_shufflevector(t2, t3, 0, 1, 4, 5), Double4);
    const Double4 cr = __builtin_convertvector(__builtin_shufflevector(t2, t3, 2, 3, 6, 7), Double4);
    const double dx = r.dir.x, dy = r.dir.y, dz = r.dir.z;
    const double a = dx * dx + dy * dy + dz * dz;
    const Double4 fx = double(r.org.x) - cx, fy = double(r.org.y) - cy, fz = double(r.org.z) - cz;
    const Double4 b = -(fx * dx + fy * dy + fz * dz);
    const Double4 rr = cr * cr;
    const Double4 tc = b / a;
    const Double4 lx = fx + tc * dx, ly = fy + tc * dy, lz = fz + tc * dz;
    const Double4 disc = rr - (lx * lx + ly * ly + lz * lz);
    std::uint32_t m = 0;
    for (std::uint32_t k = 0; k < 4; ++k) m |= std::uint32_t(disc[k] >= 0.0 && k < count) << k;
    return m;
}

// Leaf intersector of a ShapeTree: the leaf s.cur is s.cur.blocks()
// primitives from prims[s.cur.index], tested in order with the ray's
// PreparedRay through shapes.h (hit_prim); spheres four at a time first
// through sphere_candidates(), which drops exactly those hit_sphere rejects
// at its discriminant.
template <class Prim>
struct WideShapeLeaf {
    using Keep = PreparedRay;
    ShapeLeaf<Prim> leaf;
    // kAny: true at the first hit (written to best), else best shrinks.
    template <bool kAny, class State>
    inline __attribute__((always_inline)) bool visit(const State& s, Hit& best) const {
        const std::uint32_t first = s.cur.index, count = s.cur.blocks();
        for (std::uint32_t g = 0; g < count; g += 4) {
            const std::uint32_t n = count - g < 4 ? count - g : 4;
            std::uint32_t m = (1u << n) - 1;
            if constexpr (std::is_same_v<Prim, Sphere>) m = sphere_candidates(s.pr, leaf.prims + first + g, n);
            for (; m != 0; m &= m - 1) {
                const std::uint32_t i = first + g + std::uint32_t(__builtin_ctz(m));
                float t, u, v;
                if (!hit_prim(s.pr, leaf.prims[i], best.t, &t, &u, &v)) continue;
                if constexpr (kAny) {
                    best = {t, u, v, leaf.id(i)};
                    return true;
                } else if (closer(t, leaf.id(i), best)) {
                    best = {t, u, v, leaf.id(i)};
                }
            }
        }
        return false;
    }
    template <class State>
    inline __attribute__((always_inline)) void closest(const State& s, Hit& best, TraceStats*) const {
        visit<false>(s, best);
    }
    template <class State>
    inline __attribute__((always_inline)) bool any(const State& s, Hit& best, TraceStats*) const {
        return visit<true>(s, best);
    }
    template <int N>
    inline __attribute__((always_inline)) void prefetch(const NodeN<N>* nodes, ChildN<N> c) const {
        prefetch_shape_child(nodes, leaf.prims, c);
    }
};

// Rays in flight by the tree's size (nodes, primitives, ids), as the meshes'
// (bvh8::detail::one_in_flight, with the measurements).
template <class K, int N, class Prim, class Query>
inline __attribute__((always_inline)) void trace_shapes(const ShapeTree<N>& tree, const Prim* prims,
                                                        const Aabb& bounds, std::span<const Ray> rays,
                                                        std::span<Hit> hits) {
    const WideShapeLeaf<Prim> leaf{{prims, tree.prim_ids.data()}};
    const Aabb* root = tree.nodes.empty() ? nullptr : &bounds;
    const std::size_t bytes =
        tree.nodes.size() * sizeof(NodeN<N>) + tree.prim_ids.size() * (sizeof(Prim) + sizeof(std::uint32_t));
    using bvh8::detail::trace_span;
    if (bvh8::detail::one_in_flight(bytes, 0))
        trace_span<K, N, WideShapeLeaf<Prim>, Query, false, 1>(tree.nodes.data(), root, leaf, rays, hits, nullptr);
    else
        trace_span<K, N, WideShapeLeaf<Prim>, Query, false>(tree.nodes.data(), root, leaf, rays, hits, nullptr);
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
