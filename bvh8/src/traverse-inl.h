#pragma once
// BVH8 single-ray stack traversal, templated on the 8-wide kernels K (the
// scalar reference loops in scalar/, xsimd in avx2/ and avx512/). Included
// only by the per-ISA translation units; everything here is a template on K so
// no ISA-encoded copy can be shared between them.
//
// K provides: RayData pack(PreparedRay); uint32 box8(RayData, Box8, tmax,
// float entries[8]) (hit mask, entry distances); closest<Test>(RayData, Tri8,
// Hit& best); bool any<Test>(RayData, Tri8, tmax, Hit&).
//
// Counters (TraceOptions::stats): nodes_visited = Node8s visited; box_tests
// and triangle_tests count SIMD lanes, 8 per Node8 test and 8 per Tri8 block
// (empty slots and lanes included).
#include <cstdint>
#include <span>

#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/kernels/error.h"

namespace simdbvh::bvh8::detail {

// At most 7 entries are pushed per level: 1 + 7 * depth (depth <= kMaxDepth, checked at build).
inline constexpr int kStackSize = 1 + 7 * kMaxDepth;

// No default member initializers: the stack must stay uninitialized (it is
// large, and zero-filling it per ray cost a quarter of the traversal time).
struct StackEntry {
    std::uint32_t index, count;  // Child8
    float entry;
};

// Prefetch a child's lines (a Node8: 4 lines; a leaf: its first Tri8 block,
// 320 bytes at 32-byte alignment: up to 6 lines) as soon as its box is hit, so the misses of the children that are
// pushed overlap the traversal of the nearer subtree.
inline __attribute__((always_inline)) void prefetch_child(const Node8* nodes, const Tri8* blocks, Child8 c) {
    const char* p = c.count == 0 ? reinterpret_cast<const char*>(nodes + c.index)
                                 : reinterpret_cast<const char*>(blocks + c.index);
    __builtin_prefetch(p);
    __builtin_prefetch(p + 64);
    __builtin_prefetch(p + 128);
    __builtin_prefetch(p + 192);
    if (c.count != 0) {
        __builtin_prefetch(p + 256);
        __builtin_prefetch(p + 319);
    }
}

template <class K, TriangleTest kTest, bool kAnyHit, bool kStats>
inline __attribute__((always_inline)) Hit traverse(const Node8* nodes, const Tri8* blocks, bool empty, const Ray& ray,
                                                   TraceStats* stats) {
    Hit best;
    const PreparedRay r = prepare(ray);
    if constexpr (kStats) stats->rays++;
    if (!r.valid || empty) return best;
    const typename K::RayData rd = K::pack(r);
    best.t = r.tmax;
    StackEntry stack[kStackSize];
    int sp = 0;
    Child8 cur{0, 0};
    for (;;) {
        if (cur.count == 0) {
            const Node8& n = nodes[cur.index];
            if constexpr (kStats) {
                stats->nodes_visited++;
                stats->box_tests += 8;
            }
            alignas(32) float entries[8];
            std::uint32_t mask = K::box8(rd, n.boxes, best.t * kCullWiden, entries);
            if (mask != 0) {
                for (std::uint32_t m = mask; m != 0; m &= m - 1) prefetch_child(nodes, blocks, n.children[__builtin_ctz(m)]);
                const int i0 = __builtin_ctz(mask);
                mask &= mask - 1;
                if (mask == 0) {  // one hit: descend
                    cur = n.children[i0];
                    continue;
                }
                const int i1 = __builtin_ctz(mask);
                mask &= mask - 1;
                if (mask == 0) {  // two hits: push the far one
                    const bool first0 = entries[i0] <= entries[i1];
                    const int nearer = first0 ? i0 : i1, farther = first0 ? i1 : i0;
                    stack[sp++] = {n.children[farther].index, n.children[farther].count, entries[farther]};
                    cur = n.children[nearer];
                    continue;
                }
                // Three or more: insertion-sort them onto the stack, farthest
                // deepest, then continue with the nearest (Embree sorts 2-4
                // with a network; the stack slots are the sort buffer here).
                const int base = sp;
                auto insert = [&](int i) {
                    const float e = entries[i];
                    int k = sp++;
                    while (k > base && stack[k - 1].entry < e) {
                        stack[k] = stack[k - 1];
                        --k;
                    }
                    stack[k] = {n.children[i].index, n.children[i].count, e};
                };
                insert(i0);
                insert(i1);
                for (; mask != 0; mask &= mask - 1) insert(__builtin_ctz(mask));
                --sp;
                cur = Child8{stack[sp].index, stack[sp].count};
                continue;
            }
        } else {
            const Tri8* b = blocks + cur.index;
            for (std::uint32_t k = 0; k < cur.count; ++k) {
                if constexpr (kStats) stats->triangle_tests += 8;
                if constexpr (kAnyHit) {
                    Hit h;
                    if (K::template any<kTest>(rd, b[k], best.t, h)) return h;
                } else {
                    K::template closest<kTest>(rd, b[k], best);
                }
            }
        }
        // Pop the nearest pending child still in front of the closest hit.
        for (;;) {
            if (sp == 0) return best.hit() ? best : Hit{};
            const StackEntry& s = stack[--sp];
            if (s.entry <= best.t * kCullWiden) {
                cur = Child8{s.index, s.count};
                break;
            }
        }
    }
}

template <class K, TriangleTest kTest, bool kAnyHit, bool kStats>
inline __attribute__((always_inline)) void trace_span(const Bvh8& bvh, std::span<const Ray> rays, std::span<Hit> hits,
                                                      TraceStats* stats) {
    const Node8* nodes = bvh.nodes().data();
    const Tri8* blocks = bvh.blocks().data();
    const bool empty = bvh.nodes().empty();
    for (std::size_t i = 0; i < rays.size(); ++i)
        hits[i] = traverse<K, kTest, kAnyHit, kStats>(nodes, blocks, empty, rays[i], stats);
}

// The per-ISA entry: test and stats chosen once per batch.
template <class K, bool kAnyHit>
inline __attribute__((always_inline)) void trace(const Bvh8& bvh, std::span<const Ray> rays, std::span<Hit> hits,
                                                 const TraceOptions& o) {
    if (o.stats) {
        if (o.test == TriangleTest::watertight) trace_span<K, TriangleTest::watertight, kAnyHit, true>(bvh, rays, hits, o.stats);
        else trace_span<K, TriangleTest::moller, kAnyHit, true>(bvh, rays, hits, o.stats);
    } else {
        if (o.test == TriangleTest::watertight) trace_span<K, TriangleTest::watertight, kAnyHit, false>(bvh, rays, hits, nullptr);
        else trace_span<K, TriangleTest::moller, kAnyHit, false>(bvh, rays, hits, nullptr);
    }
}

}  // namespace simdbvh::bvh8::detail
