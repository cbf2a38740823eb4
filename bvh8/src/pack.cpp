// Step 2 of the wide BVH build: the N-wide topology packed into SoA NodeNs
// (child boxes in BoxN, empty slots +inf/-inf at the end, Embree-style) and
// leaves gathered into Tri8 blocks (empty lanes: NaN vertices, kInvalidPrim).
//
// Per node, the leaves of at most kBlockWidth triangles are bin-packed into
// shared blocks, first fit by decreasing size, a leaf never split across blocks
// (see ChildN in node.h for why testing the siblings' triangles too is harmless).
// Larger leaves own their blocks. A node's blocks are contiguous, in slot
// order of their first leaf.
#include <algorithm>
#include <atomic>
#include <cstring>
#include <limits>
#include <memory>
#include <string>

#include "simdbvh/bvh8/internal/collapse.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/platform/large_alloc.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh::bvh8 {

namespace {

constexpr std::uint32_t kLanes = kBlockWidth;

// First fit decreasing of a node's small leaves (<= kBlockWidth triangles) into
// bins of kBlockWidth lanes; bins numbered by their lowest slot.
template <int N>
struct NodePacking {
    int bins = 0;
    int bin_of[N], lane_of[N];        // per slot (small leaves only)
    std::uint32_t bin_slots[N] = {};  // slots per bin
};

bool is_small(const WideChild& c) { return c.is_leaf() && c.count <= kLanes; }

template <int N>
NodePacking<N> pack_node(const WideNode<N>& w) {
    NodePacking<N> p;
    int order[N], small = 0;
    for (int c = 0; c < w.child_count; ++c)
        if (is_small(w.children[c])) order[small++] = c;
    for (int k = 1; k < small; ++k) {  // stable insertion sort by decreasing count (std::stable_sort allocates)
        const int c = order[k];
        int j = k;
        for (; j > 0 && w.children[order[j - 1]].count < w.children[c].count; --j) order[j] = order[j - 1];
        order[j] = c;
    }
    int used[N], bin_of[N];
    std::uint32_t slots[N] = {};
    int bins = 0;
    for (int k = 0; k < small; ++k) {
        const int c = order[k];
        const int sz = int(w.children[c].count);
        int b = 0;
        while (b < bins && used[b] + sz > int(kLanes)) ++b;
        if (b == bins) used[bins++] = 0;
        bin_of[c] = b;
        p.lane_of[c] = used[b];
        used[b] += sz;
        slots[b] |= 1u << c;
    }
    int rank[N] = {};
    for (int c = 0; c < w.child_count; ++c)
        if (is_small(w.children[c]) && int(__builtin_ctz(slots[bin_of[c]])) == c) rank[bin_of[c]] = p.bins++;
    for (int c = 0; c < w.child_count; ++c)
        if (is_small(w.children[c])) p.bin_of[c] = rank[bin_of[c]];
    for (int b = 0; b < bins; ++b) p.bin_slots[rank[b]] = slots[b];
    return p;
}

}  // namespace

// Whether pack(mesh) reads the mesh in its own order and scatters the
// triangles to their lanes rather than gathering them in leaf order. A gather
// in leaf order reads the mesh at random when the mesh's triangle order has
// no spatial locality (a soup, a shuffled export): two dependent cache and TLB
// misses per triangle (on this KVM guest 74-89 ns per triangle at 1M
// triangles, 163-170 at 30M, and at 10M once 31 s for the whole pack). The
// scatter reads the mesh in order and writes it through buckets
// (scatter_by_buckets). Decided by how far consecutive leaf positions jump in
// the mesh, on a sample; the lane numbers must fit 32 bits (blocks <= triangles).
bool scatter_pays(std::span<const std::uint32_t> prim_ids, std::size_t triangles) {
    if (prim_ids.size() < 2 || triangles > std::numeric_limits<std::uint32_t>::max() / kLanes) return false;
    // Up to 4096 consecutive pairs spread over the leaf order: scatter when
    // more than a quarter jump over more than 16384 triangles (measured:
    // the dragon 2.4%, a random soup 98.9%).
    constexpr std::size_t kSamples = 4096;
    constexpr std::uint32_t kFar = 16384;
    const std::size_t stride = std::max<std::size_t>(1, (prim_ids.size() - 1) / kSamples);
    std::size_t far = 0, samples = 0;
    for (std::size_t k = 1; k < prim_ids.size(); k += stride, ++samples) {
        const std::uint32_t a = prim_ids[k - 1], b = prim_ids[k];
        far += (a > b ? a - b : b - a) > kFar;
    }
    return 4 * far > samples;
}

