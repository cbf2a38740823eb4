#pragma once
// Streams (TraceOptions::packets): kStream consecutive rays (32, one bit each
// in a mask) share one walk of a wide tree, after Embree 3's ray streams
// (bvh_intersector_stream.cpp: 32 rays, a ray mask per stack entry). At each
// node every active ray runs its own single-ray node test (K::box: its own
// near/far planes and cull bound, so the rays need not share an octant), and
// each ray's bit goes into the lanes of the children it hits, giving one ray
// mask per child (K::stream_add); a child is visited by the rays that hit it, and each hit
// child's lines are prefetched as it is pushed. Leaves run the leaf
// intersector per ray.
// The hit children are visited nearest first (the smallest entry over their
// rays, gathered in the same pass, K::stream_add).
// - Closest hits: a popped entry goes on with the rays whose cull bound it is
//   still in front of (K::stream_front). Each ray's node tests are its
//   single-ray tests bit for bit, and it visits every node its single-ray
//   walk would visit with a closest hit no farther, so closest hits are the
//   same bits (ties to the lower id).
// - Any hits: a ray that finds a hit leaves the stream. An any hit is a real
//   hit in [tmin, tmax], maybe another than the single-ray walk's. Nearest
//   first against slot order (Embree's), in-process A/B, AVX-512, Mrays/s:
//   the benches' 100,000 primary rays, dragon BVH8 9.6-9.9 -> 10.5-11.0,
//   BVH16 11.1-11.5 -> 11.4-12.2, terrain level; the 1000 x 1000 camera,
//   terrain 2-6% slower, dragon level.
//
// Streams replaced packets of 8 (commit bec07d3: one child box against 8 rays
// per batch), which they beat everywhere measured: in-process A/B, AVX-512, BVH8,
// Mrays/s, packets of 8 -> streams: 1000 x 1000 camera, closest hits, terrain
// 13.5 -> 18.7, dragon 18.1 -> 24.1; any hits, terrain 10.7-11.2 -> 15.0-15.9,
// dragon 13.9-14.7 -> 17.7-18.9; the benches' 100,000 primary rays (316 x 316
// camera), closest, terrain 7.6 -> 10.2 and dragon 9.0 -> 11.3 (single rays 7.7
// and 10.4). A ray-major test costs one node test per active ray instead of
// one 8-lane test per child, and 32 rays share each node's fetch.
//
// Streams pay only when their rays stay together: incoherent and diffuse rays
// (1.4-3.0 rays per node test) ran 0.5-0.8x single rays, which keep 8 rays in
// flight to hide node misses where a stream waits on them. So trace_auto()
// measures: blocks of kProbeRays go as streams while the rays per node test
// stay >= 3.5 (closest) or 3 (any: the terrain's 100,000 primary rays had
// 512-ray blocks at 3.5-4.5 that still gained), else single rays for a
// growing number of blocks before the next probe; a block whose groups of 8
// rays mostly mix direction octants (incoherent and diffuse rays) goes to
// single rays without a probe.
// Included only by traverse-inl.h (the per-ISA translation units).
#include <algorithm>
#include <cstdint>
#include <limits>
#include <span>

