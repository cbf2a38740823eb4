#pragma once
// The batched point queries in blocks, so that Ctrl-C can stop them between
// library calls (interrupt.h). The library visits a batch's points in Morton
// order (detail::morton_order), so that neighbours walk the same nodes while
// they are in cache; a block of the caller's points is sparser than the whole
// batch, and blocks in the caller's order cost a fifth more time on the
// dragon (closest points of 2^20 points near its surface). So the points are
// first put in the library's Morton order over the whole batch and the blocks
// are runs of that order: each is a region of space as dense as the batch.
// The order changes the speed only, never an answer (each point's answer is
// its own).
#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "interrupt.h"
#include "simdbvh/query/internal/point_query-inl.h"
#include "simdbvh/kernels/vec.h"

namespace simdbvh::python {

// out[i] = the answer for points[i], by query(points block, answers block) (a
// library call that spreads its block over the threads): the first 256 points
// as given, timed; the rest in one call when it fits within kWholeTime, else
// in for_blocks' blocks of its Morton order, gathered and scattered; none
// after `interrupt` stops. One call over all the points when the query cannot
// be interrupted (not on Python's main thread). Without the GIL.
template <class Out, class Query>
void for_point_blocks(std::span<const Vec3> points, std::span<Out> out, std::size_t max_block, Interrupt& interrupt,
                      Query&& query) {
    const std::size_t first = std::min<std::size_t>(points.size(), 256);
    if (!interrupt.checks() || first == points.size()) {
        query(points, out);
        return;
    }
    const auto t0 = std::chrono::steady_clock::now();
    g_block_calls.fetch_add(1, std::memory_order_relaxed);
    query(points.first(first), out.first(first));
    const double per_point =
        std::max(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1e-7) / double(first);
    const std::span<const Vec3> rest = points.subspan(first);
    const std::span<Out> rest_out = out.subspan(first);
    if (interrupt.stop()) return;
    if (fits_whole(per_point, rest.size())) {
        g_block_calls.fetch_add(1, std::memory_order_relaxed);
        query(rest, rest_out);
        return;
    }
    const std::vector<std::uint32_t> order = simdbvh::detail::morton_order(rest);
    std::vector<Vec3> in;
    std::vector<Out> res;
    for_blocks(rest.size(), max_block, interrupt, [&](std::size_t b, std::size_t e) {
        in.resize(e - b);
        res.resize(e - b);
        for (std::size_t k = b; k < e; ++k) in[k - b] = rest[order[k]];
        query(std::span<const Vec3>(in), std::span<Out>(res));
        for (std::size_t k = b; k < e; ++k) rest_out[order[k]] = res[k - b];
    });
}

}  // namespace simdbvh::python
