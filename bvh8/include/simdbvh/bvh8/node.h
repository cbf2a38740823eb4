#pragma once
// The N-wide node (N = 4, 8, 16): SoA child boxes of N lanes and N child
// references, and the Tri8 leaf blocks (kBlockWidth = 8 triangles, whatever N).
#include <cstddef>
#include <cstdint>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "simdbvh/platform/large_alloc.h"
#include "simdbvh/kernels/soa.h"

namespace simdbvh {

template <int N>
inline constexpr bool kValidWidth = N == 4 || N == 8 || N == 16;

// Child reference: an inner node, an empty slot, or a leaf (its first Tri8
// block and the number of blocks, plus, for single-block leaves, which lanes
// of that block are the leaf's own triangles and which sibling slots share the
// block).
//
// Small leaves (<= kBlockWidth triangles) of one node are bin-packed into
// shared Tri8 blocks (each small leaf in exactly one block, never split).
// Testing a sibling's triangles too never changes a result: every triangle is
// still tested through its own leaf (box culling is conservative), the closest
// hit is the (t, prim) minimum over genuine hits, and any hit accepts any
// genuine hit. Traversal tests a block shared by several hit siblings once, at
// the nearest of their entry distances. Leaves of more than kBlockWidth
// triangles own their blocks (lanes filled from 0, empty lanes at the end of
// the last block).
//
// `count` encodes the kind: 0 = inner, kInvalidPrim = empty slot, else a leaf
// whose bit fields are, from bit 0: kBlockBits bits the number of blocks
// (>= 1), kBlockWidth bits its own lanes (single-block leaves, else 0), N bits
// the slots sharing its block, its own included (0: the block is not shared).
// kBlockBits = 24 - N (N = 8: 16 bits, lanes at 16, sharing at 24). Build with
// the named constructors, read with the accessors.
template <int N>
struct ChildN {
    static_assert(kValidWidth<N>, "node widths: 4, 8, 16");
    static constexpr int kBlockBits = 24 - N;
    static constexpr int kLaneShift = kBlockBits;
    static constexpr int kSharingShift = kBlockBits + kBlockWidth;
    static_assert(kSharingShift + N == 32);
    static constexpr std::uint32_t kBlocksMask = (1u << kBlockBits) - 1u;
    static constexpr std::uint32_t kMaxBlocks = kBlocksMask;  // never kInvalidPrim: a multi-block leaf has no lanes
    static constexpr std::uint32_t kLaneMask = (1u << kBlockWidth) - 1u;

    std::uint32_t index = 0;  // inner: node index; leaf: first block
    std::uint32_t count = 0;

    static constexpr ChildN inner(std::uint32_t node) { return {node, 0}; }
    static constexpr ChildN empty() { return {0, kInvalidPrim}; }
    // A leaf that owns `blocks` blocks from `first_block` (1 <= blocks <= kMaxBlocks).
    static constexpr ChildN leaf(std::uint32_t first_block, std::uint32_t blocks) { return {first_block, blocks}; }
    // A leaf on `lanes` of one block, shared with the sibling slots `sharing` (0: not shared).
    static constexpr ChildN small_leaf(std::uint32_t block, std::uint32_t lanes, std::uint32_t sharing) {
        return {block, 1u | (lanes << kLaneShift) | (sharing << kSharingShift)};
    }

    bool is_inner() const { return count == 0; }
    bool is_empty() const { return count == kInvalidPrim; }
    bool is_leaf() const { return !is_inner() && !is_empty(); }
    std::uint32_t blocks() const { return count & kBlocksMask; }
    std::uint32_t own_lanes() const { return (count >> kLaneShift) & kLaneMask; }  // single-block leaves
    std::uint32_t sharing_slots() const { return count >> kSharingShift; }         // 0: block not shared
};
using Child8 = ChildN<8>;
static_assert(sizeof(ChildN<16>) == 8);

// Tri8 blocks start on 64-byte boundaries (a 320-byte block spans 5 cache
// lines instead of 6); large arrays on huge pages, no zero fill (every writer
// of Tri8 blocks clears or sets each block it allocates: pack, BruteForce8).
using Tri8Blocks = LargeVector<Tri8, 64>;

// Child boxes first (empty slots +inf/-inf, at the end), then the references.
template <int N>
struct alignas(64) NodeN {
    static constexpr int kWidth = N;
    BoxN<N> boxes;
    ChildN<N> children[N];
};
using Node4 = NodeN<4>;
using Node8 = NodeN<8>;
using Node16 = NodeN<16>;
static_assert(sizeof(Node4) == 128 && alignof(Node4) == 64);    // 2 cache lines
static_assert(sizeof(Node8) == 256 && alignof(Node8) == 64);    // 4
static_assert(sizeof(Node16) == 512 && alignof(Node16) == 64);  // 8
static_assert(offsetof(Node8, children) == sizeof(Box8));

// A wide tree's nodes, on huge pages like its blocks (large_alloc.h): a
// std::allocator array is not 2 MiB aligned, and its unaligned ends fault in
// 4 KiB pages (about 470 faults for the dragon's BVH8 nodes, measured).
template <int N>
using NodesN = LargeVector<NodeN<N>, 64>;

}  // namespace simdbvh
