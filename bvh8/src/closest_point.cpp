// Closest point queries over BvhN<N> (simdbvh/bvh8/closest_point.h): the
// BVH2's machinery (bvh2/src/point_query-inl.h) over wide nodes and Tri8
// blocks. A block shared by sibling leaves is offered whole: a triangle that
// is not the leaf's own is still one of the mesh's, and the winner is the
// (distance2, id) minimum over every triangle offered, so it cannot change.
#include "simdbvh/bvh8/closest_point.h"

#include "point_query-inl.h"
#include "simdbvh/kernels/parallel.h"

namespace simdbvh {
namespace {

struct Pending {
    std::uint32_t index, count;  // a ChildN
    double distance2;
};

template <int N>
void offer_leaf(detail::Best& best, const Vec3& p, const Tri8* blocks, ChildN<N> c, PointQueryStats* stats) {
    for (std::uint32_t b = 0; b < c.blocks(); ++b) {
        const Tri8& t = blocks[c.index + b];
        for (int k = 0; k < kBlockWidth; ++k)
            if (t.prim[k] != kInvalidPrim) detail::offer_triangle(best, p, t.v0(k), t.v1(k), t.v2(k), t.prim[k], stats);
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
            double d2[N];
            int order[N], hits = 0;
            for (int c = 0; c < N; ++c) {
                if (n.children[c].is_empty()) continue;
                d2[c] = detail::box_distance2(p, n.boxes.get(c));
                if (d2[c] * detail::kPruneSlack > best.distance2) continue;
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
            if (s.distance2 * detail::kPruneSlack <= best.distance2) {
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

#define SIMDBVH_WIDTH(N)                                                                                      \
    template ClosestPoint closest_point<N>(const BvhN<N>&, const Vec3&, const PointQueryOptions&);           \
    template void closest_point<N>(const BvhN<N>&, std::span<const Vec3>, std::span<ClosestPoint>,            \
                                   const PointQueryOptions&);
SIMDBVH_WIDTH(4)
SIMDBVH_WIDTH(8)
SIMDBVH_WIDTH(16)
#undef SIMDBVH_WIDTH

}  // namespace simdbvh
