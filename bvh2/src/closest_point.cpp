// Closest point queries over the BVH2 (see simdbvh/bvh2/closest_point.h):
// depth first, nearer child first by box distance, pruned by the best squared
// distance so far; and the brute force with the same rule.
#include "simdbvh/bvh2/closest_point.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "simdbvh/kernels/parallel.h"

namespace simdbvh {
namespace {

// Box distances are rounded (differences of floats in double); a box is pruned
// only when its distance exceeds the best by more than that rounding, so the
// pruning never changes the answer, ties at equal distance included.
constexpr double kPruneSlack = 1.0 - 0x1p-40;

double box_distance2(const Vec3& p, const Aabb& b) {
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

double max_distance2(const PointQueryOptions& o) {
    if (!(o.max_distance >= 0.0f))
        throw Error("max_distance must be >= 0 (got " + std::to_string(o.max_distance) + ")");
    return double(o.max_distance) * double(o.max_distance);
}

bool usable(const Vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

struct StackEntry {
    std::uint32_t node;
    double distance2;
};

ClosestPoint query(const Bvh2& bvh, const Vec3& p, double max_d2, PointQueryStats* stats) {
    if (stats) stats->points++;
    const auto& nodes = bvh.nodes();
    if (nodes.empty() || !usable(p)) return ClosestPoint{};
    const TriangleVerts* tris = bvh.triangles().data();
    const std::uint32_t* ids = bvh.prim_ids().data();
    Best best(max_d2);
    if (box_distance2(p, nodes[0].box) * kPruneSlack > best.distance2) return ClosestPoint{};
    StackEntry stack[kMaxDepth + 1];
    int sp = 0;
    std::uint32_t idx = 0;
    for (;;) {
        const Node2& n = nodes[idx];
        if (stats) stats->nodes_visited++;
        if (!n.is_leaf()) {
            const double da = box_distance2(p, nodes[n.first].box), db = box_distance2(p, nodes[n.first + 1].box);
            const bool ha = da * kPruneSlack <= best.distance2, hb = db * kPruneSlack <= best.distance2;
            if (ha && hb) {
                const bool a_first = da <= db;
                stack[sp++] = {a_first ? n.first + 1 : n.first, a_first ? db : da};
                idx = a_first ? n.first : n.first + 1;
                continue;
            }
            if (ha || hb) {
                idx = ha ? n.first : n.first + 1;
                continue;
            }
        } else {
            for (std::uint32_t i = n.first, e = n.first + n.count; i < e; ++i) {
                const TriangleVerts& t = tris[i];
                // The triangle's box bounds its distance from below: most are
                // rejected here without the exact test.
                Aabb tb;
                tb.grow(t.v0);
                tb.grow(t.v1);
                tb.grow(t.v2);
                if (stats) stats->triangle_tests++;
                if (box_distance2(p, tb) * kPruneSlack > best.distance2) continue;
                if (stats) stats->exact_tests++;
                best.offer(closest_point_on_triangle(p, t.v0, t.v1, t.v2), ids[i]);
            }
        }
        for (;;) {  // the nearest pending node that may still hold a closer triangle
            if (sp == 0) return best.result();
            const StackEntry& s = stack[--sp];
            if (s.distance2 * kPruneSlack <= best.distance2) {
                idx = s.node;
                break;
            }
        }
    }
}

// 30-bit Morton codes (10 bits per axis) of the finite points in their own
// bounds; non-finite points last. Returns the visiting order.
std::vector<std::uint32_t> morton_order(std::span<const Vec3> points) {
    if (points.size() > 0xFFFFFFFFu) throw Error("too many query points in one batch (at most 2^32 - 1)");
    Aabb b;
    for (const Vec3& p : points)
        if (usable(p)) b.grow(p);
    std::vector<std::uint64_t> keys(points.size());
    const Vec3 lo = b.lo, e = b.extent();
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
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3& p = points[i];
        const std::uint64_t code = usable(p) ? (spread(cell(p.x, lo.x, e.x)) << 2 | spread(cell(p.y, lo.y, e.y)) << 1 |
                                                spread(cell(p.z, lo.z, e.z)))
                                             : (1u << 30);
        keys[i] = code << 32 | i;
    }
    std::sort(keys.begin(), keys.end());
    std::vector<std::uint32_t> order(points.size());
    for (std::size_t i = 0; i < keys.size(); ++i) order[i] = std::uint32_t(keys[i]);
    return order;
}

}  // namespace

ClosestPoint closest_point(const Bvh2& bvh, const Vec3& p, const PointQueryOptions& opts) {
    return query(bvh, p, max_distance2(opts), opts.stats);
}

void closest_point(const Bvh2& bvh, std::span<const Vec3> points, std::span<ClosestPoint> out,
                   const PointQueryOptions& opts) {
    if (out.size() < points.size()) throw Error("output span is smaller than points span");
    const double max_d2 = max_distance2(opts);
    // Points in Morton order: neighbours walk the same nodes while they are in
    // cache (the order changes the speed only, never a result).
    const std::vector<std::uint32_t> order = morton_order(points);
    if (opts.stats) {
        for (const std::uint32_t i : order) out[i] = query(bvh, points[i], max_d2, opts.stats);
        return;
    }
    parallel_for(points.size(), opts.threads, [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) out[order[k]] = query(bvh, points[order[k]], max_d2, nullptr);
    }, ParallelOptions{.grain = 256});
}

ClosestPoint brute_force_closest_point(const Mesh& mesh, const Vec3& p, const PointQueryOptions& opts) {
    Best best(max_distance2(opts));
    if (!usable(p)) return ClosestPoint{};
    const std::size_t nv = mesh.positions.size();
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const Triangle& t = mesh.triangles[i];
        if (t[0] >= nv || t[1] >= nv || t[2] >= nv) continue;  // invalid: never closest
        best.offer(closest_point_on_triangle(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]),
                   std::uint32_t(i));
    }
    return best.result();
}

}  // namespace simdbvh
