#pragma once
// Internal: prefetch the cache lines of a wide tree's next node or leaf (used
// by the ray traversal, traverse-inl.h, and the inside test, inside.cpp, each
// with several queries in flight so the misses overlap other queries' work).
#include "simdbvh/bvh8/node.h"

namespace simdbvh::bvh8::detail {

// Prefetch the lines of the next node or leaf a query will visit (a NodeN:
// N / 2 lines, a QNodeN N / 4 (N = 8, 16); a leaf: its first Tri8 block, 320 bytes at 64-byte alignment:
// 5 lines) at the end of its step, so the miss overlaps the other queries' steps.
template <class Node, class Child>
inline __attribute__((always_inline)) void prefetch_child(const Node* nodes, const Tri8* blocks, Child c) {
    constexpr int kNodeLines = int(sizeof(Node) / 64), kBlockLines = int((sizeof(Tri8) + 63) / 64);
    constexpr int kBoth = kNodeLines < kBlockLines ? kNodeLines : kBlockLines;
    const char* p =
        c.is_inner() ? reinterpret_cast<const char*>(nodes + c.index) : reinterpret_cast<const char*>(blocks + c.index);
    for (int l = 0; l < kBoth; ++l) __builtin_prefetch(p + 64 * l);
    if constexpr (kBlockLines > kBoth) {
        if (!c.is_inner())
            for (int l = kBoth; l < kBlockLines; ++l) __builtin_prefetch(p + 64 * l);
    }
    if constexpr (kNodeLines > kBoth) {
        if (c.is_inner())
            for (int l = kBoth; l < kNodeLines; ++l) __builtin_prefetch(p + 64 * l);
    }
}

}  // namespace simdbvh::bvh8::detail
