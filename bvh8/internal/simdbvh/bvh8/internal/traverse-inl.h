#pragma once
// The wide BVH stack traversal, one loop for every width: a loop (step,
// trace_span: several rays in flight per batch; trace_one: one ray in locals) x a node test (K::box, N lanes)
// x a leaf intersector (Tri8Leaf: blocks of kBlockWidth triangles; the
// sphere and box sets' in scene/src/shape_traverse-inl.h) x a query
// (query/query.h: ClosestHit, AnyHit, what a leaf does to the ray;
// finish() writes its Hit),
// after madmann91/bvh v2's traverse_top_down(leaf_fn, inner_fn) and Embree's
// bvh_intersector1 + node_intersector1. Included only by the per-ISA
// translation units, each a few lines `template struct Traversal<isa::Kernels,
// N>;`: everything here is a template on K, so no ISA-encoded copy can be
// shared between them.
//
// K (the ISA's kernels) provides: void pack(RayData&, PreparedRay, const Ray&
// (outlives the RayData)); uint32 box(RayData, BoxN<N>, tmax, float entries[N])
// (hit mask, entry distances, entries aligned to 4 * N bytes);
// closest<Test>(RayData, Tri8, Hit& best); bool any<Test>(RayData, Tri8, tmax, Hit&).
//
// Counters (TraceOptions::stats): nodes_visited = wide nodes visited;
// box_tests and triangle_tests count lanes, N per node test and kBlockWidth
// per Tri8 block, plus one box test per valid ray for the bounds (RayFeed) (empty slots and lanes included; a block shared by several
// hit leaves of one node counts once).
#include <algorithm>
#include <cstdint>
#include <span>
#include <type_traits>

#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/kernels/box.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/bvh8/internal/prefetch-inl.h"
#include "simdbvh/bvh8/internal/traverse.h"
#include "simdbvh/kernels/internal/query/query.h"

