#pragma once
// Internal: the crossing of the +z ray from a point with one triangle, exactly
// (exact_predicates.h, docs/exact_crossings.md; the other axis rays through
// the quarter-turn frames below), and the count of crossings
// into a PointSide: shared by the BVH2's inside test (inside.cpp) and the
// wide trees' (query/src/inside_wide.cpp), so both count with the same predicates.
#include <cmath>

#include "simdbvh/query/internal/exact_predicates.h"
#include "simdbvh/query/internal/point_query-inl.h"  // detail::usable
#include "simdbvh/query/inside.h"
#include "simdbvh/kernels/aabb.h"

namespace simdbvh::detail {

// crossing()'s answer when p lies on the triangle.
inline constexpr int kOnSurface = 2;

// p below (above) the minimum (maximum) of three finite floats, with
// comparisons only (std::fmin and std::fmax are library calls here).
inline bool below3(float p, float a, float b, float c) { return p < a && p < b && p < c; }
inline bool above3(float p, float a, float b, float c) { return p > a && p > b && p > c; }

inline bool in_box(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
    for (int k = 0; k < 3; ++k)
        if (below3(p[k], a[k], b[k], c[k]) || above3(p[k], a[k], b[k], c[k])) return false;
    return true;
}

// What crossing() decides first, cheaply: the perturbed line through
// (px, py) meets the triangle only if (px, py) is in the closure of its
// projection, so in its closed xy box; a triangle wholly below p (p.z above
// its top) is neither crossed by the +z ray nor touched by p. The wide trees
// make the same decision 4 lanes at a time (query/src/inside_wide.cpp).
inline bool column_misses(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
    return below3(p.x, a.x, b.x, c.x) || above3(p.x, a.x, b.x, c.x) || below3(p.y, a.y, b.y, c.y) ||
           above3(p.y, a.y, b.y, c.y) || above3(p.z, a.z, b.z, c.z);
}

// crossing() for a triangle that column_misses() did not reject.
inline int crossing_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
    // On the triangle (faces parallel to z and silhouette edges included): the
    // rarely taken exact test, for the triangles whose box holds p.
    if (in_box(a, b, c, p) && query::exact::on_triangle(a, b, c, p)) return kOnSurface;
    const int facing = query::exact::orient2d(a, b, c);  // sign of the normal's z
    if (facing == 0) return 0;                           // parallel to the ray: never contains the perturbed line
    if (query::exact::orient2d_perturbed(a, b, p) != facing || query::exact::orient2d_perturbed(b, c, p) != facing ||
        query::exact::orient2d_perturbed(c, a, p) != facing)
        return 0;
    // The plane at (px, py) is above p when n . (p - a) and n_z have opposite signs.
    const int side = query::exact::plane_side(a, b, c, p);
    if (side == 0) return kOnSurface;  // (found above already)
    return side != facing ? facing : 0;
}

// The crossing of the +z ray from p with triangle (a, b, c): 0 none, +1 or -1
// (the sign of the triangle's normal z), or `kOnSurface` when p lies on it.
inline int crossing(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
    return column_misses(a, b, c, p) ? 0 : crossing_exact(a, b, c, p);
}

struct CrossingCounter {
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
    PointSide result(const InsideOptions& o, CountRay ray = CountRay::plus_z) {
        r.ray = ray;
        if (surface) r.side = Side::surface;
        else if (o.rule == InsideOptions::Rule::winding) r.side = r.winding != 0 ? Side::inside : Side::outside;
        else r.side = (r.crossings & 1u) ? Side::inside : Side::outside;
        return r;
    }
};

