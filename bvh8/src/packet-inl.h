#pragma once
// Packets: coherent rays (a camera's, in image order) traced kPacket at a time
// for closest hits (any hits go in streams of 32 instead: stream-inl.h)
// through one walk of a wide tree. At each node every child box is tested
// against the packet's rays in one SIMD batch (one lane per ray) with the
// single-ray slab test's operations in its order (box8-inl.h's slab_lanes, per
// lane: (plane - o) * rdir, the NaN-discarding max/min, the far bound widened
// by kFarWiden plus the far slack, against cull_bound(best.t)), so each ray
// gets the hit mask and entry distances its own node test would give; a
// child is visited by the rays that hit it, nearest (smallest entry over
// those rays) first, and every hit child's lines are prefetched as it is
// pushed (5% on both scenes); a leaf is the leaf intersector per ray (the
// single-ray triangle kernels; siblings sharing a Tri8 block test it once per
// sibling, not merged as in the single-ray loop). A ray visits every node its single-ray walk would visit
// with a closest hit no farther, so closest hits are the same bits (closer():
// ties to the lower id); an any hit is a real hit in [tmin, tmax] (maybe
// another than the single-ray walk's).
//
// Packets pay when the rays of a packet stay together: on the dragon with a
// 1000 x 1000 camera's rays (5.8 rays per node test on average) they traced
// 1.5x faster than single rays; with a 316 x 316 camera's (3.8 per test)
// 0.77x, since the single-ray loop keeps 8 rays in flight to hide the node
// misses and a packet stalls on them. So trace_auto() measures: blocks of
// kProbeRays go as packets while the rays per node test stay >= 4.5 (any
// hits: as streams while they stay >= 3; PacketCounts::coherent), else single rays for a growing number of blocks
// before the next probe; a block whose packets mostly mix direction octants
// (incoherent and diffuse rays) goes to single rays without a probe.
// Included only by traverse-inl.h (the per-ISA translation units).
#include <algorithm>
#include <cstdint>
#include <limits>
#include <span>

