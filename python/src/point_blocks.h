#pragma once
// The batched point queries in blocks, so that Ctrl-C can stop them between
// library calls (interrupt.h). The library visits a batch's points in Morton
// order, so that neighbours walk the same nodes while they are in cache; a
// block of the caller's points is sparser than the whole batch, and blocks
// in the caller's order cost a fifth more time on the dragon (closest points
// of 2^20 points near its surface). So the points are first put in Morton
// order over the whole batch and the blocks are runs of that order: each is
// a region of space as dense as the batch. The order changes the speed only,
// never an answer (each point's answer is its own).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "interrupt.h"
#include "simdbvh/kernels/aabb.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/vec.h"

namespace simdbvh::python {

// 30-bit Morton codes (10 bits per axis in the finite points' bounds, non-finite points last), sorted stably by a
// radix sort of three 11-bit passes: the visiting order.
inline std::vector<std::uint32_t> morton_order(std::span<const Vec3> points) {
    const std::size_t n = points.size();
    auto usable = [](const Vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); };
    Aabb box;
    for (const Vec3& p : points)
        if (usable(p)) box.grow(p);
    const Vec3 lo = box.lo, ext = box.extent();
    auto spread = [](std::uint32_t v) {  // 10 bits -> every third of 30 bits
        v = (v | (v << 16)) & 0x030000FFu;
        v = (v | (v << 8)) & 0x0300F00Fu;
        v = (v | (v << 4)) & 0x030C30C3u;
        v = (v | (v << 2)) & 0x09249249u;
        return v;
    };
    auto cell = [](float x, float lo, float ext) {
        const float f = ext > 0.0f ? (x - lo) / ext * 1023.0f : 0.0f;
        return std::uint32_t(std::clamp(f, 0.0f, 1023.0f));
    };
    std::vector<std::uint64_t> keys(n), tmp(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3& p = points[i];
        const std::uint64_t code = usable(p) ? (spread(cell(p.x, lo.x, ext.x)) << 2 |
                                                spread(cell(p.y, lo.y, ext.y)) << 1 | spread(cell(p.z, lo.z, ext.z)))
                                             : (1u << 30);
        keys[i] = code << 32 | i;
    }
    for (int shift = 32; shift < 65; shift += 11) {
        std::array<std::size_t, 2048> count{};
        for (const std::uint64_t k : keys) count[(k >> shift) & 2047u]++;
        std::size_t sum = 0;
        for (std::size_t& c : count) sum += std::exchange(c, sum);
        for (const std::uint64_t k : keys) tmp[count[(k >> shift) & 2047u]++] = k;
        keys.swap(tmp);
    }
    std::vector<std::uint32_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = std::uint32_t(keys[i]);
    return order;
}

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
    if (rest.size() > 0xFFFFFFFFu) throw Error("too many query points in one batch (at most 2^32 - 1)");
    const std::vector<std::uint32_t> order = morton_order(rest);
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