// A point's ray along an axis direction, and the rotation by quarter turns
// that takes it to +z: axis w (0 x, 1 y, 2 z) up or down, u and v the other
// two axes in cyclic order. map(q) = (q_u, q_v, q_w) up, (q_v, q_u, -q_w)
// down: a permutation and a negation of float coordinates, exact, with
// determinant +1, so the crossing test above runs unchanged on the mapped
// coordinates (same predicates, same facing signs along the ray).
struct RayFrame {
    int u = 0, v = 1, w = 2;
    bool up = true;
    static RayFrame of(CountRay r) {
        RayFrame f;
        f.w = int(r) / 2;
        f.up = int(r) % 2 == 0;
        f.u = (f.w + 1) % 3;
        f.v = (f.w + 2) % 3;
        return f;
    }
    CountRay ray() const { return CountRay(2 * w + (up ? 0 : 1)); }
    Vec3 map(const Vec3& q) const { return up ? Vec3{q[u], q[v], q[w]} : Vec3{q[v], q[u], -q[w]}; }
    // Whether the ray's column reaches closed box b: in the mapped
    // coordinates, (pu, pv) in its projection and its top at or above pw (the
    // perturbed line through (pu, pv) meets a triangle only if (pu, pv) is in
    // the closure of its projection, so in its box). Without mapping the box.
    bool reaches(const Aabb& b, const Vec3& p) const {
        return b.lo[u] <= p[u] && p[u] <= b.hi[u] && b.lo[v] <= p[v] && p[v] <= b.hi[v] &&
               (up ? p[w] <= b.hi[w] : b.lo[w] <= p[w]);
    }
};

// The ray InsideOptions::ray names for p; for `shortest`, the direction toward
// the nearest face of `bounds` (the union of the mesh's triangle boxes: every
// path passes the same box, so every path picks the same ray). Distances in
// double, so they never overflow.
inline RayFrame ray_frame(CountRay r, const Aabb& bounds, const Vec3& p) {
    if (r != CountRay::shortest) return RayFrame::of(r);
    CountRay best = CountRay::plus_z;
    double d = double(bounds.hi.z) - p.z;
    auto offer = [&](CountRay c, double e) {
        if (e < d) d = e, best = c;
    };
    offer(CountRay::minus_z, double(p.z) - bounds.lo.z);
    offer(CountRay::plus_x, double(bounds.hi.x) - p.x);
    offer(CountRay::minus_x, double(p.x) - bounds.lo.x);
    offer(CountRay::plus_y, double(bounds.hi.y) - p.y);
    offer(CountRay::minus_y, double(p.y) - bounds.lo.y);
    return RayFrame::of(best);
}

// A RayFrame with its axes fixed at compile time: the BVH2's and brute
// force's loops are instantiated per direction (visit_frame), so map() and
// reaches() cost what the +z code did.
template <int W, bool Up>
struct AxisFrame {
    static constexpr int u = (W + 1) % 3, v = (W + 2) % 3, w = W;
    static constexpr bool up = Up;
    static CountRay ray() { return CountRay(2 * W + (Up ? 0 : 1)); }
    static Vec3 map(const Vec3& q) { return Up ? Vec3{q[u], q[v], q[w]} : Vec3{q[v], q[u], -q[w]}; }
    static bool reaches(const Aabb& b, const Vec3& p) {
        return b.lo[u] <= p[u] && p[u] <= b.hi[u] && b.lo[v] <= p[v] && p[v] <= b.hi[v] &&
               (Up ? p[w] <= b.hi[w] : b.lo[w] <= p[w]);
    }
};

// fn(AxisFrame<...>{}) for frame f's direction.
template <class Fn>
decltype(auto) visit_frame(const RayFrame& f, Fn&& fn) {
    switch (f.ray()) {
    case CountRay::plus_x: return fn(AxisFrame<0, true>{});
    case CountRay::minus_x: return fn(AxisFrame<0, false>{});
    case CountRay::plus_y: return fn(AxisFrame<1, true>{});
    case CountRay::minus_y: return fn(AxisFrame<1, false>{});
    case CountRay::minus_z: return fn(AxisFrame<2, false>{});
    default: return fn(AxisFrame<2, true>{});
    }
}

// crossing() of p's ray in frame f (a RayFrame or an AxisFrame).
template <class Frame>
inline int crossing(const Frame& f, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
    return crossing(f.map(a), f.map(b), f.map(c), f.map(p));
}
template <class Frame>
inline int crossing_exact(const Frame& f, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
    return crossing_exact(f.map(a), f.map(b), f.map(c), f.map(p));
}

}  // namespace simdbvh::detail