namespace simdbvh::bvh8::detail {

#define SIMDBVH_STREAM_INLINE inline __attribute__((always_inline))

inline constexpr int kStream = 32;               // rays per stream (one bit each in a uint32 mask)
inline constexpr std::size_t kProbeRays = 512;   // rays per probe of trace_auto()
inline constexpr std::size_t kMaxBackoff = 128;  // single-ray blocks between probes, at most

// Node tests and active rays over them, for trace_auto()'s choice.
struct StreamCounts {
    std::uint64_t tests = 0, rays = 0;
    // At least min_twice / 2 rays per node test.
    SIMDBVH_STREAM_INLINE bool coherent(std::uint64_t min_twice) const { return 2 * rays >= min_twice * tests; }
};

template <class K, int N, class Keep>
struct StreamRay {  // RayState's fields but its stack, so start() fills it: the leaf intersector's state (rd, pr, cur)
    typename K::RayData rd;
    [[no_unique_address]] Keep pr;
    Hit best;
    float cull;  // unused here (start() sets it; the stream keeps cull[])
    ChildN<N> cur;
    int sp;  // unused here (start() sets it)
    int t_exp;
    std::size_t ray;
};

// The octant of a ray as prepare() sets it (the signs of 1/d: -0 counts as negative).
SIMDBVH_STREAM_INLINE int octant_of(const Vec3& d) {
    return int(std::signbit(d.x)) | (int(std::signbit(d.y)) << 1) | (int(std::signbit(d.z)) << 2);
}

// How many of the groups of 8 consecutive rays in `rays` have every ray in one direction octant (invalid rays
// included): a cheap sign of incoherent input for trace_auto's choice, not a condition of the streams.
SIMDBVH_STREAM_INLINE std::size_t one_octant_groups(std::span<const Ray> rays) {
    std::size_t same = 0;
    for (std::size_t b = 0; b < rays.size(); b += 8) {
        const std::size_t e = std::min(rays.size(), b + 8);
        const int o = octant_of(rays[b].dir);
        bool one = true;
        for (std::size_t i = b + 1; i < e; ++i) one &= octant_of(rays[i].dir) == o;
        same += one;
    }
    return same;
}

template <class K, int N, class Leaf, class Query>
SIMDBVH_STREAM_INLINE void trace_stream(const NodeN<N>* nodes, const Aabb* root, const Leaf& leaf,
                                        std::span<const Ray> rays, std::span<Hit> hits, StreamCounts& counts) {
    constexpr bool kAny = Query::kAnyHit;
    using Child = ChildN<N>;
    using Keep = typename Leaf::Keep;
    struct Entry {
        std::uint32_t index, count;  // ChildN
        std::uint32_t rays;          // the stream's rays that hit it
        float entry;                 // their smallest entry distance (closest hits)
    };
    constexpr int kLanes = (N + 7) / 8 * 8;  // per-child lanes, N rounded up to 8 (K::stream_add)
    StreamRay<K, N, Keep> sr[kStream];
    PreparedRay pr[8];
    alignas(64) float cull[kStream];  // each ray's cull_bound(best.t); -inf for no ray
    Entry stack[kStackSize<N>];
    std::uint64_t tests = 0, active = 0;
    const std::size_t n = rays.size();
    for (std::size_t base = 0; base < n; base += kStream) {
        const int cnt = int(std::min<std::size_t>(kStream, n - base));
        std::uint32_t live = 0;
        for (int r = 0; r < kStream; ++r) cull[r] = -std::numeric_limits<float>::infinity();
        for (int g0 = 0; g0 < cnt; g0 += 8) {  // prepared 8 at a time (RayFeed, traverse-inl.h)
            const std::size_t g = std::size_t(std::min(8, cnt - g0));
            std::uint32_t valid;
            const std::uint32_t m =
                prepare_group<K, Query>(rays, base + std::size_t(g0), g, root, hits.data(), pr, &valid);
            for (std::uint32_t q = m; q != 0; q &= q - 1) {
                const int l = __builtin_ctz(q), r = g0 + l;
                start<K, N>(sr[r], pr[l], rays[base + std::size_t(r)], base + std::size_t(r));
                cull[r] = cull_bound(sr[r].best.t);
                live |= 1u << r;
            }
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
                auto acc = K::template stream_init<N>();  // per child: its rays and their smallest entry
                for (std::uint32_t m = mask; m != 0; m &= m - 1) {
                    const int r = __builtin_ctz(m);
                    alignas(64) float entries[kLanes];
                    const std::uint32_t h = K::box(sr[r].rd, node.boxes, cull[r], entries);
                    hit |= h;
                    K::template stream_add<N>(acc, r, h, entries);
                }
                if (hit != 0) {
                    // Push them farthest deepest, continue with the nearest.
                    alignas(64) std::uint32_t rays_of[kLanes];
                    alignas(64) float near_of[kLanes];
                    K::template stream_store<N>(acc, rays_of, near_of);
                    const int base_sp = sp;
                    for (std::uint32_t q = hit; q != 0; q &= q - 1) {
                        const int i = __builtin_ctz(q);
                        const float e = near_of[i];
                        int k = sp++;
                        while (k > base_sp && stack[k - 1].entry < e) {
                            stack[k] = stack[k - 1];
                            --k;
                        }
                        stack[k] = {node.children[i].index, node.children[i].count, rays_of[i], e};
                        leaf.prefetch(nodes, node.children[i]);
                    }
                    --sp;
                    cur = Child{stack[sp].index, stack[sp].count};
                    mask = stack[sp].rays;
                    continue;
                }
            } else {
                for (std::uint32_t m = mask; m != 0; m &= m - 1) {
                    const int r = __builtin_ctz(m);
                    sr[r].cur = cur;
                    if (Query::leaf(leaf, sr[r], sr[r].best, nullptr)) live &= ~(1u << r);  // any hit: done
                    if constexpr (!kAny) cull[r] = cull_bound(sr[r].best.t);
                }
                if (live == 0) break;
            }
            // Pop the next entry with a ray still live (closest hits: and still in front of its closest hit).
            bool found = false;
            while (sp > 0) {
                const Entry& e = stack[--sp];
                std::uint32_t m = e.rays & live;
                if constexpr (!kAny) m &= K::stream_front(cull, e.entry);
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
            Query::finish(sr[r].best, sr[r].t_exp, hits[sr[r].ray]);
        }
    }
    counts.tests += tests;
    counts.rays += active;
}

// The batch loop with streams where they pay (see the top of this file).
// kFlight: the single-ray loop's rays in flight.
template <class K, int N, class Leaf, class Query, int kFlight>
SIMDBVH_STREAM_INLINE void trace_auto(const NodeN<N>* nodes, const Aabb* root, const Leaf& leaf,
                                      std::span<const Ray> rays, std::span<Hit> hits, Packets mode) {
    constexpr std::uint64_t kMinTwice = Query::kAnyHit ? 6 : 7;  // rays per node test, times 2
    const std::size_t n = rays.size();
    std::size_t i = 0, backoff = 1;
    while (i < n) {
        const std::size_t e = std::min(n, i + (mode == Packets::on ? n : kProbeRays));
        const std::span<const Ray> block = rays.subspan(i, e - i);
        const std::size_t groups = (block.size() + 7) / 8;
        StreamCounts c;
        if (mode == Packets::on || 4 * one_octant_groups(block) >= 3 * groups) {
            trace_stream<K, N, Leaf, Query>(nodes, root, leaf, block, hits.subspan(i, e - i), c);
            i = e;
            if (c.coherent(kMinTwice)) {
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

#undef SIMDBVH_STREAM_INLINE

}  // namespace simdbvh::bvh8::detail
