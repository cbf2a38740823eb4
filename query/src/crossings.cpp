// All hits and crossing counts along rays (see simdbvh/query/crossings.h).
#include "simdbvh/query/crossings.h"
#include "simdbvh/kernels/error.h"

#include <algorithm>

#include "simdbvh/kernels/box.h"
#include "simdbvh/platform/parallel.h"
#include "simdbvh/kernels/triangle.h"

namespace simdbvh {
namespace {

// The edge P -> Q of a triangle whose sheared area has sign `det_sign`, when the
// ray passes exactly through its line: the edge direction with the triangle on
// its left is e = (Q - P) * det_sign; the triangle owns the crossing when e
// points up, or right when horizontal. The neighbour across the edge sees -e,
// so exactly one of the two owns it (both or neither for a fold, whose
// crossings then cancel in the winding number).
bool owns_edge(float px, float py, float qx, float qy, int det_sign) {
    const int dy = (qy > py) - (qy < py), dx = (qx > px) - (qx < px);  // exact signs of float differences
    const int ey = dy * det_sign, ex = dx * det_sign;
    return ey > 0 || (ey == 0 && ex > 0);
}

int sign_of(double v) { return (v > 0.0) - (v < 0.0); }

// The watertight test with the tie rule. On a crossing in [tmin, tmax] fills c
// (t in the prepared ray's parameter).
bool cross(const PreparedRay& r, const Vec3& v0, const Vec3& v1, const Vec3& v2, Crossing* c) {
    const detail::ShearedTriangle sh = detail::shear(r, v0, v1, v2);
    float eu, ev, ew;
    detail::edge_functions(sh, &eu, &ev, &ew);
    int su = sign_of(eu), sv = sign_of(ev), sw = sign_of(ew);
    if (su == 0 || sv == 0 || sw == 0) {  // exact signs in double (products of floats are exact)
        double du, dv, dw;
        detail::edge_functions_exact(sh, &du, &dv, &dw);
        su = sign_of(du);
        sv = sign_of(dv);
        sw = sign_of(dw);
        eu = float(du);
        ev = float(dv);
        ew = float(dw);
    }
    if ((su < 0 || sv < 0 || sw < 0) && (su > 0 || sv > 0 || sw > 0)) return false;
    const int s = su != 0 ? su : (sv != 0 ? sv : sw);  // the area's sign: the nonzero ones agree
    if (s == 0) return false;                          // the ray lies in the triangle's plane
    // Exactly on an edge line (or two: a vertex): the edge must own the crossing.
    if (su == 0 && !owns_edge(sh.bx, sh.by, sh.cx, sh.cy, s)) return false;  // edge v1 -> v2
    if (sv == 0 && !owns_edge(sh.cx, sh.cy, sh.ax, sh.ay, s)) return false;  // edge v2 -> v0
    if (sw == 0 && !owns_edge(sh.ax, sh.ay, sh.bx, sh.by, s)) return false;  // edge v0 -> v1
    const float det = eu + ev + ew;
    if (det == 0.0f) return false;
    const float t = detail::sheared_t(r, sh, eu, ev, ew, det);
    if (!(t >= r.tmin && t <= r.tmax)) return false;
    c->t = t;
    c->u = ev / det;
    c->v = ew / det;
    c->facing = s > 0 ? -1 : 1;  // (positive sheared area: the normal points against the ray)
    return true;
}

template <class F>
void for_each_crossing(const Bvh2& bvh, const PreparedRay& r, F&& f) {
    const auto& nodes = bvh.nodes();
    if (!r.valid || nodes.empty()) return;
    const TriangleVerts* tris = bvh.triangles().data();
    const std::uint32_t* ids = bvh.prim_ids().data();
    std::uint32_t stack[kMaxDepth + 1];
    int sp = 0;
    float entry;
    if (!intersect_box(r, nodes[0].box, r.tmax, &entry)) return;
    std::uint32_t idx = 0;
    for (;;) {
        const Node2& n = nodes[idx];
        if (!n.is_leaf()) {
            const bool ha = intersect_box(r, nodes[n.first].box, r.tmax, &entry);
            const bool hb = intersect_box(r, nodes[n.first + 1].box, r.tmax, &entry);
            if (ha && hb) stack[sp++] = n.first + 1;
            if (ha || hb) {
                idx = ha ? n.first : n.first + 1;
                continue;
            }
        } else {
            for (std::uint32_t i = n.first, e = n.first + n.count; i < e; ++i) {
                Crossing c;
                if (cross(r, tris[i].v0, tris[i].v1, tris[i].v2, &c)) {
                    c.prim = ids[i];
                    f(c);
                }
            }
        }
        if (sp == 0) return;
        idx = stack[--sp];
    }
}

template <class F>
void brute_for_each_crossing(const Mesh& mesh, const PreparedRay& r, F&& f) {
    if (!r.valid) return;
    const std::size_t nv = mesh.positions.size();
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const Triangle& t = mesh.triangles[i];
        if (t[0] >= nv || t[1] >= nv || t[2] >= nv) continue;
        Crossing c;
        if (cross(r, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]], &c)) {
            c.prim = std::uint32_t(i);
            f(c);
        }
    }
}

AllHits finish_all(std::vector<Crossing> hits, const PreparedRay& r, std::size_t cap) {
    auto before = [](const Crossing& a, const Crossing& b) { return a.t < b.t || (a.t == b.t && a.prim < b.prim); };
    std::sort(hits.begin(), hits.end(), before);
    AllHits out;
    if (hits.size() > cap) {
        out.dropped = hits.size() - cap;
        hits.resize(cap);
    }
    for (Crossing& c : hits) c.t = to_caller_t(r, c.t);
    out.hits = std::move(hits);
    return out;
}

// The two queries over any crossing enumerator (BVH2 or brute force).
template <class Source, class Enumerate>
AllHits all_hits(const Source& src, const Ray& ray, std::size_t cap, Enumerate each) {
    const PreparedRay r = prepare(ray);
    std::vector<Crossing> hits;
    each(src, r, [&](const Crossing& c) { hits.push_back(c); });
    return finish_all(std::move(hits), r, cap);
}

template <class Source, class Enumerate>
CrossingCount counts(const Source& src, const Ray& ray, Enumerate each) {
    CrossingCount n;
    each(src, prepare(ray), [&](const Crossing& c) {
        n.winding += c.facing;
        n.crossings++;
    });
    return n;
}

constexpr auto kTree = [](const Bvh2& b, const PreparedRay& r, auto&& f) { for_each_crossing(b, r, f); };
constexpr auto kBrute = [](const Mesh& m, const PreparedRay& r, auto&& f) { brute_for_each_crossing(m, r, f); };

}  // namespace

AllHits intersect_all(const Bvh2& bvh, const Ray& ray, std::size_t cap) { return all_hits(bvh, ray, cap, kTree); }
CrossingCount count_crossings(const Bvh2& bvh, const Ray& ray) { return counts(bvh, ray, kTree); }

void count_crossings(const Bvh2& bvh, std::span<const Ray> rays, std::span<CrossingCount> out, int threads) {
    simdbvh::detail::check_size(out.size(), rays.size(), "out");
    parallel_for(rays.size(), threads, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) out[i] = count_crossings(bvh, rays[i]);
    });
}

AllHits brute_force_intersect_all(const Mesh& mesh, const Ray& ray, std::size_t cap) {
    return all_hits(mesh, ray, cap, kBrute);
}
CrossingCount brute_force_count_crossings(const Mesh& mesh, const Ray& ray) { return counts(mesh, ray, kBrute); }

}  // namespace simdbvh
