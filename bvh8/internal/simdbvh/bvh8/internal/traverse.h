#pragma once
// Internal: the per-ISA wide BVH traversals. Traversal<K, N> is defined once
// (traverse-inl.h) and instantiated per ISA and width in its own translation
// unit (src/scalar, src/avx2, src/avx512), each with the kernels of its ISA
// (K = <isa>::Kernels, a distinct type per ISA); traverse.cpp holds the one
// switch on the ISA.
#include <utility>

#include "simdbvh/kernels/internal/by_isa.h"
#include <cstddef>
#include <span>

#include "simdbvh/bvh8/bvh8.h"

namespace simdbvh::bvh8 {

namespace detail {
// Rays in flight per batch loop: each step ends with its next node or leaf
// prefetched, and the other rays' steps run while those lines arrive (the
// traversal of incoherent rays is bound by the latency of those misses).
#ifndef SIMDBVH_BVH8_IN_FLIGHT
#define SIMDBVH_BVH8_IN_FLIGHT 8
#endif
inline constexpr int kInFlight = SIMDBVH_BVH8_IN_FLIGHT;

// A tree of at most this many bytes is traced one ray at a time: it stays in
// cache, so interleaving rays to hide misses only costs state switches.
// Measured (AMD EPYC Zen 3, L2 512 KiB, AVX2, BVH8, one thread, Google
// Benchmark medians of 5, 1 against 8 in flight): random triangle soups of
// 20000 triangles (about 1.2 MB) 1.22-1.64x faster on primary and incoherent
// rays; 80000 (about 5 MB) 1.37-1.41x on primary rays but 0.73x on incoherent
// closest; 300000: primary 1.26-1.29x, incoherent 0.47-0.49x; the dragon
// (about 50 MB) 0.78-0.96x on primary and diffuse rays; the terrain 1.00-1.17x
// on primary and diffuse rays in one run, 0.48-0.90x on every ray kind in a
// later one (BM_Bvh8InFlight). Sphere trees: 1000 spheres 1.11-1.26x, 20000
// (about 0.6 MB) 1.0-1.2x, 200000 (about 6 MB) 0.63-0.66x on incoherent rays.
// (Those were measured with the RayState loop; one ray in flight now runs
// trace_one, 0-15% faster again: docs/performance_log.md#trace-speed,
// "Instructions per visit", commit d669a90.) With trace_one (2026-11-29,
// commit 2838c6c), AMD Zen 4 (L2 1 MiB, L3 32 MiB), AVX-512 BVH8, 262,144 rays, one thread, 1
// against 8 in flight: dragon-res3 (47,794 triangles, 2.8 MiB) primary
// 1.00x, incoherent 1.06-1.10x, diffuse 1.20-1.26x; dragon-res2 (202,520,
// 11.9 MiB) primary 0.94-1.18x, incoherent 0.64-0.66x, diffuse 1.03-1.06x.
// So the bound moved from 2 to 4 MiB: above the first, well below the second.
inline constexpr std::size_t kInCacheBytes = std::size_t(4) << 20;
inline bool one_in_flight(std::size_t tree_bytes, int requested) {
    return requested == 1 || (requested == 0 && tree_bytes <= kInCacheBytes);
}
}  // namespace detail

namespace scalar {
struct Kernels;
}  // namespace scalar
namespace avx2 {  // x86 only: by_isa never picks it elsewhere
struct Kernels;
}  // namespace avx2
namespace avx512 {
struct Kernels;
}  // namespace avx512

// The wide kernel set of an ISA: f.template operator()<K>() with K one of the
// Kernels above, after require(isa) (the one switch is kernels' by_isa.h).
template <class F>
decltype(auto) with_kernels(Isa isa, F&& f) {
    return kernels::detail::by_isa<scalar::Kernels, avx2::Kernels, avx512::Kernels>(isa, std::forward<F>(f));
}

// Flattened (on the declaration: GCC drops it from an out-of-class template
// member definition), so the whole loop, its kernels and lambdas are one function.
template <class K, int N>
struct Traversal {
    [[gnu::flatten]] static void intersect(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits,
                                           const TraceOptions& o);
    [[gnu::flatten]] static void occluded(const BvhN<N>& bvh, std::span<const Ray> rays, std::span<Hit> hits,
                                          const TraceOptions& o);
    // The stream path (stream-inl.h), a function of its own (inlined into
    // the loops above, the packets of 8 of commit bec07d3 ran 15% slower). False: not taken (scalar kernels,
    // TraceOptions::packets off, quantized nodes, an empty tree).
    [[gnu::flatten, gnu::noinline]] static bool intersect_streams(const BvhN<N>& bvh, std::span<const Ray> rays,
                                                                  std::span<Hit> hits, const TraceOptions& o);
    [[gnu::flatten, gnu::noinline]] static bool occluded_streams(const BvhN<N>& bvh, std::span<const Ray> rays,
                                                                 std::span<Hit> hits, const TraceOptions& o);
};

#define SIMDBVH_WIDE_ISA(isa)                          \
    extern template struct Traversal<isa::Kernels, 4>; \
    extern template struct Traversal<isa::Kernels, 8>; \
    extern template struct Traversal<isa::Kernels, 16>;
SIMDBVH_WIDE_ISA(scalar)
#if defined(__x86_64__)
SIMDBVH_WIDE_ISA(avx2)
SIMDBVH_WIDE_ISA(avx512)
#endif
#undef SIMDBVH_WIDE_ISA

}  // namespace simdbvh::bvh8