// Blocks of a leaf too large to share one.
std::uint32_t own_blocks(const WideChild& c) { return (c.count + kLanes - 1u) / kLanes; }

// `set_tri(pos, blk, lane)` writes the triangle at BVH2 leaf position pos;
// `clear(blk)` empties a block before its lanes are written.
template <int N, class SetTri, class ClearBlock>
void pack_with(const WideTopology<N>& topo, NodesN<N>& nodes, Tri8Blocks& blocks, WideStats& stats, int threads,
               SetTri set_tri, ClearBlock clear) {
    using Child = ChildN<N>;
    ParallelOptions po;
    po.grain = 256;
    po.pin = false;
    // Each node's packing and block count (independent, in parallel), then
    // the prefix sum of the counts: each node's first block. The nodes are
    // then independent.
    LargeVector<NodePacking<N>> packing(topo.nodes.size());         // each written below
    std::vector<std::uint32_t> first_block(topo.nodes.size() + 1);  // a node's block count, then its first block
    std::atomic<std::size_t> used_slots{0}, leaves{0}, shared{0};
    std::atomic<std::uint32_t> too_large{0};  // the largest leaf over Child::kMaxBlocks blocks (deterministic message)
    parallel_for(
        topo.nodes.size(), threads,
        [&](std::size_t b, std::size_t e) {
            std::size_t used = 0, nleaves = 0, nshared = 0;
            std::uint32_t largest = 0;
            for (std::size_t i = b; i < e; ++i) {
                const WideNode<N>& w = topo.nodes[i];
                const NodePacking<N>& p = packing[i] = pack_node(w);
                std::uint32_t count = std::uint32_t(p.bins);
                for (int k = 0; k < p.bins; ++k) nshared += __builtin_popcount(p.bin_slots[k]) > 1;
                used += std::size_t(w.child_count);
                for (int c = 0; c < w.child_count; ++c) {
                    const WideChild& wc = w.children[c];
                    if (!wc.is_leaf()) continue;
                    ++nleaves;
                    if (is_small(wc)) continue;
                    if (own_blocks(wc) > Child::kMaxBlocks) largest = std::max(largest, wc.count);
                    else count += own_blocks(wc);  // <= N * kMaxBlocks: no overflow
                }
                first_block[i] = count;
            }
            used_slots += used;
            leaves += nleaves;
            shared += nshared;
            for (std::uint32_t t = too_large.load(); largest > t && !too_large.compare_exchange_weak(t, largest);) {}
        },
        po);
    if (too_large.load())
        throw Error("BVH" + std::to_string(N) + " leaf of " + std::to_string(too_large.load()) + " triangles exceeds " +
                    std::to_string(Child::kMaxBlocks) + " Tri8 blocks");
    std::size_t blocks_needed = 0;
    for (std::uint32_t& f : first_block) {
        const std::uint32_t count = f;
        f = std::uint32_t(blocks_needed);
        blocks_needed += count;
        if (blocks_needed > std::size_t(std::numeric_limits<std::uint32_t>::max()))
            throw Error("BVH" + std::to_string(N) + ": more than 2^32 Tri8 blocks");
    }
    nodes.clear();
    nodes.resize(topo.nodes.size());  // each written by pack_one
    blocks.clear();
    blocks.resize(blocks_needed);
    auto fill = [&](Tri8& blk, int lane0, const WideChild& wc, std::uint32_t from, std::uint32_t n) {
        for (std::uint32_t k = 0; k < n; ++k) set_tri(wc.index + from + k, blk, lane0 + int(k));
    };
    auto pack_one = [&](std::size_t i) {
        const WideNode<N>& w = topo.nodes[i];
        NodeN<N>& n = nodes[i];
        n.boxes.clear();
        for (int c = 0; c < N; ++c) n.children[c] = Child::empty();
        const NodePacking<N>& p = packing[i];
        const std::uint32_t base = first_block[i];
        for (std::uint32_t b = base; b < first_block[i + 1]; ++b) clear(blocks[b]);
        std::uint32_t next = base + std::uint32_t(p.bins);  // the large leaves' own blocks, in slot order
        for (int c = 0; c < w.child_count; ++c) {
            const WideChild& wc = w.children[c];
            n.boxes.set(c, wc.box);
            if (!wc.is_leaf()) {
                n.children[c] = Child::inner(wc.index);
                continue;
            }
            if (is_small(wc)) {
                const int b = p.bin_of[c];
                fill(blocks[base + std::uint32_t(b)], p.lane_of[c], wc, 0, wc.count);
                const std::uint32_t lanes = ((1u << wc.count) - 1u) << p.lane_of[c];
                const std::uint32_t sharing = __builtin_popcount(p.bin_slots[b]) > 1 ? p.bin_slots[b] : 0u;
                n.children[c] = Child::small_leaf(base + std::uint32_t(b), lanes, sharing);
                continue;
            }
            const std::uint32_t count = own_blocks(wc);
            for (std::uint32_t b = 0; b < count; ++b)
                fill(blocks[next + b], 0, wc, b * kLanes, std::min(kLanes, wc.count - b * kLanes));
            n.children[c] = Child::leaf(next, count);
            next += count;
        }
    };
    parallel_for(
        topo.nodes.size(), threads,
        [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) pack_one(i);
        },
        po);
    stats.nodes = nodes.size();
    stats.leaves = leaves;
    stats.blocks = blocks.size();
    stats.shared_blocks = shared;
    stats.triangles = topo.prims;
    stats.width = N;
    stats.depth = topo.depth;
    stats.bytes_per_triangle =
        stats.triangles
            ? double(nodes.size() * sizeof(NodeN<N>) + blocks.size() * sizeof(Tri8)) / double(stats.triangles)
            : 0.0;
    stats.fill_rate = nodes.empty() ? 0.0 : double(used_slots) / (double(N) * double(nodes.size()));
    stats.block_fill = blocks.empty() ? 0.0 : double(stats.triangles) / (double(kLanes) * double(blocks.size()));
}

