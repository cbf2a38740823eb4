// Closest point queries over BvhN<N> (simdbvh/query/closest_point_wide.h): the
// BVH2's machinery (query/internal/simdbvh/query/internal/point_query-inl.h) over wide nodes and Tri8
// blocks. A block shared by sibling leaves is offered whole: a triangle that
// is not the leaf's own is still one of the mesh's, and the winner is the
// (distance2, id) minimum over every triangle offered, so it cannot change.
// Boxes and triangles are pruned by float lower bounds (point_bounds-inl.h),
// 4 lanes at a time.
#include "simdbvh/query/closest_point_wide.h"

#include "point_bounds-inl.h"
#include "simdbvh/query/internal/point_query-inl.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh {
namespace {

struct Pending {
    std::uint32_t index, count;  // a ChildN
    double distance2;
};

// A leaf's blocks: every triangle's box bound first (8 lanes in float, see
// point_bounds-inl.h), the exact (double) test only for those that may be
// closer than the best so far.
template <int N>
void offer_leaf(detail::Best& best, const Vec3& p, const Tri8* blocks, ChildN<N> c, PointQueryStats* stats) {
    double key[kBlockWidth];
    for (std::uint32_t b = 0; b < c.blocks(); ++b) {
        const Tri8& t = blocks[c.index + b];
        detail::triangle_keys(t, p, key);
        for (int k = 0; k < kBlockWidth; ++k) {
            if (t.prim[k] == kInvalidPrim) continue;
            if (stats) stats->triangle_tests++;
            if (key[k] > best.distance2) continue;
            if (stats) stats->exact_tests++;
            best.offer(closest_point_on_triangle(p, t.v0(k), t.v1(k), t.v2(k)), t.prim[k]);
        }
    }
}

template <int N>
ClosestPoint query(const BvhN<N>& bvh, const Vec3& p, double max_d2, PointQueryStats* stats) {
    if (stats) stats->points++;
    const auto& nodes = bvh.nodes();
    if (nodes.empty() || !detail::usable(p)) return ClosestPoint{};
    const Tri8* blocks = bvh.blocks().data();
    detail::Best best(max_d2);
    if (detail::box_distance2(p, bvh.bounds()) * detail::kPruneSlack > best.distance2) return ClosestPoint{};
    Pending stack[1 + (N - 1) * kMaxDepth];
    int sp = 0;
    ChildN<N> cur = ChildN<N>::inner(0);
    for (;;) {
        if (cur.is_inner()) {
            const NodeN<N>& n = nodes[cur.index];
            if (stats) stats->nodes_visited++;
            double d2[N];  // prune keys (point_bounds-inl.h): prune when d2 > best
            detail::box_keys<N>(n.boxes, p, d2);
            int order[N], hits = 0;
            for (int c = 0; c < N; ++c) {
                if (n.children[c].is_empty()) continue;
                if (d2[c] > best.distance2) continue;
                int k = hits++;  // insertion sort, farthest first
                while (k > 0 && d2[order[k - 1]] < d2[c]) {
                    order[k] = order[k - 1];
                    --k;
                }
                order[k] = c;
            }
            if (hits > 0) {
                for (int k = 0; k + 1 < hits; ++k)
                    stack[sp++] = {n.children[order[k]].index, n.children[order[k]].count, d2[order[k]]};
                cur = n.children[order[hits - 1]];
                continue;
            }
        } else {
            offer_leaf<N>(best, p, blocks, cur, stats);
        }
        for (;;) {  // the nearest pending child that may still hold a closer triangle
            if (sp == 0) return best.result();
            const Pending& s = stack[--sp];
            if (s.distance2 <= best.distance2) {
                cur = ChildN<N>{s.index, s.count};
                break;
            }
        }
    }
}

}  // namespace

template <int N>
ClosestPoint closest_point(const BvhN<N>& bvh, const Vec3& p, const PointQueryOptions& opts) {
    return query(bvh, p, detail::max_distance2(opts), opts.stats);
}

template <int N>
void closest_point(const BvhN<N>& bvh, std::span<const Vec3> points, std::span<ClosestPoint> out,
                   const PointQueryOptions& opts) {
    detail::closest_points(points, out, opts, [&](const Vec3& p, double max_d2, PointQueryStats* stats) {
        return query(bvh, p, max_d2, stats);
    });
}

#define SIMDBVH_WIDTH(N)                                                                           \
    template ClosestPoint closest_point<N>(const BvhN<N>&, const Vec3&, const PointQueryOptions&); \
    template void closest_point<N>(const BvhN<N>&, std::span<const Vec3>, std::span<ClosestPoint>, \
                                   const PointQueryOptions&);
SIMDBVH_WIDTH(4)
SIMDBVH_WIDTH(8)
SIMDBVH_WIDTH(16)
#undef SIMDBVH_WIDTH

}  // namespace simdbvh