namespace simdbvh::bvh8::detail {

#define SIMDBVH_PACKET_INLINE inline __attribute__((always_inline))

inline constexpr int kPacket = 8;                                   // rays per packet (one 8-lane batch)
inline constexpr std::size_t kProbeRays = 64 * std::size_t(kPacket);  // rays per probe of trace_auto()
inline constexpr std::size_t kMaxBackoff = 128;                    // single-ray blocks between probes, at most

// Node tests and active rays over them, for trace_auto()'s choice.
struct PacketCounts {
    std::uint64_t tests = 0, lanes = 0;
    // At least min_twice / 2 rays per node test: 4.5 for packets of 8; 3 for streams of 32 (stream-inl.h: the
    // 512-ray blocks of the terrain's 100,000 primary rays averaged 3.5-18, 1.3x faster as streams than single
    // rays; incoherent rays 1.4 and diffuse 2.4-2.8, slower as streams).
    SIMDBVH_PACKET_INLINE bool coherent(std::uint64_t min_twice) const { return 2 * lanes >= min_twice * tests; }
};

// A packet's rays, one lane each, for K::packet_load (lanes without a live
// ray are zeros with cull = -inf: they never hit, and every mask is ANDed
// with the live rays anyway).
struct PacketLanes {
    alignas(64) float ox[kPacket], oy[kPacket], oz[kPacket], rx[kPacket], ry[kPacket], rz[kPacket];
    alignas(64) float tmin[kPacket], slack[kPacket], cull[kPacket];
    SIMDBVH_PACKET_INLINE void clear() {
        for (int r = 0; r < kPacket; ++r) {
            ox[r] = oy[r] = oz[r] = rx[r] = ry[r] = rz[r] = tmin[r] = slack[r] = 0.0f;
            cull[r] = -std::numeric_limits<float>::infinity();
        }
    }
    SIMDBVH_PACKET_INLINE void set(int r, const PreparedRay& p) {
        ox[r] = p.org.x, oy[r] = p.org.y, oz[r] = p.org.z;
        rx[r] = p.rdir.x, ry[r] = p.rdir.y, rz[r] = p.rdir.z;
        tmin[r] = p.tmin, slack[r] = p.far_slack, cull[r] = cull_bound(p.tmax);
    }
};

template <class K, int N, class Keep>
struct PacketRay {  // the leaf intersector's state (rd, pr, cur) and the ray's closest hit
    typename K::RayData rd;
    [[no_unique_address]] Keep pr;
    ChildN<N> cur;
    Hit best;
    int t_exp;
};

struct PacketEntry {
    std::uint32_t index, count;  // ChildN
    std::uint32_t rays;          // the packet's rays that hit it
    float entry;                 // their smallest entry distance
};

// The octant of a ray as prepare() sets it (the signs of 1/d: -0 counts as negative).
SIMDBVH_PACKET_INLINE int octant_of(const Vec3& d) {
    return int(std::signbit(d.x)) | (int(std::signbit(d.y)) << 1) | (int(std::signbit(d.z)) << 2);
}

// How many of the packets of kPacket consecutive rays in `rays` have every ray in one direction octant (invalid
// rays included: this only steers trace_auto's choice; trace_packets checks the prepared rays).
SIMDBVH_PACKET_INLINE std::size_t one_octant_packets(std::span<const Ray> rays) {
    std::size_t same = 0;
    for (std::size_t b = 0; b < rays.size(); b += kPacket) {
        const std::size_t e = std::min(rays.size(), b + kPacket);
        const int o = octant_of(rays[b].dir);
        bool one = true;
        for (std::size_t i = b + 1; i < e; ++i) one &= octant_of(rays[i].dir) == o;
        same += one;
    }
    return same;
}

template <class K, int N, class Leaf, class Query>
SIMDBVH_PACKET_INLINE void trace_packets(const NodeN<N>* nodes, const Aabb* root, const Leaf& leaf,
                                         std::span<const Ray> rays, std::span<Hit> hits, PacketCounts& counts) {
    using Child = ChildN<N>;
    using Keep = typename Leaf::Keep;
    PacketRay<K, N, Keep> pk[kPacket];
    PacketLanes lanes;
    typename K::Packet packet;
    PacketEntry stack[kStackSize<N>];
    std::uint64_t tests = 0, active = 0;
    const std::size_t n = rays.size();
    for (std::size_t base = 0; base < n; base += kPacket) {
        const int cnt = int(std::min<std::size_t>(kPacket, n - base));
        std::uint32_t live = 0;
        int octant = -1;
        bool mixed = false;
        lanes.clear();
        for (int r = 0; r < cnt; ++r) {
            const Ray& ray = rays[base + r];
            const PreparedRay pr = prepare(ray);
            float entry;
            if (!pr.valid || !root || !intersect_box(pr, *root, pr.tmax, &entry)) {  // as start()
                Query::finish(Hit{}, 0, hits[base + r]);
                continue;
            }
            if (octant < 0) octant = pr.octant;
            mixed |= pr.octant != octant;
            K::pack(pk[r].rd, pr, ray);
            if constexpr (std::is_same_v<Keep, PreparedRay>) pk[r].pr = pr;
            pk[r].best = Hit{};
            pk[r].best.t = pr.tmax;
            pk[r].t_exp = pr.t_exp;
            lanes.set(r, pr);
            live |= 1u << r;
        }
        if (live == 0) continue;
        if (mixed) {  // one near/far plane choice per packet: rays of several octants go one at a time
            tests += kPacket;
            active += kPacket;
            trace_span<K, N, Leaf, Query, false, 1>(nodes, root, leaf, rays.subspan(base, std::size_t(cnt)),
                                                    hits.subspan(base, std::size_t(cnt)), nullptr);
            continue;
        }
        K::packet_load(packet, lanes);
        // Plane p of a BoxN: N floats from p * N (lo_x, hi_x, lo_y, hi_y, lo_z, hi_z); near = hi for a negative direction.
        const int px = octant & 1, py = (octant >> 1) & 1, pz = (octant >> 2) & 1;
        const int near_x = px * N, far_x = (1 - px) * N, near_y = (2 + py) * N, far_y = (3 - py) * N;
        const int near_z = (4 + pz) * N, far_z = (5 - pz) * N;
        const std::uint32_t started = live;
        int sp = 0;
        Child cur = Child::inner(0);
        std::uint32_t mask = live;
        for (;;) {
            if (cur.is_inner()) {
                const NodeN<N>& node = nodes[cur.index];
                const float* pl = reinterpret_cast<const float*>(&node.boxes);
                tests++;
                active += std::uint64_t(__builtin_popcount(mask));
                std::uint32_t hit_children = 0, rays_of[N];
                float entry_of[N];
                for (int i = 0; i < N; ++i) {
                    if (node.children[i].is_empty()) continue;
                    alignas(64) float e[kPacket];
                    const std::uint32_t h = K::packet_box(packet, pl[near_x + i], pl[far_x + i], pl[near_y + i],
                                                          pl[far_y + i], pl[near_z + i], pl[far_z + i], mask, e);
                    if (h == 0) continue;
                    float emin = std::numeric_limits<float>::infinity();
                    for (std::uint32_t q = h; q != 0; q &= q - 1) emin = std::min(emin, e[__builtin_ctz(q)]);
                    hit_children |= 1u << i;
                    rays_of[i] = h;
                    entry_of[i] = emin;
                }
                if (hit_children != 0) {  // push them farthest deepest, continue with the nearest
                    const int base_sp = sp;
                    for (std::uint32_t h = hit_children; h != 0; h &= h - 1) {
                        const int i = __builtin_ctz(h);
                        const float e = entry_of[i];
                        int k = sp++;
                        while (k > base_sp && stack[k - 1].entry < e) {
                            stack[k] = stack[k - 1];
                            --k;
                        }
                        stack[k] = {node.children[i].index, node.children[i].count, rays_of[i], e};
                        leaf.prefetch(nodes, node.children[i]);  // 5% (dragon and terrain, 1000 x 1000 camera)
                    }
                    --sp;
                    cur = Child{stack[sp].index, stack[sp].count};
                    mask = stack[sp].rays;
                    continue;
                }
            } else {
                bool shrunk = false;
                for (std::uint32_t m = mask; m != 0; m &= m - 1) {
                    const int r = __builtin_ctz(m);
                    pk[r].cur = cur;
                    const float before = pk[r].best.t;
                    if (Query::leaf(leaf, pk[r], pk[r].best, nullptr)) live &= ~(1u << r);  // any hit: done
                    if (pk[r].best.t != before) {
                        lanes.cull[r] = cull_bound(pk[r].best.t);
                        shrunk = true;
                    }
                }
                if (live == 0) break;
                if (shrunk) K::packet_cull(packet, lanes);
            }
            // Pop the nearest entry with a ray still live and in front of its closest hit.
            bool found = false;
            while (sp > 0) {
                const PacketEntry& e = stack[--sp];
                const std::uint32_t m = e.rays & live & K::packet_front(packet, e.entry);
                if (m != 0) {
                    cur = Child{e.index, e.count};
                    mask = m;
                    found = true;
                    break;
                }
            }
            if (!found) break;
        }
        for (std::uint32_t m = started; m != 0; m &= m - 1) {
            const int r = __builtin_ctz(m);
            Query::finish(pk[r].best, pk[r].t_exp, hits[base + r]);
        }
    }
    counts.tests += tests;
    counts.lanes += active;
}

}  // namespace simdbvh::bvh8::detail

