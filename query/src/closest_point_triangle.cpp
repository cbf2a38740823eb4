// The closest point of a triangle to a point, in double (Ericson, Real-Time
// Collision Detection, 5.1.5: Voronoi regions of the vertices, edges and face).
#include <algorithm>
#include <cmath>

#include "simdbvh/query/closest_point.h"

namespace simdbvh {
namespace {

struct D3 {
    double x, y, z;
};
D3 to_d(const Vec3& a) { return {a.x, a.y, a.z}; }
D3 operator-(const D3& a, const D3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator+(const D3& a, const D3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator*(const D3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(const D3& a, const D3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

TrianglePoint make(const D3& p, const D3& q, double u, double v) {
    const D3 d = q - p;
    return TrianglePoint{q.x, q.y, q.z, u, v, dot(d, d)};
}

// The closest point of segment a + s (b - a), s in [0, 1].
double segment_param(const D3& p, const D3& a, const D3& b) {
    const D3 ab = b - a;
    const double len2 = dot(ab, ab);
    if (!(len2 > 0.0)) return 0.0;
    return std::clamp(dot(p - a, ab) / len2, 0.0, 1.0);
}

// The nearest of the three edges (a point is its own edge), in the order
// (v0 v1), (v0 v2), (v1 v2), the first of equals kept.
TrianglePoint nearest_edge(const D3& p, const D3& a, const D3& b, const D3& c) {
    const double s0 = segment_param(p, a, b), s1 = segment_param(p, a, c), s2 = segment_param(p, b, c);
    TrianglePoint best = make(p, a + (b - a) * s0, s0, 0.0);
    const TrianglePoint e1 = make(p, a + (c - a) * s1, 0.0, s1);
    if (e1.distance2 < best.distance2) best = e1;
    const TrianglePoint e2 = make(p, b + (c - b) * s2, 1.0 - s2, s2);
    if (e2.distance2 < best.distance2) best = e2;
    return best;
}

}  // namespace

TrianglePoint closest_point_on_triangle(const Vec3& pf, const Vec3& v0, const Vec3& v1, const Vec3& v2) {
    const D3 p = to_d(pf), a = to_d(v0), b = to_d(v1), c = to_d(v2);
    const D3 ab = b - a, ac = c - a;
    const D3 n = cross(ab, ac);
    if (!(dot(n, n) > 0.0)) return nearest_edge(p, a, b, c);  // zero area
    const D3 ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return make(p, a, 0.0, 0.0);  // vertex v0
    const D3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return make(p, b, 1.0, 0.0);  // vertex v1
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {                  // edge v0 v1
        if (!(d1 - d3 > 0.0)) return nearest_edge(p, a, b, c);  // rounding (a far point): no 0/0
        const double s = d1 / (d1 - d3);
        return make(p, a + ab * s, s, 0.0);
    }
    const D3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return make(p, c, 0.0, 1.0);  // vertex v2
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {  // edge v0 v2
        if (!(d2 - d6 > 0.0)) return nearest_edge(p, a, b, c);
        const double s = d2 / (d2 - d6);
        return make(p, a + ac * s, 0.0, s);
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {  // edge v1 v2
        if (!((d4 - d3) + (d5 - d6) > 0.0)) return nearest_edge(p, a, b, c);
        const double s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return make(p, b + (c - b) * s, 1.0 - s, s);
    }
    const double sum = va + vb + vc;
    if (!(sum > 0.0)) return nearest_edge(p, a, b, c);  // rounding at a sliver
    const double v = vb / sum, w = vc / sum;            // face
    return make(p, a + ab * v + ac * w, v, w);
}

}  // namespace simdbvh
