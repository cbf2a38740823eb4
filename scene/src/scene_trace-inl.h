#pragma once
// Internal: the parts of a scene trace shared by the accelerated traversal
// (traverse.cpp) and the brute force (brute_force.cpp), so both run the same
// arithmetic: the box node test of the binary hierarchies (with the top
// level's per-ray slack), the leaf intersector of sphere and box sets, the
// planes, and the ray a bottom level sees.
#include <cmath>
#include <cstdint>
#include <limits>

#include "simdbvh/kernels/box.h"
#include "simdbvh/scene/scene.h"
#include "simdbvh/kernels/internal/query/query.h"
#include "shape_traverse.h"
#include "simdbvh/bvh8/internal/traverse.h"  // bvh8/src: the per-ISA wide traversals

namespace simdbvh::scene::detail {

#define SIMDBVH_SCENE_INLINE inline __attribute__((always_inline))

// The tmax a ray gets from a closest hit found so far at caller's t `t` (a
// plane's, another instance's), so that every hit whose t rounds to `t` is
// still found and the tie goes to the lower id as in the brute force, which
// traces each instance with the ray's own tmax. A traversal compares t in
// its prepared ray's scale (PreparedRay::t_exp), which is exact for a normal
// t; a subnormal or zero t (a ray with a direction near 1e38) is coarser
// than that scale, so a hit a little beyond it there can round to it: the
// next float up keeps those (and a hit that rounds above `t` loses to it).
SIMDBVH_SCENE_INLINE float tmax_keeping_ties(float t) {
    return std::fabs(t) < std::numeric_limits<float>::min() ? std::nextafter(t, INFINITY) : t;
}

// Width-2 box test (Ize 2013, as the BVH2's) with every box grown by `slack`
// world units (0 for bottom levels).
struct SlackBox2Test {
    float slack = 0.0f;
    SIMDBVH_SCENE_INLINE Aabb grow(const Aabb& b) const {
        if (slack == 0.0f) return b;
        return {{b.lo.x - slack, b.lo.y - slack, b.lo.z - slack}, {b.hi.x + slack, b.hi.y + slack, b.hi.z + slack}};
    }
    SIMDBVH_SCENE_INLINE bool root(const PreparedRay& r, const Node2& n, float tmax, float* entry) const {
        return intersect_box(r, grow(n.box), tmax, entry);
    }
    SIMDBVH_SCENE_INLINE std::uint32_t children(const PreparedRay& r, const Node2* nodes, const Node2& n, float tmax,
                                                float* e) const {
        const bool ha = intersect_box(r, grow(nodes[n.first].box), tmax, &e[0]);
        const bool hb = intersect_box(r, grow(nodes[n.first + 1].box), tmax, &e[1]);
        return std::uint32_t(ha) | (std::uint32_t(hb) << 1);
    }
    SIMDBVH_SCENE_INLINE float cull(float t) const { return cull_bound(t); }
};

SIMDBVH_SCENE_INLINE bool hit_prim(const PreparedRay& r, const Sphere& s, float tmax, float* t, float* u, float* v) {
    return hit_sphere(r, s, tmax, t, u, v);
}
SIMDBVH_SCENE_INLINE bool hit_prim(const PreparedRay& r, const Aabb& b, float tmax, float* t, float* u, float* v) {
    return hit_box(r, b, tmax, t, u, v);
}

// Leaf intersector over gathered analytic primitives (prims[i] is primitive
// ids[i]; ids == nullptr: the identity), with Hit's closer() tie rule.
template <class Prim>
struct ShapeLeaf {
    const Prim* prims;
    const std::uint32_t* ids;
    SIMDBVH_SCENE_INLINE std::uint32_t id(std::uint32_t i) const { return ids ? ids[i] : i; }
    SIMDBVH_SCENE_INLINE void closest(const PreparedRay& r, std::uint32_t first, std::uint32_t count, Hit& best,
                                      TraceStats*) const {
        for (std::uint32_t i = first, e = first + count; i < e; ++i) {
            float t, u, v;
            if (hit_prim(r, prims[i], best.t, &t, &u, &v) && closer(t, id(i), best)) best = {t, u, v, id(i)};
        }
    }
    SIMDBVH_SCENE_INLINE bool any(const PreparedRay& r, std::uint32_t first, std::uint32_t count, Hit& best,
                                  TraceStats*) const {
        for (std::uint32_t i = first, e = first + count; i < e; ++i) {
            float t, u, v;
            if (hit_prim(r, prims[i], best.t, &t, &u, &v)) {
                best = {t, u, v, id(i)};
                return true;
            }
        }
        return false;
    }
};

// The planes' closest hit for a prepared world ray, as a SceneHit in the
// caller's parameter (plane k: inst = first_inst + k, prim = k). Any hit: the first.
template <bool kAnyHit>
SceneHit trace_planes(const std::vector<Plane>& planes, const PreparedRay& r, std::uint32_t first_inst) {
    SceneHit best;
    float t;
    const int k = nearest_plane(r, planes, r.tmax, kAnyHit, &t);
    if (k >= 0)
        best = SceneHit{to_caller_t(r, t), 0.0f, 0.0f, std::uint32_t(k), kNoGeometry, first_inst + std::uint32_t(k)};
    return best;
}

// The per-ISA wide traversal of a bottom-level mesh, chosen once per batch.
template <int N>
using WideFn = void (*)(const BvhN<N>&, std::span<const Ray>, std::span<Hit>, const TraceOptions&);

template <int N, bool kAnyHit>
WideFn<N> wide_fn(Isa isa) {
    return bvh8::with_kernels(isa, [&]<class K>() -> WideFn<N> {
        return kAnyHit ? &bvh8::Traversal<K, N>::occluded : &bvh8::Traversal<K, N>::intersect;
    });
}

// The per-ISA wide traversal of a sphere or box set, chosen once per batch.
template <int N, class Prim>
using ShapeFn = void (*)(const ShapeTree<N>&, const Prim*, const Aabb&, std::span<const Ray>, std::span<Hit>);

template <int N, class Prim, bool kAnyHit>
ShapeFn<N, Prim> shape_fn(Isa isa) {
    return bvh8::with_kernels(isa, [&]<class K>() -> ShapeFn<N, Prim> {
        return kAnyHit ? &ShapeTraversal<K, N, Prim>::occluded : &ShapeTraversal<K, N, Prim>::intersect;
    });
}

#undef SIMDBVH_SCENE_INLINE

}  // namespace simdbvh::scene::detail