#include "stream-inl.h"

namespace simdbvh::bvh8::detail {

// The batch loop with packets (closest hits) or streams (any hits, stream-inl.h) where they pay (see the top of
// this file; a stream's rays per node test are measured the same way).
// kFlight: the single-ray loop's rays in flight.
template <class K, int N, class Leaf, class Query, int kFlight>
SIMDBVH_PACKET_INLINE void trace_auto(const NodeN<N>* nodes, const Aabb* root, const Leaf& leaf,
                                      std::span<const Ray> rays, std::span<Hit> hits, Packets mode) {
    const std::size_t n = rays.size();
    std::size_t i = 0, backoff = 1;
    while (i < n) {
        const std::size_t e = std::min(n, i + (mode == Packets::on ? n : kProbeRays));
        const std::span<const Ray> block = rays.subspan(i, e - i);
        const std::size_t packets = (block.size() + kPacket - 1) / kPacket;
        PacketCounts c;
        if (mode == Packets::on || 4 * one_octant_packets(block) >= 3 * packets) {
            if constexpr (Query::kAnyHit) trace_stream<K, N, Leaf, Query>(nodes, root, leaf, block, hits.subspan(i, e - i), c);
            else trace_packets<K, N, Leaf, Query>(nodes, root, leaf, block, hits.subspan(i, e - i), c);
            i = e;
            if (c.coherent(Query::kAnyHit ? 6 : 9)) {
                backoff = 1;
                continue;
            }
        }
        const std::size_t e2 = std::min(n, i + backoff * kProbeRays);
        trace_span<K, N, Leaf, Query, false, kFlight>(nodes, root, leaf, rays.subspan(i, e2 - i),
                                                      hits.subspan(i, e2 - i), nullptr);
        i = e2;
        backoff = std::min(backoff * 2, kMaxBackoff);
    }
}

#undef SIMDBVH_PACKET_INLINE

}  // namespace simdbvh::bvh8::detail
