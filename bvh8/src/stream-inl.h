#pragma once
// Any-hit streams: kStream consecutive rays (32, one bit each) share one walk
// of a wide tree, after Embree 3's incoherent occlusion stream
// (rtcOccluded1M: 32 rays, bvh_intersector_stream.cpp's occludedIncoherent).
// At each node every active ray runs its own single-ray node test (K::box:
// its own near/far planes, so the rays need not share an octant), and the
// rays' hit masks are transposed into one ray mask per child
// (K::stream_rays); the hit children are visited in slot order, the lowest
// first, by the rays that hit them, and each one's lines are prefetched as it
// is pushed. A leaf is the leaf intersector per ray; a ray that finds a hit
// leaves the stream. The node test of each ray is its single-ray test bit for
// bit, so a ray visits a superset of the nodes its single-ray walk would visit
// before its first hit, and an any hit is a real hit in [tmin, tmax] (maybe
// another than the single-ray walk's).
//
// Why rays per node instead of a packet's lanes per box (packet-inl.h, which
// closest hits use): an any-hit ray's bound does not shrink, so nothing is
// lost by not ordering children by distance, and the test costs one node test
// per active ray instead of one 8-lane test per child. In-process A/B on
// 1,000,000 rays of a 1000 x 1000 camera, AVX-512, BVH8: the terrain 15.0-15.9
// Mrays/s against 10.7-11.2 with packets of 8, the dragon 17.7-18.9 against
// 13.9-14.7; the benches' 100,000 primary rays (316 x 316): terrain 9.1 against
// 6.9 single-ray, dragon level (9.6 against 9.7); incoherent and diffuse rays
// lose (rays per node test 1.4-2.8), so trace_auto() probes, as for packets.
// Included only by packet-inl.h (the per-ISA translation units).
#include <algorithm>
#include <cstdint>
#include <span>

namespace simdbvh::bvh8::detail {

inline constexpr int kStream = 32;  // rays per stream (one bit each in a uint32 mask)

template <class K, int N, class Leaf, class Query>
inline __attribute__((always_inline)) void trace_stream(const NodeN<N>* nodes, const Aabb* root, const Leaf& leaf,
                                                        std::span<const Ray> rays, std::span<Hit> hits,
                                                        PacketCounts& counts) {
    static_assert(Query::kAnyHit, "streams trace any hits (the children are not visited front to back)");
    using Child = ChildN<N>;
    using Keep = typename Leaf::Keep;
    struct Entry {
        std::uint32_t index, count;  // ChildN
        std::uint32_t rays;          // the stream's rays that hit it
    };
    PacketRay<K, N, Keep> sr[kStream];
    float cull[kStream];
    Entry stack[kStackSize<N>];
    typename K::StreamMasks masks;  // each active ray's child hit mask at the current node
    K::stream_clear(masks);
    std::uint64_t tests = 0, active = 0;
    const std::size_t n = rays.size();
    for (std::size_t base = 0; base < n; base += kStream) {
        const int cnt = int(std::min<std::size_t>(kStream, n - base));
        std::uint32_t live = 0;
        for (int r = 0; r < cnt; ++r) {
            const Ray& ray = rays[base + r];
            const PreparedRay pr = prepare(ray);
            float entry;
            if (!pr.valid || !root || !intersect_box(pr, *root, pr.tmax, &entry)) {  // as start()
                Query::finish(Hit{}, 0, hits[base + r]);
                continue;
            }
            K::pack(sr[r].rd, pr, ray);
            if constexpr (std::is_same_v<Keep, PreparedRay>) sr[r].pr = pr;
            sr[r].best = Hit{};
            sr[r].best.t = pr.tmax;
            sr[r].t_exp = pr.t_exp;
            cull[r] = cull_bound(pr.tmax);
            live |= 1u << r;
        }
        if (live == 0) continue;
        const std::uint32_t started = live;
        int sp = 0;
        Child cur = Child::inner(0);
        std::uint32_t mask = live;
        for (;;) {
            if (cur.is_inner()) {
                const NodeN<N>& node = nodes[cur.index];
                tests++;
                active += std::uint64_t(__builtin_popcount(mask));
                std::uint32_t hit = 0;
                for (std::uint32_t m = mask; m != 0; m &= m - 1) {
                    const int r = __builtin_ctz(m);
                    alignas(4 * N) float entries[N];
                    const std::uint32_t h = K::box(sr[r].rd, node.boxes, cull[r], entries);
                    hit |= h;
                    K::template stream_set<N>(masks, r, h);
                }
                if (hit != 0) {
                    std::uint32_t rays_of[N];
                    K::template stream_rays<N>(masks, hit, rays_of);
                    // Continue with the lowest hit slot; push the others highest first (popped lowest first).
                    const int first = __builtin_ctz(hit);
                    for (std::uint32_t q = hit & (hit - 1); q != 0;) {
                        const int i = 31 - __builtin_clz(q);
                        q &= ~(1u << i);
                        stack[sp++] = {node.children[i].index, node.children[i].count, rays_of[i]};
                        leaf.prefetch(nodes, node.children[i]);
                    }
                    cur = node.children[first];
                    mask = rays_of[first];
                    continue;
                }
            } else {
                for (std::uint32_t m = mask; m != 0; m &= m - 1) {
                    const int r = __builtin_ctz(m);
                    sr[r].cur = cur;
                    if (Query::leaf(leaf, sr[r], sr[r].best, nullptr)) live &= ~(1u << r);
                }
                if (live == 0) break;
            }
            // Pop the next entry with a ray still live.
            bool found = false;
            while (sp > 0) {
                const Entry& e = stack[--sp];
                const std::uint32_t m = e.rays & live;
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
            Query::finish(sr[r].best, sr[r].t_exp, hits[base + r]);
        }
    }
    counts.tests += tests;
    counts.lanes += active;
}

}  // namespace simdbvh::bvh8::detail