namespace simdbvh::bvh8::detail {

#define SIMDBVH_TRAVERSE_INLINE inline __attribute__((always_inline))

// What a ray state keeps of its PreparedRay for the leaf intersector: nothing
// (Tri8Leaf reads the packed RayData) or the PreparedRay itself (leaves of
// scalar primitive tests, scene/src/shape_traverse-inl.h).
struct NoPreparedRay {};

// Leaf intersector: a leaf is `count` consecutive Tri8 blocks. The leaf
// interface of step() and trace_span(): `Keep` (what the ray state keeps of
// the PreparedRay), closest(state, best, stats), any(state, best, stats) on
// the leaf state.cur, prefetch(nodes, child) for the next node or leaf, and
// kShared (whether leaf siblings may share a block: merge_shared below).
template <class K, TriangleTest kTest, bool kStats>
struct Tri8Leaf {
    using Keep = NoPreparedRay;
    static constexpr bool kShared = true;  // small leaves may share a block (merge_shared)
    const Tri8* blocks;
    // Closest hit: shrinks `best` (best.t is the current tmax).
    template <class State>
    SIMDBVH_TRAVERSE_INLINE void closest(const State& s, Hit& best, TraceStats* stats) const {
        const Tri8* b = blocks + s.cur.index;
        for (std::uint32_t k = 0, count = s.cur.blocks(); k < count; ++k) {
            if constexpr (kStats) stats->triangle_tests += kBlockWidth;
            K::template closest<kTest>(s.rd, b[k], best);
        }
    }
    // Any hit: true at the first hit in [tmin, best.t], written to `best`.
    template <class State>
    SIMDBVH_TRAVERSE_INLINE bool any(const State& s, Hit& best, TraceStats* stats) const {
        const Tri8* b = blocks + s.cur.index;
        for (std::uint32_t k = 0, count = s.cur.blocks(); k < count; ++k) {
            if constexpr (kStats) stats->triangle_tests += kBlockWidth;
            Hit h;
            if (K::template any<kTest>(s.rd, b[k], best.t, h)) {
                best = h;
                return true;
            }
        }
        return false;
    }
    template <class Node, class Child>
    SIMDBVH_TRAVERSE_INLINE void prefetch(const Node* nodes, Child c) const {
        prefetch_child(nodes, blocks, c);
    }
};

using query::AnyHit;
using query::ClosestHit;

// At most N - 1 entries are pushed per level: 1 + (N - 1) * depth (depth <= kMaxDepth, checked at build).
template <int N>
inline constexpr int kStackSize = 1 + (N - 1) * kMaxDepth;

// No default member initializers: the stack must stay uninitialized (it is
// large, and zero-filling it per ray cost a quarter of the traversal time).
struct StackEntry {
    std::uint32_t index, count;  // Child8
    float entry;
};

// Hit leaf siblings sharing one Tri8 block (ChildN::sharing_slots) are merged
// into the lowest hit slot at the nearest of their entry distances, so the
// block is tested once. Called with two or more hits in `mask`.
template <class Node>
inline __attribute__((always_inline)) std::uint32_t merge_shared(const Node& n, std::uint32_t mask, float* entries) {
    for (std::uint32_t m = mask; m != 0;) {
        const int i = __builtin_ctz(m);
        const std::uint32_t group = n.children[i].sharing_slots() & mask;  // i is its lowest hit slot
        m &= m - 1;
        const std::uint32_t others = group & ~(1u << i);
        if (others == 0) continue;
        m &= ~others;
        mask &= ~others;
        float e = entries[i];
        for (std::uint32_t o = others; o != 0; o &= o - 1) e = std::min(e, entries[__builtin_ctz(o)]);
        entries[i] = e;
    }
    return mask;
}

// One ray's traversal state. No default member initializers (the stack must
// stay uninitialized). `Keep`: the leaf's (NoPreparedRay or PreparedRay).
template <class K, int N, class Keep = NoPreparedRay>
struct RayState {
    typename K::RayData rd;
    [[no_unique_address]] Keep pr;
    Hit best;       // closest hit so far; best.t = current tmax (any hit: the ray's tmax, then the hit)
    float cull;     // cull_bound(best.t), kept with it (one computation per leaf, not two per node)
    ChildN<N> cur;  // next node or leaf to visit
    int sp;
    int t_exp;        // PreparedRay::t_exp: the caller's t is ldexp(best.t, t_exp)
    std::size_t ray;  // index in the batch
    StackEntry stack[kStackSize<N>];
};

// One traversal step of ray `s`: visits s.cur (one NodeN or QNodeN, or one leaf), then
// sets s.cur to the next node or leaf to visit. Returns true when the ray is
// finished, its result in s.best (Query::finish turns it into the Hit).
template <class K, int N, class Leaf, class Query, bool kStats, class Node, class State>
inline __attribute__((always_inline)) bool step(const Node* nodes, const Leaf& leaf, State& s, TraceStats* stats) {
    using Child = ChildN<N>;
    const typename K::RayData& rd = s.rd;
    Hit& best = s.best;
    StackEntry* stack = s.stack;
    if (s.cur.count == 0) {
        const Node& n = nodes[s.cur.index];
        if constexpr (kStats) {
            stats->nodes_visited++;
            stats->box_tests += N;
        }
        alignas(4 * N) float entries[N];
        std::uint32_t mask = K::box(rd, n.boxes, s.cull, entries);
        if constexpr (Leaf::kShared)
            if ((mask & (mask - 1)) != 0) mask = merge_shared(n, mask, entries);
        if (mask != 0) {
            const int i0 = __builtin_ctz(mask);
            mask &= mask - 1;
            if (mask == 0) {  // one hit: descend
                s.cur = n.children[i0];
                return false;
            }
            if constexpr (Query::kAnyHit) {
                // Any hit: the ray ends at its first hit, wherever it is, so
                // the pending children are not sorted: continue with the
                // nearest (a primary ray's occluder is usually in front),
                // push the others in slot order.
                int near = i0, sp = s.sp;
                for (; mask != 0; mask &= mask - 1) {
                    int i = __builtin_ctz(mask);
                    if (entries[i] < entries[near]) std::swap(i, near);
                    stack[sp++] = {n.children[i].index, n.children[i].count, entries[i]};
                }
                s.sp = sp;
                s.cur = n.children[near];
                return false;
            }
            const int i1 = __builtin_ctz(mask);
            mask &= mask - 1;
            int sp = s.sp;
            if (mask == 0) {  // two hits: push the far one
                const bool first0 = entries[i0] <= entries[i1];
                const int nearer = first0 ? i0 : i1, farther = first0 ? i1 : i0;
                stack[sp++] = {n.children[farther].index, n.children[farther].count, entries[farther]};
                s.sp = sp;
                s.cur = n.children[nearer];
                return false;
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
            s.sp = sp;
            s.cur = Child{stack[sp].index, stack[sp].count};
            return false;
        }
    } else if (Query::leaf(leaf, s, best, stats)) {
        return true;
    } else if constexpr (!Query::kAnyHit) {
        s.cull = cull_bound(best.t);  // a closest-hit leaf may have shrunk best.t
    }
    // Pop the nearest pending child still in front of the closest hit.
    int sp = s.sp;
    for (;;) {
        if (sp == 0) return true;
        const StackEntry& e = stack[--sp];
        if (e.entry <= s.cull) {
            s.cur = Child{e.index, e.count};
            s.sp = sp;
            return false;
        }
    }
}

// Starts ray `i` (prepared as `r`, which need not outlive the call) in `s`.
template <class K, int N, class State>
inline __attribute__((always_inline)) void start(State& s, const PreparedRay& r, const Ray& ray, std::size_t i) {
    K::pack(s.rd, r, ray);  // a pack keeps no pointer to r (a copy of r here was a store-forwarding stall)
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(s.pr)>, PreparedRay>) s.pr = r;
    s.best = Hit{};
    s.best.t = r.tmax;
    s.cull = cull_bound(r.tmax);
    s.cur = ChildN<N>::inner(0);
    s.sp = 0;
    s.t_exp = r.t_exp;
    s.ray = i;
}

// The rays of a batch prepared 8 at a time (K::prepare8: on the SIMD paths
// in vector lanes, without prepare()'s per-ray branches and divisions) and
// handed out one by one. A ray that cannot hit anything is finished as a
// miss when its group is prepared: an invalid ray, an empty tree (no bounds),
// or a ray that misses the tree's bounds. The bounds test is the BVH2's own
// root test (intersect_box, the conservative slab test with tmax = the
// ray's): the BVH2 and the BVH2's root box are these bounds (the union of
// the triangles' boxes), and the BVH2 is bit-identical to brute force, so a
// ray that misses them hits nothing. Rays that miss the scene (a camera's
// sky) then cost their share of a prepare8 and no ray state or node test.
// One group of that: rays [base, base + g), g <= 8, prepared into pr[0 .. g);
// the ones that cannot hit are finished as misses. Returns the others
// (*valid: the valid ones).
template <class K, class Query>
inline __attribute__((always_inline)) std::uint32_t prepare_group(std::span<const Ray> rays, std::size_t base,
                                                                  std::size_t g, const Aabb* root, Hit* hits,
                                                                  PreparedRay* pr, std::uint32_t* valid) {
    const std::uint32_t m = K::prepare8(rays.data() + base, g, root, pr, valid);
    for (std::uint32_t q = ~m & ((1u << g) - 1u); q != 0; q &= q - 1)
        Query::finish(Hit{}, 0, hits[base + std::size_t(__builtin_ctz(q))]);
    return m;
}

template <class K, class Query, bool kStats>
struct RayFeed {
    RayFeed(std::span<const Ray> rays_, const Aabb* root_, Hit* hits_, TraceStats* stats_)
        : rays(rays_), root(root_), hits(hits_), stats(stats_) {}
    std::span<const Ray> rays;
    const Aabb* root;
    Hit* hits;
    TraceStats* stats;
    std::size_t base = 0, next = 0;  // the group's first ray, the first ray not yet prepared
    std::uint32_t pending = 0;       // the group's rays not yet handed out
    PreparedRay pr[8];
    // The next ray that can hit: its index in the batch and its PreparedRay
    // (valid until the next call); false when none is left.
    inline __attribute__((always_inline)) bool pop(std::size_t& i, const PreparedRay*& r) {
        while (pending == 0) {
            if (next >= rays.size()) return false;
            base = next;
            const std::size_t g = std::min<std::size_t>(8, rays.size() - base);
            next += g;
            std::uint32_t valid;
            pending = prepare_group<K, Query>(rays, base, g, root, hits, pr, &valid);
            if constexpr (kStats) {
                stats->rays += g;
                stats->box_tests += std::uint64_t(__builtin_popcount(valid));
            }
        }
        const int l = __builtin_ctz(pending);
        pending &= pending - 1;
        i = base + std::size_t(l);
        r = &pr[l];
        return true;
    }
};

// A ray state whose fields are the caller's locals (trace_one): step() reads
// and writes them by reference, and once inlined they stay in registers.
template <class RD, class Keep, int N>
struct RayRefs {
    RD& rd;
    Keep& pr;
    Hit& best;
    float& cull;
    ChildN<N>& cur;
    int& sp;
    int& t_exp;
    std::size_t& ray;
    StackEntry* stack;
};

// One ray at a time to its end, its state in locals (kFlight == 1: a tree
// that stays in cache, or TraceOptions::in_flight = 1). Against step() on a
// RayState in memory (AMD Zen 4, one thread, ABBA over two rounds,
// simdbvh_bench_scene_desc, 262,144 rays): spheres-1000, every row 10-15%
// faster (BVH16 AVX-512 interior closest 4.22-4.25 -> 4.80-4.83 Mrays/s,
// BVH8 AVX2 primary any 11.98-12.58 -> 13.31-13.64); the dragon with one
// ray in flight forced, 0-6%.
template <class K, int N, class Leaf, class Query, bool kStats, class Node>
inline __attribute__((always_inline)) void trace_one(const Node* nodes, const Aabb* root, const Leaf& leaf,
                                                     std::span<const Ray> rays, std::span<Hit> hits,
                                                     TraceStats* stats) {
    using Keep = typename Leaf::Keep;
    RayFeed<K, Query, kStats> feed(rays, root, hits.data(), stats);
    StackEntry stack[kStackSize<N>];
    std::size_t i;
    const PreparedRay* r;
    while (feed.pop(i, r)) {
        typename K::RayData rd;
        Keep pr;
        Hit best;
        float cull;
        ChildN<N> cur;
        int sp, t_exp;
        std::size_t ray;
        RayRefs<typename K::RayData, Keep, N> s{rd, pr, best, cull, cur, sp, t_exp, ray, stack};
        start<K, N>(s, *r, rays[i], i);
        while (!step<K, N, Leaf, Query, kStats>(nodes, leaf, s, stats)) {}
        Query::finish(best, t_exp, hits[ray]);
    }
}

// The batch loop over any wide tree: `nodes` (NodeN or QNodeN, root at 0), its bounds (nullptr:
// an empty tree) and the leaf intersector, kFlight rays in flight (1 for a
// tree that stays in cache, where interleaving only costs state switches).
template <class K, int N, class Leaf, class Query, bool kStats, int kFlight = kInFlight, class Node>
inline __attribute__((always_inline)) void trace_span(const Node* nodes, const Aabb* root, const Leaf& leaf,
                                                      std::span<const Ray> rays, std::span<Hit> hits,
                                                      TraceStats* stats) {
    if constexpr (kFlight == 1) {
        return trace_one<K, N, Leaf, Query, kStats>(nodes, root, leaf, rays, hits, stats);
    }
    using State = RayState<K, N, typename Leaf::Keep>;
    State states[kFlight];
    int live[kFlight];
    int nlive = 0;
    RayFeed<K, Query, kStats> feed(rays, root, hits.data(), stats);
    auto refill = [&](int slot) {
        std::size_t i;
        const PreparedRay* r;
        if (!feed.pop(i, r)) return false;
        start<K, N>(states[slot], *r, rays[i], i);
        return true;
    };
    for (int w = 0; w < kFlight; ++w)
        if (refill(w)) live[nlive++] = w;
    while (nlive > 0) {
        for (int k = 0; k < nlive;) {
            State& s = states[live[k]];
            if (!step<K, N, Leaf, Query, kStats>(nodes, leaf, s, stats)) {
                if constexpr (kFlight > 1) leaf.prefetch(nodes, s.cur);  // one in flight: nothing to overlap
            } else {
                Query::finish(s.best, s.t_exp, hits[s.ray]);
                if (!refill(live[k])) {
                    live[k] = live[--nlive];
                    continue;
                }
            }
            ++k;
        }
    }
}

// A BvhN: its nodes (the quantized ones when it has them), bounds and Tri8 blocks.
template <class K, int N, class Leaf, class Query, bool kStats, int kFlight = kInFlight>
inline __attribute__((always_inline)) void trace_span(const BvhN<N>& bvh, std::span<const Ray> rays,
                                                      std::span<Hit> hits, TraceStats* stats) {
    const Aabb bounds = bvh.bounds();
    const Aabb* root = bvh.nodes().empty() ? nullptr : &bounds;
    if constexpr (N != 4) {  // a BVH4 has no quantized nodes (WideOptions::quantized_nodes)
        if (!bvh.qnodes().empty())
            return trace_span<K, N, Leaf, Query, kStats, kFlight>(bvh.qnodes().data(), root, Leaf{bvh.blocks().data()},
                                                                  rays, hits, stats);
    }
    trace_span<K, N, Leaf, Query, kStats, kFlight>(bvh.nodes().data(), root, Leaf{bvh.blocks().data()}, rays, hits,
                                                   stats);
}

}  // namespace simdbvh::bvh8::detail

