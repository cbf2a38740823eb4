// Exact inside/outside by crossing counting along +z (see simdbvh/bvh2/inside.h
// and docs/exact_crossings.md).
#include "simdbvh/bvh2/inside.h"

#include <cmath>

#include "exact_predicates.h"
#include "point_query-inl.h"
#include "simdbvh/kernels/parallel.h"

namespace simdbvh {
namespace {

// The crossing of the +z ray from p with triangle (a, b, c): 0 none, +1 or -1
// (the sign of the triangle's normal z), or `kOnSurface` when p lies on it.
constexpr int kOnSurface = 2;

bool in_box(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
    for (int k = 0; k < 3; ++k)
        if (p[k] < std::fmin(a[k], std::fmin(b[k], c[k])) || p[k] > std::fmax(a[k], std::fmax(b[k], c[k]))) return false;
    return true;
}

int crossing(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
    // Cheap reject first (most triangles of a reached leaf): the perturbed line
    // through (px, py) meets the triangle only if (px, py) is in the closure of
    // its projection, so in its closed xy box; a triangle wholly below p
    // (p.z above its top) is neither crossed by the +z ray nor touched by p.
    if (p.x < std::fmin(a.x, std::fmin(b.x, c.x)) || p.x > std::fmax(a.x, std::fmax(b.x, c.x)) ||
        p.y < std::fmin(a.y, std::fmin(b.y, c.y)) || p.y > std::fmax(a.y, std::fmax(b.y, c.y)) ||
        p.z > std::fmax(a.z, std::fmax(b.z, c.z)))
        return 0;
    // On the triangle (faces parallel to z and silhouette edges included): the
    // rarely taken exact test, for the triangles whose box holds p.
    if (in_box(a, b, c, p) && exact::on_triangle(a, b, c, p)) return kOnSurface;
    const int facing = exact::orient2d(a, b, c);  // sign of the normal's z
    if (facing == 0) return 0;                    // parallel to the ray: never contains the perturbed line
    if (exact::orient2d_perturbed(a, b, p) != facing || exact::orient2d_perturbed(b, c, p) != facing ||
        exact::orient2d_perturbed(c, a, p) != facing)
        return 0;
    // The plane at (px, py) is above p when n . (p - a) and n_z have opposite signs.
    const int side = exact::plane_side(a, b, c, p);
    if (side == 0) return kOnSurface;  // (found above already)
    return side != facing ? facing : 0;
}

struct Counter {
    PointSide r;
    bool surface = false;
    void add(int c) {
        if (c == kOnSurface) {
            surface = true;
        } else if (c != 0) {
            r.winding += c;
            r.crossings++;
        }
    }
    PointSide result(const InsideOptions& o) {
        if (surface) r.side = Side::surface;
        else if (o.rule == InsideOptions::Rule::winding) r.side = r.winding != 0 ? Side::inside : Side::outside;
        else r.side = (r.crossings & 1u) ? Side::inside : Side::outside;
        return r;
    }
};

bool usable(const Vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

// Closed boxes: the perturbed line through (px, py) meets a triangle only if
// (px, py) is in the closure of its projection, so in its box.
bool box_reaches(const Aabb& b, const Vec3& p) {
    return b.lo.x <= p.x && p.x <= b.hi.x && b.lo.y <= p.y && p.y <= b.hi.y && p.z <= b.hi.z;
}

PointSide classify(const Bvh2& bvh, const Vec3& p, const InsideOptions& o) {
    Counter cnt;
    const auto& nodes = bvh.nodes();
    if (!usable(p) || nodes.empty() || !box_reaches(nodes[0].box, p)) return cnt.result(o);
    const TriangleVerts* tris = bvh.triangles().data();
    std::uint32_t stack[kMaxDepth + 1];
    int sp = 0;
    std::uint32_t idx = 0;
    for (;;) {
        const Node2& n = nodes[idx];
        if (!n.is_leaf()) {
            const bool ha = box_reaches(nodes[n.first].box, p), hb = box_reaches(nodes[n.first + 1].box, p);
            if (ha && hb) stack[sp++] = n.first + 1;
            if (ha || hb) {
                idx = ha ? n.first : n.first + 1;
                continue;
            }
        } else {
            for (std::uint32_t i = n.first, e = n.first + n.count; i < e; ++i)
                cnt.add(crossing(tris[i].v0, tris[i].v1, tris[i].v2, p));
        }
        if (sp == 0) return cnt.result(o);
        idx = stack[--sp];
    }
}

}  // namespace

PointSide classify_point(const Bvh2& bvh, const Vec3& p, const InsideOptions& opts) { return classify(bvh, p, opts); }

void classify_points(const Bvh2& bvh, std::span<const Vec3> points, std::span<PointSide> out,
                     const InsideOptions& opts) {
    if (out.size() < points.size()) throw Error("output span is smaller than points span");
    // Morton order (point_query-inl.h): neighbouring points walk the same
    // nodes while they are in cache. The order changes the speed only.
    const std::vector<std::uint32_t> order = detail::morton_order(points);
    parallel_for(points.size(), opts.threads, [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) out[order[k]] = classify(bvh, points[order[k]], opts);
    }, ParallelOptions{.grain = 1024});
}

PointSide brute_force_classify_point(const Mesh& mesh, const Vec3& p, const InsideOptions& opts) {
    Counter cnt;
    if (!usable(p)) return cnt.result(opts);
    const std::size_t nv = mesh.positions.size();
    for (const Triangle& t : mesh.triangles) {
        if (t[0] >= nv || t[1] >= nv || t[2] >= nv) continue;
        cnt.add(crossing(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]], p));
    }
    return cnt.result(opts);
}

}  // namespace simdbvh