template <int N>
void pack(const Bvh2& bvh2, const WideTopology<N>& topo, NodesN<N>& nodes, Tri8Blocks& blocks, WideStats& stats,
          int threads) {
    const auto& tris = bvh2.triangles();
    const auto& ids = bvh2.prim_ids();
    pack_with(
        topo, nodes, blocks, stats, threads,
        [&](std::uint32_t pos, Tri8& blk, int lane) {
            const TriangleVerts& tv = tris[pos];
            blk.set(lane, tv.v0, tv.v1, tv.v2, ids[pos]);
        },
        [](Tri8& blk) { blk.clear(); });
}

namespace {

// A lane as one record (a Tri8 is 8 of these, transposed): the scatter moves
// records, each one or two cache lines where a Tri8 lane is five. The records
// live in the Tri8 blocks' bytes before the transpose: may_alias (GCC, Clang)
// lets them be read and written there as LaneRecords.
struct __attribute__((may_alias)) LaneRecord {
    float v[9];
    std::uint32_t prim;
};
static_assert(sizeof(LaneRecord) * kLanes == sizeof(Tri8));

// A block of 8 records, in place, into the Tri8 layout.
void transpose(Tri8& blk) {
    LaneRecord r[kLanes];
    std::memcpy(r, &blk, sizeof r);
    for (int i = 0; i < int(kLanes); ++i)
        blk.set(i, {r[i].v[0], r[i].v[1], r[i].v[2]}, {r[i].v[3], r[i].v[4], r[i].v[5]},
                {r[i].v[6], r[i].v[7], r[i].v[8]}, r[i].prim);
}

// The scatter in two passes, so that no write lands at random in the whole
// of the blocks (a single pass writing each record at random, with the empty
// lanes written beforehand, took soup-10M's collapse + pack to 1,454 ms against
// 891 for this, in-process A/B):
// 1. the triangles, read in mesh order, are appended as lane records to the
//    start of their bucket's own lanes (kBucketLanes consecutive lanes, 640 KB:
//    one sequential write stream per bucket), each with its lane within the
//    bucket in `slot`;
// 2. each bucket, in L2, is copied aside, filled with empty records, its
//    records written to their lanes, and its blocks transposed.
// Pass 1 runs on chunks of the mesh (each chunk its own offsets into every
// bucket), pass 2 on buckets. Scratch: 2 bytes per lane. Buckets of 2^12,
// 2^14 and 2^16 lanes measured within 7% of each other (soup-10M pack).
constexpr int kBucketShift = 14;
constexpr std::uint32_t kBucketLanes = 1u << kBucketShift;
static_assert(kBucketLanes % kLanes == 0 && kBucketLanes <= 65536);  // slot: uint16

void scatter_by_buckets(const Mesh& mesh, std::span<const std::uint32_t> lane_of, Tri8Blocks& blocks, int threads) {
    constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
    const std::size_t n = lane_of.size();
    const std::size_t lanes = blocks.size() * kLanes;
    const std::size_t buckets = (lanes + kBucketLanes - 1) / kBucketLanes;
    const std::size_t chunks = std::size_t(std::max(1, threads));
    auto chunk_begin = [&](std::size_t c) { return n * c / chunks; };
    // next[c * buckets + b]: chunk c's next record in bucket b (a lane index).
    std::vector<std::uint32_t> next(chunks * buckets, 0);
    std::vector<std::uint32_t> filled(buckets);
    run_tasks(chunks, [&](std::size_t c) {
        std::uint32_t* count = next.data() + c * buckets;
        for (std::size_t p = chunk_begin(c); p < chunk_begin(c + 1); ++p)
            if (const std::uint32_t l = lane_of[p]; l != kNone) ++count[l >> kBucketShift];
    });
    for (std::size_t b = 0; b < buckets; ++b) {
        std::uint32_t at = std::uint32_t(b * kBucketLanes);
        for (std::size_t c = 0; c < chunks; ++c) {
            const std::uint32_t k = next[c * buckets + b];
            next[c * buckets + b] = at;
            at += k;
        }
        filled[b] = at - std::uint32_t(b * kBucketLanes);
    }
    LargeVector<std::uint16_t> slot(lanes);  // for the lanes holding records after pass 1
    LaneRecord* rec = reinterpret_cast<LaneRecord*>(blocks.data());
    run_tasks(chunks, [&](std::size_t c) {
        std::uint32_t* at = next.data() + c * buckets;
        for (std::size_t p = chunk_begin(c); p < chunk_begin(c + 1); ++p) {
            const std::uint32_t l = lane_of[p];
            if (l == kNone) continue;
            const Vec3 a = mesh.vertex(p, 0), b = mesh.vertex(p, 1), d = mesh.vertex(p, 2);
            const std::uint32_t k = at[l >> kBucketShift]++;
            rec[k] = {{a.x, a.y, a.z, b.x, b.y, b.z, d.x, d.y, d.z}, std::uint32_t(p)};
            slot[k] = std::uint16_t(l & (kBucketLanes - 1));
        }
    });
    ParallelOptions po;
    po.grain = 8;
    po.pin = false;
    parallel_for(
        buckets, threads,
        [&](std::size_t b0, std::size_t b1) {
            constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
            const LaneRecord empty{{kNan, kNan, kNan, kNan, kNan, kNan, kNan, kNan, kNan}, kInvalidPrim};
            const std::unique_ptr<LaneRecord[]> aside(new LaneRecord[kBucketLanes]);  // not zeroed
            for (std::size_t b = b0; b < b1; ++b) {
                const std::size_t first = b * kBucketLanes, count = filled[b];
                const std::size_t end = std::min(lanes, first + kBucketLanes);
                std::memcpy(aside.get(), rec + first, count * sizeof(LaneRecord));
                std::fill(rec + first, rec + end, empty);
                for (std::size_t k = 0; k < count; ++k) rec[first + slot[first + k]] = aside[k];
                for (std::size_t k = first / kLanes; k < end / kLanes; ++k) transpose(blocks[k]);
            }
        },
        po);
}

}  // namespace

