// Exact inside/outside by crossing counting along an axis (see simdbvh/query/inside.h
// and docs/exact_crossings.md).
#include "simdbvh/query/inside.h"
#include "simdbvh/kernels/error.h"

#include <cmath>
#include <string>

#include "simdbvh/query/internal/crossing-inl.h"
#include "simdbvh/query/internal/point_query-inl.h"
#include "simdbvh/platform/parallel.h"

namespace simdbvh {
namespace {

using detail::crossing;
using detail::usable;
using Counter = detail::CrossingCounter;

template <class Frame>
PointSide classify_along(const Bvh2& bvh, const Vec3& p, const InsideOptions& o, Frame f) {
    Counter cnt;
    const auto& nodes = bvh.nodes();
    if (!f.reaches(nodes[0].box, p)) return cnt.result(o, f.ray());
    const TriangleVerts* tris = bvh.triangles().data();
    std::uint32_t stack[kMaxDepth + 1];
    int sp = 0;
    std::uint32_t idx = 0;
    for (;;) {
        const Node2& n = nodes[idx];
        if (!n.is_leaf()) {
            const bool ha = f.reaches(nodes[n.first].box, p), hb = f.reaches(nodes[n.first + 1].box, p);
            if (ha && hb) stack[sp++] = n.first + 1;
            if (ha || hb) {
                idx = ha ? n.first : n.first + 1;
                continue;
            }
        } else {
            for (std::uint32_t i = n.first, e = n.first + n.count; i < e; ++i)
                cnt.add(crossing(f, tris[i].v0, tris[i].v1, tris[i].v2, p));
        }
        if (sp == 0) return cnt.result(o, f.ray());
        idx = stack[--sp];
    }
}

PointSide classify(const Bvh2& bvh, const Vec3& p, const InsideOptions& o) {
    if (!usable(p) || bvh.nodes().empty()) return Counter{}.result(o);
    return detail::visit_frame(detail::ray_frame(o.ray, bvh.nodes()[0].box, p),
                               [&](auto f) { return classify_along(bvh, p, o, f); });
}

}  // namespace

CountRay count_ray_named(std::string_view name) {
    static constexpr std::string_view names[] = {"+x", "-x", "+y", "-y", "+z", "-z", "shortest"};
    for (int k = 0; k <= int(CountRay::shortest); ++k)
        if (name == names[k]) return CountRay(k);
    throw Error("unknown ray '" + std::string(name) + "' (shortest, +x, -x, +y, -y, +z, -z)");
}

PointSide classify_point(const Bvh2& bvh, const Vec3& p, const InsideOptions& opts) { return classify(bvh, p, opts); }

void classify_points(const Bvh2& bvh, std::span<const Vec3> points, std::span<PointSide> out,
                     const InsideOptions& opts) {
    simdbvh::detail::check_size(out.size(), points.size(), "out");
    // Morton order (point_query-inl.h): neighbouring points walk the same
    // nodes while they are in cache. The order changes the speed only.
    const std::vector<std::uint32_t> order = detail::morton_order(points, opts.threads);
    parallel_for(
        points.size(), opts.threads,
        [&](std::size_t b, std::size_t e) {
            for (std::size_t k = b; k < e; ++k) out[order[k]] = classify(bvh, points[order[k]], opts);
        },
        ParallelOptions{.grain = 1024});
}

PointSide brute_force_classify_point(const Mesh& mesh, const Vec3& p, const InsideOptions& opts) {
    Counter cnt;
    if (!usable(p)) return cnt.result(opts);
    const std::size_t nv = mesh.positions.size();
    auto valid = [&](const Triangle& t) { return t[0] < nv && t[1] < nv && t[2] < nv; };
    Aabb bounds;  // the trees' root box: the union of the triangles' boxes
    if (opts.ray == CountRay::shortest)
        for (const Triangle& t : mesh.triangles)
            if (valid(t))
                for (int k = 0; k < 3; ++k) bounds.grow(mesh.positions[t[k]]);
    return detail::visit_frame(detail::ray_frame(opts.ray, bounds, p), [&](auto f) {
        for (const Triangle& t : mesh.triangles)
            if (valid(t)) cnt.add(crossing(f, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]], p));
        return cnt.result(opts, f.ray());
    });
}

}  // namespace simdbvh
