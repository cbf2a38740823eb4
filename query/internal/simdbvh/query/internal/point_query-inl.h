#pragma once
// Internal: the closest-point machinery shared by the BVH2 (closest_point.cpp)
// and the wide trees (query/src/closest_point_wide.cpp): conservative box
// distances, the (distance2, prim) winner, the Morton visiting order.
#include <algorithm>
#include "simdbvh/kernels/error.h"
#include <array>
#include <functional>
#include <utility>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "simdbvh/query/closest_point.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh::detail {

// Box distances are rounded (differences of floats in double); a box is pruned
// only when its distance exceeds the best by more than that rounding, so the
// pruning never changes the answer, ties at equal distance included.
constexpr double kPruneSlack = 1.0 - 0x1p-40;

inline double box_distance2(const Vec3& p, const Aabb& b) {
    auto axis = [](float lo, float hi, float x) {
        const double d = x < lo ? double(lo) - double(x) : (x > hi ? double(x) - double(hi) : 0.0);
        return d * d;
    };
    return axis(b.lo.x, b.hi.x, p.x) + axis(b.lo.y, b.hi.y, p.y) + axis(b.lo.z, b.hi.z, p.z);
}

struct Best {
    explicit Best(double max_distance2) : distance2(max_distance2) {}
    double distance2;
    std::uint32_t prim = kInvalidPrim;
    TrianglePoint at;

    // Smaller squared distance first, ties to the lower triangle id.
    void offer(const TrianglePoint& tp, std::uint32_t id) {
        if (tp.distance2 < distance2 || (tp.distance2 == distance2 && id < prim)) {
            distance2 = tp.distance2;
            prim = id;
            at = tp;
        }
    }
    ClosestPoint result() const {
        if (prim == kInvalidPrim) return ClosestPoint{};
        ClosestPoint c;
        c.point = Vec3{float(at.x), float(at.y), float(at.z)};
        c.distance = float(std::sqrt(distance2));
        c.prim = prim;
        c.u = float(at.u);
        c.v = float(at.v);
        c.distance2 = distance2;
        return c;
    }
};

// One triangle offered to `best`: its box bounds its distance from below, so
// most are rejected here without the exact test.
inline void offer_triangle(Best& best, const Vec3& p, const Vec3& v0, const Vec3& v1, const Vec3& v2, std::uint32_t id,
                           PointQueryStats* stats) {
    Aabb tb;
    tb.grow(v0);
    tb.grow(v1);
    tb.grow(v2);
    if (stats) stats->triangle_tests++;
    if (box_distance2(p, tb) * kPruneSlack > best.distance2) return;
    if (stats) stats->exact_tests++;
    best.offer(closest_point_on_triangle(p, v0, v1, v2), id);
}

inline double max_distance2(const PointQueryOptions& o) {
    if (!(o.max_distance >= 0.0f))
        throw Error("max_distance must be >= 0 (got " + std::to_string(o.max_distance) + ")");
    return double(o.max_distance) * double(o.max_distance);
}

inline bool usable(const Vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

// 30-bit Morton codes (10 bits per axis) of the finite points in their own
// bounds; non-finite points last. Returns the visiting order. With threads > 1
// and enough points, the codes and the radix sort's passes run in chunks on
// threads (per-chunk digit counts, offsets digit-major then chunk: the same
// stable order as one thread).
inline std::vector<std::uint32_t> morton_order(std::span<const Vec3> points, int threads = 1) {
    if (points.size() > 0xFFFFFFFFu) throw Error("too many query points in one batch (at most 2^32 - 1)");
    const std::size_t n = points.size();
    const std::size_t chunks = std::max<std::size_t>(1, std::min<std::size_t>(std::max(threads, 1), n >> 16));
    auto chunk_range = [&](std::size_t c) { return std::pair{n * c / chunks, n * (c + 1) / chunks}; };
    auto each_chunk = [&](const std::function<void(std::size_t)>& f) {
        parallel_for(
            chunks, threads,
            [&](std::size_t b, std::size_t e) {
                for (std::size_t c = b; c < e; ++c) f(c);
            },
            ParallelOptions{.grain = 1});
    };
    std::vector<Aabb> boxes(chunks);
    each_chunk([&](std::size_t c) {
        const auto [b, e] = chunk_range(c);
        for (std::size_t i = b; i < e; ++i)
            if (usable(points[i])) boxes[c].grow(points[i]);
    });
    Aabb box;
    for (const Aabb& cb : boxes) box.grow(cb);
    std::vector<std::uint64_t> keys(n);
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
    each_chunk([&](std::size_t c) {
        const auto [b, e] = chunk_range(c);
        for (std::size_t i = b; i < e; ++i) {
            const Vec3& p = points[i];
            const std::uint64_t code = usable(p)
                                           ? (spread(cell(p.x, lo.x, ext.x)) << 2 |
                                              spread(cell(p.y, lo.y, ext.y)) << 1 | spread(cell(p.z, lo.z, ext.z)))
                                           : (1u << 30);
            keys[i] = code << 32 | i;
        }
    });
    // Stable LSD radix sort on the 31-bit codes (3 passes of 11 bits): the
    // order std::sort gives the (code, index) keys, at a fraction of its time
    // (std::sort was a fifth of an inside query over 100,000 points).
    std::vector<std::uint64_t> tmp(n);
    std::vector<std::array<std::size_t, 2048>> count(chunks);
    for (int shift = 32; shift < 65; shift += 11) {
        each_chunk([&](std::size_t c) {
            const auto [b, e] = chunk_range(c);
            count[c].fill(0);
            for (std::size_t i = b; i < e; ++i) count[c][(keys[i] >> shift) & 2047u]++;
        });
        std::size_t sum = 0;  // offsets: digit-major, then chunk (stable)
        for (std::size_t d = 0; d < 2048; ++d)
            for (std::size_t c = 0; c < chunks; ++c) sum += std::exchange(count[c][d], sum);
        each_chunk([&](std::size_t c) {
            const auto [b, e] = chunk_range(c);
            for (std::size_t i = b; i < e; ++i) tmp[count[c][(keys[i] >> shift) & 2047u]++] = keys[i];
        });
        keys.swap(tmp);
    }
    std::vector<std::uint32_t> order(n);
    each_chunk([&](std::size_t c) {
        const auto [b, e] = chunk_range(c);
        for (std::size_t i = b; i < e; ++i) order[i] = std::uint32_t(keys[i]);
    });
    return order;
}

// The batched form of one tree's single-point query(p, max_d2, stats):
// points in Morton order (neighbours walk the same nodes while they are in
// cache; the order changes the speed only, never a result), on opts.threads.
template <class Query>
void closest_points(std::span<const Vec3> points, std::span<ClosestPoint> out, const PointQueryOptions& opts,
                    const Query& query) {
    simdbvh::detail::check_size(out.size(), points.size(), "out");
    const double max_d2 = max_distance2(opts);
    const std::vector<std::uint32_t> order = morton_order(points, opts.threads);
    if (opts.stats) {
        for (const std::uint32_t i : order) out[i] = query(points[i], max_d2, opts.stats);
        return;
    }
    parallel_for(
        points.size(), opts.threads,
        [&](std::size_t b, std::size_t e) {
            for (std::size_t k = b; k < e; ++k) out[order[k]] = query(points[order[k]], max_d2, nullptr);
        },
        ParallelOptions{.grain = 256});
}

}  // namespace simdbvh::detail
