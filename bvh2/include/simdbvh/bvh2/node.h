#pragma once
// The flat BVH2 traversal node (32 bytes: two per cache line).
#include <cstdint>

#include "simdbvh/kernels/aabb.h"
#include "simdbvh/platform/large_alloc.h"

namespace simdbvh {

struct Node2 {
    Aabb box;             // 24 bytes
    std::uint32_t first;  // leaf: first index into prim_ids; inner: left child (right = first + 1)
    std::uint32_t count;  // 0 = inner node
    bool is_leaf() const { return count != 0; }
};
static_assert(sizeof(Node2) == 32);

// A BVH2's nodes: a large array (large_alloc.h), root at 0.
using Nodes2 = LargeVector<Node2>;

}  // namespace simdbvh
