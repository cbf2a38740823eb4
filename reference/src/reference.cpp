// Double-precision brute-force reference: see simdbvh/reference/reference.h.
#include "simdbvh/reference/reference.h"

#include <algorithm>
#include <cmath>

namespace simdbvh::reference {
namespace {

struct D3 {
    double x, y, z;
    double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};
D3 to_d(const Vec3& a) { return {a.x, a.y, a.z}; }
D3 sub(const D3& a, const D3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double inf_norm(const Vec3& a) {
    return std::max({std::fabs(double(a.x)), std::fabs(double(a.y)), std::fabs(double(a.z))});
}

// Ray setup in double: the permutation of prepare() (a choice made on the float
// inputs, so it is the same), shear constants in double.
struct RayD {
    D3 org, dir;
    double tmin, tmax;
    int kx, ky, kz;
    double sx, sy, sz;
    bool valid;
};

RayD setup(const Ray& r) {
    const PreparedRay p = prepare(r);
    RayD d{};
    d.valid = p.valid;
    if (!p.valid) return d;
    d.org = to_d(r.org);
    d.dir = to_d(r.dir);
    d.tmin = r.tmin;
    d.tmax = r.tmax;
    d.kx = p.kx;
    d.ky = p.ky;
    d.kz = p.kz;
    d.sx = d.dir[d.kx] / d.dir[d.kz];
    d.sy = d.dir[d.ky] / d.dir[d.kz];
    d.sz = 1.0 / d.dir[d.kz];
    return d;
}

TriangleRef test(const RayD& r, const Ray& ray, const Vec3& v0, const Vec3& v1, const Vec3& v2) {
    TriangleRef out;
    const D3 a = sub(to_d(v0), r.org), b = sub(to_d(v1), r.org), c = sub(to_d(v2), r.org);
    const double ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
    const double bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
    const double cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
    const double eu = cx * by - cy * bx;
    const double ev = ax * cy - ay * cx;
    const double ew = bx * ay - by * ax;
    // Float error bound of the edge functions (see TriangleRef).
    auto mag = [&](const D3& p) {
        return std::max(std::fabs(p[r.kx]) + std::fabs(r.sx) * std::fabs(p[r.kz]),
                        std::fabs(p[r.ky]) + std::fabs(r.sy) * std::fabs(p[r.kz]));
    };
    const double m = std::max({mag(a), mag(b), mag(c)});
    const double delta = 32.0 * kFloatEps * m * m;
    const bool near_inside =
        (eu >= -delta && ev >= -delta && ew >= -delta) || (eu <= delta && ev <= delta && ew <= delta);
    if (!near_inside) return out;  // implies no strict hit either
    const double det = eu + ev + ew;
    if (det == 0.0) return out;  // edge-on (or degenerate): no t, every method misses

    const double az = r.sz * a[r.kz], bz = r.sz * b[r.kz], cz = r.sz * c[r.kz];
    const double t = (eu * az + ev * bz + ew * cz) / det;
    if (!std::isfinite(t)) return out;
    // dt/dE_i = (z_i - t) / det: an error delta in each E moves t by at most this.
    const double slack =
        tolerance(ray, t) + delta * (std::fabs(az - t) + std::fabs(bz - t) + std::fabs(cz - t)) / std::fabs(det);

    const bool neg = eu < 0.0 || ev < 0.0 || ew < 0.0;
    const bool pos = eu > 0.0 || ev > 0.0 || ew > 0.0;
    const bool in_interval = t >= r.tmin && t <= r.tmax;
    out.hit = !(neg && pos) && in_interval;
    out.near = out.hit || (near_inside && t >= r.tmin - slack && t <= r.tmax + slack);
    const bool robust_inside = (eu > delta && ev > delta && ew > delta) || (eu < -delta && ev < -delta && ew < -delta);
    out.robust = out.hit && robust_inside && t >= r.tmin + slack && t <= r.tmax - slack;
    if (out.near) {
        out.t = t;
        out.u = ev / det;
        out.v = ew / det;
        out.slack = slack;
    }
    return out;
}

}  // namespace

// Why 16: the float watertight t is the barycentric mean of the sheared z's,
// sz * (v_kz - o_kz). Each is off by a few roundings relative to the size of the
// coordinates involved, and near the hit |v| <= |o|inf + |t| |d|inf, so the
// absolute error of t is c * eps * (|o|inf + |t| |d|inf) / |d_kz| with c about
// 8-10 (v - o, the shear, sz, three products, two sums, det, the division).
// |d_kz| = |d|inf >= |d| / sqrt(3), hence 16 ~ 9 * sqrt(3) when dividing by |d|.
// Embree's formula has a similar number of roundings.
double tolerance(const Ray& ray, double t_ref) {
    const double dlen =
        std::sqrt(double(ray.dir.x) * ray.dir.x + double(ray.dir.y) * ray.dir.y + double(ray.dir.z) * ray.dir.z);
    if (!(dlen > 0.0) || !std::isfinite(t_ref)) return 0.0;
    return 16.0 * kFloatEps * (inf_norm(ray.org) + std::fabs(t_ref) * inf_norm(ray.dir)) / dlen;
}

TriangleRef intersect_double(const Ray& ray, const Vec3& v0, const Vec3& v1, const Vec3& v2) {
    const RayD r = setup(ray);
    if (!r.valid) return TriangleRef{};
    return test(r, ray, v0, v1, v2);
}

bool Reference::robust_hit() const {
    return std::any_of(candidates.begin(), candidates.end(), [](const RefHit& h) { return h.robust; });
}

std::vector<std::uint32_t> Reference::tie_set() const {
    std::vector<std::uint32_t> ids;
    if (!hit()) return ids;
    for (const RefHit& h : candidates)
        if (std::fabs(h.t - t) <= tau) ids.push_back(h.prim);
    std::sort(ids.begin(), ids.end());
    return ids;
}

bool Reference::in_tie_set(std::uint32_t id) const {
    const RefHit* h = find(id);
    return hit() && h && std::fabs(h->t - t) <= tau;
}

const RefHit* Reference::find(std::uint32_t id) const {
    for (const RefHit& h : candidates)
        if (h.prim == id) return &h;
    return nullptr;
}

Reference reference_intersect(const Mesh& mesh, const Ray& ray) {
    Reference ref;
    const RayD r = setup(ray);
    ref.valid = r.valid;
    if (!r.valid) return ref;
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const TriangleRef h = test(r, ray, mesh.vertex(i, 0), mesh.vertex(i, 1), mesh.vertex(i, 2));
        if (!h.near) continue;
        const auto id = static_cast<std::uint32_t>(i);
        ref.candidates.push_back(RefHit{id, h.t, h.u, h.v, h.slack, h.hit, h.robust});
        if (h.hit && (h.t < ref.t || (h.t == ref.t && id < ref.prim))) {
            ref.t = h.t;
            ref.prim = id;
        }
    }
    std::sort(ref.candidates.begin(), ref.candidates.end(),
              [](const RefHit& x, const RefHit& y) { return x.t < y.t || (x.t == y.t && x.prim < y.prim); });
    if (ref.hit()) ref.tau = tolerance(ray, ref.t);
    return ref;
}

bool reference_occluded(const Mesh& mesh, const Ray& ray) {
    const RayD r = setup(ray);
    if (!r.valid) return false;
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
        if (test(r, ray, mesh.vertex(i, 0), mesh.vertex(i, 1), mesh.vertex(i, 2)).hit) return true;
    return false;
}

Hit to_hit(const Reference& ref) {
    if (!ref.hit()) return Hit{};
    const RefHit* h = ref.find(ref.prim);
    return Hit{static_cast<float>(ref.t), static_cast<float>(h->u), static_cast<float>(h->v), ref.prim};
}

}  // namespace simdbvh::reference