#include "simdbvh/bvh8/internal/stream-inl.h"

namespace simdbvh::bvh8::detail {

// Streams where they pay (stream-inl.h), for kernels that have them;
// kFlight: the single-ray loop's rays in flight, 0 by the tree's size.
template <class K, int N, class Query>
inline __attribute__((always_inline)) bool trace_streams_auto(const BvhN<N>& bvh, std::span<const Ray> rays,
                                                              std::span<Hit> hits, const TraceOptions& o) {
    if constexpr (K::kStreams) {
        if (o.stats || o.packets == Packets::off || !bvh.qnodes().empty() || bvh.nodes().empty()) return false;
        const Aabb bounds = bvh.bounds();
        const bool one =
            one_in_flight(bvh.nodes().size() * sizeof(NodeN<N>) + bvh.blocks().size() * sizeof(Tri8), o.in_flight);
        auto go = [&]<class Leaf>(Leaf leaf) {
            if (one) trace_auto<K, N, Leaf, Query, 1>(bvh.nodes().data(), &bounds, leaf, rays, hits, o.packets);
            else trace_auto<K, N, Leaf, Query, kInFlight>(bvh.nodes().data(), &bounds, leaf, rays, hits, o.packets);
        };
        if (o.test == TriangleTest::watertight) go(Tri8Leaf<K, TriangleTest::watertight, false>{bvh.blocks().data()});
        else go(Tri8Leaf<K, TriangleTest::moller, false>{bvh.blocks().data()});
        return true;
    } else {
        return false;
    }
}

// Triangle test, stats, streams and rays in flight chosen once per batch (stats: 8).
template <class K, int N, class Query>
inline __attribute__((always_inline)) void trace(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits,
                                                 const TraceOptions& o) {
    using enum TriangleTest;
    if constexpr (std::is_same_v<Query, ClosestHit>) {
        if (Traversal<K, N>::intersect_streams(bvh, rays, hits, o)) return;
    } else {
        if (Traversal<K, N>::occluded_streams(bvh, rays, hits, o)) return;
    }
    const bool one = one_in_flight(
        (bvh.qnodes().empty() ? bvh.nodes().size() * sizeof(NodeN<N>) : bvh.qnodes().size() * sizeof(QNodeN<N>)) +
            bvh.blocks().size() * sizeof(Tri8),
        o.in_flight);
    if (o.stats) {
        if (o.test == watertight)
            trace_span<K, N, Tri8Leaf<K, watertight, true>, Query, true>(bvh, rays, hits, o.stats);
        else trace_span<K, N, Tri8Leaf<K, moller, true>, Query, true>(bvh, rays, hits, o.stats);
    } else if (one) {
        if (o.test == watertight)
            trace_span<K, N, Tri8Leaf<K, watertight, false>, Query, false, 1>(bvh, rays, hits, nullptr);
        else trace_span<K, N, Tri8Leaf<K, moller, false>, Query, false, 1>(bvh, rays, hits, nullptr);
    } else {
        if (o.test == watertight)
            trace_span<K, N, Tri8Leaf<K, watertight, false>, Query, false>(bvh, rays, hits, nullptr);
        else trace_span<K, N, Tri8Leaf<K, moller, false>, Query, false>(bvh, rays, hits, nullptr);
    }
}

#undef SIMDBVH_TRAVERSE_INLINE

}  // namespace simdbvh::bvh8::detail

namespace simdbvh::bvh8 {

// The per-ISA entry points (traverse.h, flattened there).
template <class K, int N>
void Traversal<K, N>::intersect(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits,
                                const TraceOptions& o) {
    detail::trace<K, N, detail::ClosestHit>(bvh, rays, hits, o);
}
template <class K, int N>
void Traversal<K, N>::occluded(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits,
                               const TraceOptions& o) {
    detail::trace<K, N, detail::AnyHit>(bvh, rays, hits, o);
}
template <class K, int N>
bool Traversal<K, N>::intersect_streams(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits,
                                        const TraceOptions& o) {
    return detail::trace_streams_auto<K, N, detail::ClosestHit>(bvh, rays, hits, o);
}
template <class K, int N>
bool Traversal<K, N>::occluded_streams(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits,
                                       const TraceOptions& o) {
    return detail::trace_streams_auto<K, N, detail::AnyHit>(bvh, rays, hits, o);
}

}  // namespace simdbvh::bvh8