template <int N>
void pack(const Mesh& mesh, std::span<const std::uint32_t> prim_ids, const WideTopology<N>& topo, NodesN<N>& nodes,
          Tri8Blocks& blocks, WideStats& stats, int threads) {
    const std::size_t n = mesh.triangles.size();
    if (!scatter_pays(prim_ids, n)) {
        // The gather waits on three dependent loads per triangle (its id, its
        // vertex indices, its vertices): the indices are fetched 16 positions
        // ahead and the vertices 8 ahead (leaves are runs of positions).
        const std::size_t m = prim_ids.size();
        pack_with(
            topo, nodes, blocks, stats, threads,
            [&](std::uint32_t pos, Tri8& blk, int lane) {
                if (pos + 16u < m) __builtin_prefetch(&mesh.triangles[prim_ids[pos + 16u]]);
                if (pos + 8u < m) {
                    const Triangle& t = mesh.triangles[prim_ids[pos + 8u]];
                    for (int k = 0; k < 3; ++k) __builtin_prefetch(&mesh.positions[t[k]]);
                }
                const std::uint32_t p = prim_ids[pos];
                blk.set(lane, mesh.vertex(p, 0), mesh.vertex(p, 1), mesh.vertex(p, 2), p);
            },
            [](Tri8& blk) { blk.clear(); });
        return;
    }
    // Scatter: the packing records each triangle's lane (block * kLanes +
    // lane, by triangle id) and leaves the blocks alone; scatter_by_buckets
    // then writes every lane, the empty ones included. The same values in
    // the same lanes as the gather above (an empty record transposes to
    // Tri8::set_empty's lane).
    constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
    ParallelOptions po;
    po.grain = std::size_t(1) << 16;
    po.pin = false;
    LargeVector<std::uint32_t> lane_of(n);  // each written below
    parallel_for(
        n, threads,
        [&](std::size_t b, std::size_t e) {
            std::fill(lane_of.begin() + std::ptrdiff_t(b), lane_of.begin() + std::ptrdiff_t(e), kNone);
        },
        po);
    pack_with(
        topo, nodes, blocks, stats, threads,
        [&](std::uint32_t pos, Tri8& blk, int lane) {
            lane_of[prim_ids[pos]] = std::uint32_t(&blk - blocks.data()) * kLanes + std::uint32_t(lane);
        },
        [](Tri8&) {});
    scatter_by_buckets(mesh, lane_of, blocks, threads);
}

#define SIMDBVH_WIDTH(N)                                                                                   \
    template void pack<N>(const Bvh2&, const WideTopology<N>&, NodesN<N>&, Tri8Blocks&, WideStats&, int);  \
    template void pack<N>(const Mesh&, std::span<const std::uint32_t>, const WideTopology<N>&, NodesN<N>&, \
                          Tri8Blocks&, WideStats&, int);
SIMDBVH_WIDTH(4)
SIMDBVH_WIDTH(8)
SIMDBVH_WIDTH(16)
#undef SIMDBVH_WIDTH

}  // namespace simdbvh::bvh8
