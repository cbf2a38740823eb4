#pragma once
// The binary stack loop, one for every two-child hierarchy: the BVH2 (box
// node test, traverse.cpp) and the sphere hierarchy (sphere node test,
// spheres.cpp). A loop x a width-2 node test x a leaf intersector (single
// gathered triangles) x a query (query/query.h), as the N-wide loop of
// bvh8/internal/simdbvh/bvh8/internal/traverse-inl.h; one ray at a time, near child first, the closest
// hit so far culls children and stack entries.
//
// NodeTest provides: bool root(PreparedRay, Node, tmax, float* entry) (the
// root's own volume); uint32 children(PreparedRay, const Node* nodes, Node n,
// tmax, float entries[2]) (bit 0: left child n.first hit, bit 1: right child
// n.first + 1); float cull(float t) (the culling distance for a closest hit at t).
// The members may be static; a test with per-ray state (the scene top level's
// box slack) is passed as `test`.
#include <cstdint>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/triangle.h"
#include "simdbvh/kernels/internal/query/query.h"

namespace simdbvh::bvh2 {

#define SIMDBVH_BINARY_INLINE inline __attribute__((always_inline))

struct StackEntry {
    std::uint32_t node;
    float entry;
};
// Children are pushed one at a time, so the stack never holds more entries
// than the tree is deep.
inline constexpr int kStackSize = kMaxDepth + 1;

// Leaf intersector: the leaf's range of the gathered triangles (tris[i] is
// triangle ids[i]), the scalar tests with the closer() tie rule.
template <TriangleTest kTest, bool kStats>
struct TriangleLeaf {
    const TriangleVerts* tris;
    const std::uint32_t* ids;
    SIMDBVH_BINARY_INLINE void closest(const PreparedRay& r, std::uint32_t first, std::uint32_t count, Hit& best,
                                       TraceStats* stats) const {
        for (std::uint32_t i = first, e = first + count; i < e; ++i) {
            const TriangleVerts& tv = tris[i];
            float t, u, v;
            if constexpr (kStats) stats->triangle_tests++;
            if (intersect_triangle<kTest>(r, tv.v0, tv.v1, tv.v2, best.t, &t, &u, &v) && closer(t, ids[i], best))
                best = {t, u, v, ids[i]};
        }
    }
    SIMDBVH_BINARY_INLINE bool any(const PreparedRay& r, std::uint32_t first, std::uint32_t count, Hit& best,
                                   TraceStats* stats) const {
        for (std::uint32_t i = first, e = first + count; i < e; ++i) {
            const TriangleVerts& tv = tris[i];
            float t, u, v;
            if constexpr (kStats) stats->triangle_tests++;
            if (intersect_triangle<kTest>(r, tv.v0, tv.v1, tv.v2, best.t, &t, &u, &v)) {
                best = {t, u, v, ids[i]};
                return true;
            }
        }
        return false;
    }
};

// One ray through a binary hierarchy (nodes: root at 0, children adjacent).
template <class NodeTest, class Query, bool kStats, class Node, class Alloc, class Leaf>
SIMDBVH_BINARY_INLINE Hit traverse_binary(const std::vector<Node, Alloc>& nodes, const Leaf& leaf, const Ray& ray,
                                          TraceStats* stats, const NodeTest& test = NodeTest{}) {
    Hit out;
    const PreparedRay r = prepare(ray);
    if constexpr (kStats) stats->rays++;
    if (!r.valid || nodes.empty()) {
        Query::finish(Hit{}, 0, out);
        return out;
    }
    Hit best;
    best.t = r.tmax;
    StackEntry stack[kStackSize];
    int sp = 0;
    float entry;
    if constexpr (kStats) stats->box_tests++;
    if (!test.root(r, nodes[0], best.t, &entry)) {
        Query::finish(Hit{}, 0, out);
        return out;
    }
    std::uint32_t idx = 0;
    for (;;) {
        const Node& n = nodes[idx];
        if constexpr (kStats) stats->nodes_visited++;
        if (!n.is_leaf()) {
            float e[2];
            const std::uint32_t hit = test.children(r, nodes.data(), n, test.cull(best.t), e);
            if constexpr (kStats) stats->box_tests += 2;
            if (hit == 3u) {  // both: push the far one
                const bool left_first = e[0] <= e[1];
                stack[sp++] = {left_first ? n.first + 1 : n.first, left_first ? e[1] : e[0]};
                idx = left_first ? n.first : n.first + 1;
                continue;
            }
            if (hit != 0u) {
                idx = hit == 1u ? n.first : n.first + 1;
                continue;
            }
        } else if (Query::leaf(leaf, r, n.first, n.count, best, stats)) {
            Query::finish(best, r.t_exp, out);
            return out;
        }
        // Pop the nearest pending node still in front of the closest hit (a
        // NaN entry, possible for spheres, is kept: the test is conservative).
        for (;;) {
            if (sp == 0) {
                Query::finish(best, r.t_exp, out);
                return out;
            }
            const StackEntry& s = stack[--sp];
            if (!(s.entry > test.cull(best.t))) {
                idx = s.node;
                break;
            }
        }
    }
}

#undef SIMDBVH_BINARY_INLINE

}  // namespace simdbvh::bvh2
