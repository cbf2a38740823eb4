#pragma once
// Internal, ISA-neutral: the query policies every traversal loop takes (the
// N-wide loop of bvh8/internal/simdbvh/bvh8/internal/traverse-inl.h, the binary loop of
// bvh2/internal/simdbvh/bvh2/internal/traverse_binary-inl.h). A query says what a leaf does to the ray
// (the leaf intersector shrinks the closest hit, or stops at the first hit)
// and finish() is the one place a ray's Hit is written (a miss: Hit{}).
// madmann91/bvh v2 passes the same choice as traverse_top_down<IsAnyHit>.
#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/ray.h"

namespace simdbvh::query {

#define SIMDBVH_QUERY_INLINE inline __attribute__((always_inline))

struct QueryBase {
    // `best` is the ray's state: best.t is the current tmax, best.prim kInvalidPrim until a hit. A hit's t
    // is mapped back to the caller's direction scale (PreparedRay::t_exp, ray.h's to_caller).
    static SIMDBVH_QUERY_INLINE void finish(const Hit& best, int t_exp, Hit& out) {
        out = best.hit() ? to_caller(t_exp, best) : Hit{};
    }
};

// Closest hit: the leaf shrinks `best`; the ray ends when no node is left.
struct ClosestHit : QueryBase {
    static constexpr bool kAnyHit = false;
    template <class Leaf, class... Args>
    static SIMDBVH_QUERY_INLINE bool leaf(const Leaf& l, Args&&... args) {
        l.closest(static_cast<Args&&>(args)...);
        return false;
    }
};

// Any hit: the ray ends at the leaf's first hit (written to `best`).
struct AnyHit : QueryBase {
    static constexpr bool kAnyHit = true;
    template <class Leaf, class... Args>
    static SIMDBVH_QUERY_INLINE bool leaf(const Leaf& l, Args&&... args) {
        return l.any(static_cast<Args&&>(args)...);
    }
};

#undef SIMDBVH_QUERY_INLINE

}  // namespace simdbvh::query
