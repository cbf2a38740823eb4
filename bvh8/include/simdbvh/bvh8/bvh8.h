#pragma once
// 8-wide BVH: the BVH2 collapsed by SAH cost (Ylitie, Karras, Laine 2017),
// packed into SoA nodes whose 8 child boxes are tested in one SIMD operation,
// with triangles pre-gathered into SoA blocks of 8.
#include <cstddef>
#include <cstdint>
#include <new>
#include <span>
#include <string_view>
#include <optional>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/kernels/soa.h"

namespace simdbvh {

enum class Collapse : std::uint8_t {
    sah,     // Ylitie et al. 2017 section 4 dynamic program (default)
    greedy,  // adopt the child with the largest surface area until 8 children
};
std::string_view name(Collapse c);
std::optional<Collapse> parse_collapse(std::string_view s);

struct Bvh8Options {
    Collapse collapse = Collapse::sah;
    int max_leaf_size = 8;  // triangles per BVH8 leaf (one or more Tri8 blocks; small leaves share blocks)
    // Collapse cost model (Ylitie 2017 section 4 adapted to Tri8 blocks): a
    // Node8 visit (one 8-wide box test) costs node_cost, a leaf costs
    // block_cost per Tri8 block, i.e. block_cost * ceil(n / 8) for n triangles.
    float node_cost = 1.0f;
    float block_cost = 1.0f;
};

// Child reference: inner node index, or a leaf: its first Tri8 block and the
// number of blocks, plus (single-block leaves) which lanes of that block are
// the leaf's own triangles and which sibling slots share the block.
//
// Small leaves (<= 8 triangles) of one Node8 are bin-packed into shared Tri8
// blocks (each small leaf in exactly one block, never split). Testing a
// sibling's triangles too never changes a result: every triangle is still
// tested through its own leaf (box culling is conservative), the closest hit
// is the (t, prim) minimum over genuine hits, and any hit accepts any genuine
// hit. Traversal tests a block shared by several hit siblings once, at the
// nearest of their entry distances. Leaves of more than 8 triangles own their
// blocks (lanes filled from 0, empty lanes at the end of the last block).
struct Child8 {
    // count for a leaf: bits 0-15 number of blocks (>= 1); bits 16-23 the
    // leaf's own lanes (single-block leaves, else 0); bits 24-31 the slots of
    // this node whose leaves share the block, this slot included (0 when the
    // block is not shared). 0 = inner node; kInvalidPrim = empty slot (never a
    // leaf: a leaf with 0xFFFF blocks has no lane mask).
    static constexpr std::uint32_t kBlocksMask = 0xFFFFu;
    static constexpr std::uint32_t kMaxBlocks = 0xFFFFu;
    std::uint32_t index = 0;  // inner: node index; leaf: first block
    std::uint32_t count = 0;

    bool is_inner() const { return count == 0; }
    bool is_empty() const { return count == kInvalidPrim; }
    std::uint32_t blocks() const { return count & kBlocksMask; }
    std::uint32_t own_lanes() const { return (count >> 16) & 0xFFu; }    // single-block leaves
    std::uint32_t sharing_slots() const { return count >> 24; }          // 0: block not shared
};

// Tri8 blocks start on 64-byte boundaries (a 320-byte block spans 5 cache
// lines instead of 6).
template <class T, std::size_t kAlign>
struct AlignedAllocator {
    using value_type = T;
    template <class U>
    struct rebind {
        using other = AlignedAllocator<U, kAlign>;
    };
    AlignedAllocator() = default;
    template <class U>
    AlignedAllocator(const AlignedAllocator<U, kAlign>&) noexcept {}
    T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(kAlign))); }
    // Unsized aligned delete: clang without -fsized-deallocation has no sized form.
    void deallocate(T* p, std::size_t) noexcept { ::operator delete(p, std::align_val_t(kAlign)); }
    template <class U>
    bool operator==(const AlignedAllocator<U, kAlign>&) const noexcept { return true; }
};
using Tri8Blocks = std::vector<Tri8, AlignedAllocator<Tri8, 64>>;

struct alignas(64) Node8 {
    Box8 boxes;         // 192 bytes: SoA lower/upper x, y, z; empty slots +inf/-inf, at the end
    Child8 children[8]; // 64 bytes
};
static_assert(sizeof(Node8) == 256 && alignof(Node8) == 64);

struct Bvh8Stats {
    double build_ms = 0;  // collapse + pack (add the BVH2's build_ms for the total)
    std::size_t nodes = 0, leaves = 0, blocks = 0, triangles = 0;
    std::size_t shared_blocks = 0; // blocks holding the triangles of more than one leaf
    int depth = 0;
    double sah_cost = 0;           // sum of cost * A(n)/A(root) (as the BVH2), node_cost / block_cost model
    double bytes_per_triangle = 0; // nodes + triangle blocks
    double fill_rate = 0;          // used child slots / (8 * nodes)
    double block_fill = 0;         // used triangle lanes: triangles / (8 * blocks)
};

class Bvh8 {
public:
    Bvh8() = default;
    static Bvh8 build(const Bvh2& bvh2, const Bvh8Options& opts = {});
    static Bvh8 build(const Mesh& mesh, const BuildOptions& bvh2_opts = {}, const Bvh8Options& opts = {});

    const std::vector<Node8>& nodes() const { return nodes_; }
    const Tri8Blocks& blocks() const { return blocks_; }
    const Bvh8Stats& stats() const { return stats_; }
    Aabb bounds() const { return bounds_; }

private:
    friend struct Bvh8Access;
    std::vector<Node8> nodes_;  // root at 0 (when the mesh is not empty)
    Tri8Blocks blocks_;
    Bvh8Stats stats_;
    Aabb bounds_;
};

// Closest hit and any hit, bit-identical to the BVH2 (same kernels, same tie
// rule). One switch on `isa` per batch; an unsupported isa throws simdbvh::Error.
// TraceOptions::stats: nodes_visited counts Node8s; box_tests and
// triangle_tests count SIMD lanes (8 per Node8 test, 8 per Tri8 block).
void intersect(const Bvh8& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts = {},
               Isa isa = active_isa());
void occluded(const Bvh8& bvh, std::span<const Ray> rays, std::span<Hit> hits, const TraceOptions& opts = {},
              Isa isa = active_isa());
Hit intersect(const Bvh8& bvh, const Ray& ray, const TraceOptions& opts = {}, Isa isa = active_isa());
Hit occluded(const Bvh8& bvh, const Ray& ray, const TraceOptions& opts = {}, Isa isa = active_isa());

}  // namespace simdbvh
