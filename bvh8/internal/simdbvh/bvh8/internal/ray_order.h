#pragma once
// Internal: the order a wide tree's batch is traced in (TraceOptions::reorder).
// Rays are traced one at a time (or in streams) and each ray's hit does not
// depend on the others, so a batch may be traced in any order and its hits
// written back to the caller's positions: the same bits. Diffuse bounces,
// which a renderer makes in pixel order with random directions, are the batch
// this is for: sorted, neighbours start close together and go one way, and the
// streams of 32 rays (stream-inl.h) take them (measured: the gain is the
// streams'; with streams off sorted bounces ran no faster).
//
// The key of a ray (21 bits): the Morton code of its origin's cell in an 8 x
// 8 x 8 grid over the tree's bounds, then its direction octant (the signs of
// d, -0 negative, as the traversal's), then the Morton code of its origin's
// cell of a 64^3 grid within that cell (origins outside the bounds are
// clamped to them, non-finite coordinates go to cell 0). Measured against the
// other keys tried: docs/performance_log.md#trace-speed, "Sorted batches"
// (2026-11-29, commit d5554f3).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "simdbvh/kernels/aabb.h"
#include "simdbvh/kernels/ray.h"

namespace simdbvh::bvh8::detail {

// Batches smaller than this keep their order under Reorder::automatic, and so
// do batches with fewer rays than this per 8^3 cell their origins occupy:
// the dragon's diffuse bounces (in 155 of the 512 cells), BVH8 and BVH16
// AVX-512, sorted against the caller's order, closest / any hits: 16,384 rays
// 0.94-0.95x / 0.97-1.01x, 32,768 (211 per cell) 0.96x / 1.00-1.03x, 100,000
// (645 per cell) 1.04-1.06x / 1.12-1.15x, 262,144 1.16-1.17x / 1.26-1.31x;
// the terrain's (269 cells): 100,000 (372 per cell) 1.05-1.06x / 1.18-1.20x,
// 262,144 1.19-1.24x / 1.29-1.36x (2026-11-29, commit d5554f3, AMD EPYC Zen 4). The denser the
// bounces, the more of each stream of 32 stays together.
inline constexpr std::size_t kReorderMinRays = 16384;
inline constexpr std::size_t kReorderRaysPerCell = 300;
// At most this many 8^3 cells hold the sampled origins of rays that share an origin (scattered()).
inline constexpr std::size_t kReorderSharedOriginCells = 8;
// Rays sorted together at most (their positions fit in the key's low bits).
inline constexpr int kReorderIndexBits = 20;
inline constexpr std::size_t kReorderSegment = std::size_t(1) << kReorderIndexBits;
// Rays gathered, traced and scattered back at a time (per thread).
inline constexpr std::size_t kReorderBlock = 16384;

inline constexpr int kFineBits = 9;  // the key's low bits: the 64^3 cell within the 8^3 cell
std::uint32_t ray_key(const Ray& ray, const Aabb& bounds);

// Reorder::automatic's test: true when (1) the batch is not already in an
// order that keeps neighbours together: more than a quarter of 1,024 evenly
// spaced pairs of consecutive rays change 8^3 cell or octant (a camera's rays
// in image order share their origin and mostly their octant: kept; diffuse
// bounces in pixel order change octant in 7 pairs of 8), or it is in such an
// order but its origins spread over more than kReorderSharedOriginCells cells
// (shadow rays from the primary hits toward one light), (2) the origins lie
// on surfaces within the tree's bounds: at least half of 4,096 evenly spaced
// rays start inside the bounds, and those in fewer than 3/4 of the 512 cells
// (rays from outside, as the benches' incoherent rays, or from random points
// filling the bounds: sorted, the dragon's incoherent rays ran 12-17% slower;
// the sort costs and the streams do not pay for them), and (3) there are at
// least kReorderRaysPerCell rays per cell they occupy.
bool scattered(std::span<const Ray> rays, const Aabb& bounds);
// The same on n rays given by ray_at(i) (it reads about 6,000 of them).
bool scattered(std::size_t n, const std::function<Ray(std::size_t)>& ray_at, const Aabb& bounds);

// The batch's positions in traced order: order[i] is the position (in rays)
// of the i-th ray to trace. rays.size() <= kReorderSegment. Stable: rays with
// equal keys keep their order. `work` is scratch (resized).
void sort_rays(std::span<const Ray> rays, const Aabb& bounds, std::vector<std::uint64_t>& order,
               std::vector<std::uint64_t>& work);

inline std::uint32_t order_index(std::uint64_t v) {
    return std::uint32_t(v & ((std::uint64_t(1) << kReorderIndexBits) - 1));
}

}  // namespace simdbvh::bvh8::detail
