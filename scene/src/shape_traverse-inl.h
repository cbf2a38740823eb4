#pragma once
// The wide traversal of sphere and box sets: the wide BVH's batch loop
// (bvh8/internal/simdbvh/bvh8/internal/traverse-inl.h: rays in flight, the N-wide SIMD node test of the
// ISA, front-to-back order, culling) with a leaf intersector for gathered
// primitives: boxes one at a time through shapes.h's hit_box (compiled once
// without ISA flags, the function the brute force calls), spheres four at a
// time through hit_sphere's own arithmetic in vector lanes (sphere_roots), so
// every ISA gets the brute force's bits. Included only by the per-ISA
// translation units (src/scalar, src/avx2, src/avx512).
#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <cstring>
#include <limits>
#include <type_traits>

#include "scene_trace-inl.h"
#include "shape_traverse.h"
#include "sphere_uv.h"
#include "simdbvh/kernels/internal/simd/sse2.h"
#include "simdbvh/bvh8/internal/traverse-inl.h"  // bvh8/src

namespace simdbvh::scene::detail {

// The next node's lines, or the leaf's first primitives.
template <int N, class Prim>
inline __attribute__((always_inline)) void prefetch_shape_child(const NodeN<N>* nodes, const Prim* prims, ChildN<N> c) {
    if (c.is_inner()) {
        const char* p = reinterpret_cast<const char*>(nodes + c.index);
        for (std::size_t l = 0; l < sizeof(NodeN<N>) / 64; ++l) __builtin_prefetch(p + 64 * l);
    } else {
        __builtin_prefetch(prims + c.index);
    }
}

// Spheres, four at a time: hit_sphere (shapes.cpp) for four spheres in one
// pass of double-precision vector arithmetic, up to the choice of root: the
// discriminant, c, q and both roots with the same operations in the same
// order (the build has -ffp-contract=off: no fused multiply-add here or
// there; division and square root are correctly rounded in every lane), so
// each lane holds the bits hit_sphere computes. Each lane then takes
// hit_sphere's root for `tmax`: the nearer root whose float is in [tmin,
// tmax], else the farther one, else none.
//
// One tmax for the four, where hit_sphere in a loop sees the closest hit so
// far: a root chosen under the larger tmax but beyond the current closest hit
// is one the loop would reject (the farther root is no nearer) and that
// closer() rejects here; a root within it is the loop's own. So the leaf below
// gives the loop's hits bit for bit, and computes u, v (sphere_uv, the
// function hit_sphere calls) only for the hits it keeps.
typedef double Double4 __attribute__((vector_size(32)));
typedef double Double2 __attribute__((vector_size(16)));
typedef float Float4 __attribute__((vector_size(16)));
typedef long long Long4 __attribute__((vector_size(32)));
typedef int Int4 __attribute__((vector_size(16)));

struct SphereRoots {
    std::uint32_t mask;  // bit k: sphere k has a root in [tmin, tmax]
    float t[4];          // its float (the hit's t)
    double th[4];        // the root itself (for u, v)
};

// (Results through references: a 32-byte vector returned by value changes
// the ABI where AVX is off, the scalar translation unit.)
inline __attribute__((always_inline)) void sqrt4(const Double4& x, Double4& out) {
#if defined(__AVX__)
    out = (Double4)_mm256_sqrt_pd((__m256d)x);
#else
    const Double2 lo = (Double2)_mm_sqrt_pd((__m128d)Double2{x[0], x[1]});
    const Double2 hi = (Double2)_mm_sqrt_pd((__m128d)Double2{x[2], x[3]});
    out = Double4{lo[0], lo[1], hi[0], hi[1]};
#endif
}
// out = the lanes of a where m (all ones or zero per lane), else b's.
inline __attribute__((always_inline)) void select4(const Long4& m, const Double4& a, const Double4& b, Double4& out) {
    out = Double4((Long4(a) & m) | (Long4(b) & ~m));
}

inline __attribute__((always_inline)) SphereRoots sphere_roots(const PreparedRay& r, const Sphere* sp,
                                                               std::uint32_t count, float tmax) {
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
    const Long4 candidate = disc >= 0.0;  // false for NaN
    SphereRoots out;
    out.mask = 0;
    std::uint32_t any = 0;
    for (std::uint32_t k = 0; k < 4; ++k) any |= std::uint32_t(candidate[k] != 0 && k < count) << k;
    if (any == 0) return out;  // most leaves a ray visits: no square root, no division more
    const Double4 c = (fx * fx + fy * fy + fz * fz) - rr;
    const Long4 sign = Long4(b) & (Long4{} + std::numeric_limits<long long>::min());
    Double4 root;
    sqrt4(a * disc, root);
    const Double4 q = b + Double4((Long4(root) & ~sign) | sign);  // copysign(sqrt, b): sqrt's sign bit is clear
    // Lanes without a candidate may divide by zero; their results are dropped.
    Double4 r0, near, far;
    select4(q != 0.0, c / q, Double4{}, r0);
    const Double4 r1 = q / a;
    const Long4 swap = r0 > r1;
    select4(swap, r1, r0, near);
    select4(swap, r0, r1, far);
    const Float4 f0 = __builtin_convertvector(near, Float4), f1 = __builtin_convertvector(far, Float4);
    const Int4 in0 = (f0 >= r.tmin) & (f0 <= tmax), in1 = (f1 >= r.tmin) & (f1 <= tmax);  // false for NaN
    for (std::uint32_t k = 0; k < 4; ++k) {
        const bool hit = (any >> k & 1u) != 0 && (in0[k] != 0 || in1[k] != 0);
        out.mask |= std::uint32_t(hit) << k;
        out.t[k] = in0[k] != 0 ? f0[k] : f1[k];
        out.th[k] = in0[k] != 0 ? near[k] : far[k];
    }
    return out;
}

// Leaf intersector of a ShapeTree: the leaf s.cur is s.cur.blocks()
// primitives from prims[s.cur.index], tested in order with the ray's
// PreparedRay: spheres four at a time through sphere_roots(), boxes one at a
// time through shapes.h's hit_box; the hits are those of ShapeLeaf's loop
// (scene_trace-inl.h, the brute force's), bit for bit.
template <class Prim>
struct WideShapeLeaf {
    using Keep = PreparedRay;
    static constexpr bool kShared = false;  // every leaf owns its primitives
    ShapeLeaf<Prim> leaf;
    // kAny: true at the first hit (written to best), else best shrinks.
    template <bool kAny, class State>
    inline __attribute__((always_inline)) bool visit(const State& s, Hit& best) const {
        const std::uint32_t first = s.cur.index, count = s.cur.blocks();
        for (std::uint32_t g = 0; g < count; g += 4) {
            const std::uint32_t n = count - g < 4 ? count - g : 4;
            if constexpr (std::is_same_v<Prim, Sphere>) {
                const SphereRoots h = sphere_roots(s.pr, leaf.prims + first + g, n, best.t);
                for (std::uint32_t m = h.mask; m != 0; m &= m - 1) {
                    const std::uint32_t k = std::uint32_t(__builtin_ctz(m)), i = first + g + k;
                    if (kAny || closer(h.t[k], leaf.id(i), best)) {
                        float u, v;
                        sphere_uv(s.pr, leaf.prims[i], h.th[k], &u, &v);
                        best = {h.t[k], u, v, leaf.id(i)};
                        if constexpr (kAny) return true;
                    }
                }
            } else {
                for (std::uint32_t i = first + g, e = first + g + n; i < e; ++i) {
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
inline __attribute__((always_inline)) void trace_shapes(const ShapeTree<N>& tree, const Prim* prims, const Aabb& bounds,
                                                        std::span<const Ray> rays, std::span<Hit> hits) {
    const WideShapeLeaf<Prim> leaf{{prims, tree.prim_ids.data()}};
    const Aabb* root = tree.nodes.empty() ? nullptr : &bounds;
    const std::size_t bytes =
        tree.nodes.size() * sizeof(NodeN<N>) + tree.prim_ids.size() * (sizeof(Prim) + sizeof(std::uint32_t));
    using bvh8::detail::trace_span;
    if (bvh8::detail::one_in_flight(bytes, 0))
        trace_span<K, N, WideShapeLeaf<Prim>, Query, false, 1>(tree.nodes.data(), root, leaf, rays, hits, nullptr);
    else trace_span<K, N, WideShapeLeaf<Prim>, Query, false>(tree.nodes.data(), root, leaf, rays, hits, nullptr);
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

}  // namespace simdbvh::scene::detail

#define SIMDBVH_SHAPE_INSTANTIATE(isa)                              \
    namespace simdbvh::scene::detail {                              \
    template struct ShapeTraversal<bvh8::isa::Kernels, 4, Sphere>;  \
    template struct ShapeTraversal<bvh8::isa::Kernels, 8, Sphere>;  \
    template struct ShapeTraversal<bvh8::isa::Kernels, 16, Sphere>; \
    template struct ShapeTraversal<bvh8::isa::Kernels, 4, Aabb>;    \
    template struct ShapeTraversal<bvh8::isa::Kernels, 8, Aabb>;    \
    template struct ShapeTraversal<bvh8::isa::Kernels, 16, Aabb>;   \
    }
