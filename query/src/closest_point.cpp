// Closest point queries over the BVH2 (see simdbvh/query/closest_point.h):
// depth first, nearer child first by box distance, pruned by the best squared
// distance so far; and the brute force with the same rule.
#include "simdbvh/query/closest_point.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "simdbvh/query/internal/point_query-inl.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh {
namespace {

using detail::Best;
using detail::box_distance2;
using detail::kPruneSlack;
using detail::max_distance2;
using detail::usable;

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
            for (std::uint32_t i = n.first, e = n.first + n.count; i < e; ++i)
                detail::offer_triangle(best, p, tris[i].v0, tris[i].v1, tris[i].v2, ids[i], stats);
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

}  // namespace

ClosestPoint closest_point(const Bvh2& bvh, const Vec3& p, const PointQueryOptions& opts) {
    return query(bvh, p, max_distance2(opts), opts.stats);
}

void closest_point(const Bvh2& bvh, std::span<const Vec3> points, std::span<ClosestPoint> out,
                   const PointQueryOptions& opts) {
    detail::closest_points(points, out, opts, [&](const Vec3& p, double max_d2, PointQueryStats* stats) {
        return query(bvh, p, max_d2, stats);
    });
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
