// Exact orientation predicates for float coordinates (see exact_predicates.h).
#include "simdbvh/query/internal/exact_predicates.h"

#include <cmath>
#include <utility>

namespace simdbvh::query::exact {
namespace {

// a + b = x + y exactly (Knuth's TwoSum).
inline void two_sum(double a, double b, double& x, double& y) {
    x = a + b;
    const double bv = x - a, av = x - bv;
    y = (a - av) + (b - bv);
}

// A nonoverlapping expansion, components in increasing magnitude, zeros removed.
struct Expansion {
    static constexpr int kMax = 64;
    double c[kMax];
    int n = 0;

    // Shewchuk's Grow-Expansion with zero elimination: this += b, exactly.
    void add(double b) {
        double q = b;
        int m = 0;
        for (int i = 0; i < n; ++i) {
            double x, y;
            two_sum(q, c[i], x, y);
            q = x;
            if (y != 0.0) c[m++] = y;
        }
        if (q != 0.0) c[m++] = q;
        n = m;
    }
    // a * b * s exactly (a * b is exact for floats a, b; the product with s is a two-term expansion).
    void add_product(double ab, double s) {
        const double x = ab * s;
        const double y = std::fma(ab, s, -x);
        add(y);
        add(x);
    }
    int sign() const { return n == 0 ? 0 : (c[n - 1] > 0.0 ? 1 : -1); }
};

int sign_of(double v) { return (v > 0.0) - (v < 0.0); }

}  // namespace

int orient2d_expansion(double ax, double ay, double bx, double by, double px, double py) {
    // bx py - bx ay - ax py - by px + by ax + ay px (ax ay cancels), each a
    // product of two floats, exact in double.
    Expansion e;
    const double terms[6] = {bx * py, -(bx * ay), -(ax * py), -(by * px), by * ax, ay * px};
    for (double t : terms) e.add(t);
    return e.sign();
}

int orient2d(const Vec3& a, const Vec3& b, const Vec3& p, int i, int j) {
    const int s = orient2d_filtered(a[i], a[j], b[i], b[j], p[i], p[j]);
    return s != kUndecided ? s : orient2d_expansion(a[i], a[j], b[i], b[j], p[i], p[j]);
}

bool on_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
    if (plane_side(a, b, c, p) != 0) return false;
    // On the plane: closed containment in a projection where the triangle has area.
    for (const auto& [i, j] : {std::pair{0, 1}, std::pair{1, 2}, std::pair{2, 0}}) {
        const int s = orient2d(a, b, c, i, j);
        if (s == 0) continue;
        const int e0 = orient2d(a, b, p, i, j), e1 = orient2d(b, c, p, i, j), e2 = orient2d(c, a, p, i, j);
        return e0 != -s && e1 != -s && e2 != -s;
    }
    return false;  // zero area
}

int plane_side(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
    // Filter in double: n . (p - a) from rounded differences.
    const double bax = double(b.x) - a.x, bay = double(b.y) - a.y, baz = double(b.z) - a.z;
    const double cax = double(c.x) - a.x, cay = double(c.y) - a.y, caz = double(c.z) - a.z;
    const double pax = double(p.x) - a.x, pay = double(p.y) - a.y, paz = double(p.z) - a.z;
    const double nx = bay * caz - baz * cay, ny = baz * cax - bax * caz, nz = bax * cay - bay * cax;
    const double d = nx * pax + ny * pay + nz * paz;
    const double perm = (std::fabs(bay * caz) + std::fabs(baz * cay)) * std::fabs(pax) +
                        (std::fabs(baz * cax) + std::fabs(bax * caz)) * std::fabs(pay) +
                        (std::fabs(bax * cay) + std::fabs(bay * cax)) * std::fabs(paz);
    const double bound = 0x1p-48 * perm;
    if (d > bound || -d > bound) return sign_of(d);
    // Exact: n . (p - a) = -det4 | a 1; b 1; c 1; p 1 | = M_a - M_b + M_c - M_p,
    // M_r the 3x3 determinant of the other three rows.
    Expansion e;
    auto det3 = [&e](const Vec3& r, const Vec3& s, const Vec3& t, double sign) {
        // r . (s x t) = rx (sy tz - sz ty) - ry (sx tz - sz tx) + rz (sx ty - sy tx)
        e.add_product(sign * double(r.x) * s.y, t.z);
        e.add_product(-sign * double(r.x) * s.z, t.y);
        e.add_product(-sign * double(r.y) * s.x, t.z);
        e.add_product(sign * double(r.y) * s.z, t.x);
        e.add_product(sign * double(r.z) * s.x, t.y);
        e.add_product(-sign * double(r.z) * s.y, t.x);
    };
    det3(b, c, p, 1.0);   // M_a
    det3(a, c, p, -1.0);  // M_b
    det3(a, b, p, 1.0);   // M_c
    det3(a, b, c, -1.0);  // M_p
    return e.sign();
}

}  // namespace simdbvh::query::exact
