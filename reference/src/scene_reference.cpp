// The double-precision scene reference and its classification (scene_reference.h).
#include "simdbvh/reference/scene_reference.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "simdbvh/reference/reference.h"
#include "simdbvh/kernels/error.h"

namespace simdbvh::reference {

namespace {

constexpr double kNearSlack = 0x1p-16;       // relative, for skipping instances the ray cannot come near
constexpr double kNearDelta = 16 * 0x1p-24;  // absolute near distance per unit of |o| + |t d|, times cond
constexpr double kInf = std::numeric_limits<double>::infinity();

using RayD = SceneReferencer::RayD;

RayD world_ray(const Ray& r) { return {{r.org.x, r.org.y, r.org.z}, {r.dir.x, r.dir.y, r.dir.z}, r.tmin, r.tmax}; }

RayD object_ray(const SceneReferencer::InstanceD& in, const RayD& w) {
    RayD r{{0, 0, 0}, {0, 0, 0}, w.tmin, w.tmax};
    for (int i = 0; i < 3; ++i) {
        r.o[i] = in.inv[i][3];
        for (int k = 0; k < 3; ++k) {
            r.o[i] += in.inv[i][k] * w.o[k];
            r.d[i] += in.inv[i][k] * w.d[k];
        }
    }
    return r;
}

double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Moller-Trumbore in double on float vertices. Near and robust: the hit point within `delta` (object space) of
// the triangle, or that far inside it: each barycentric against delta over the height to its edge.
ObjectRef triangle(const RayD& r, const Vec3& a, const Vec3& b, const Vec3& c, double delta, double tau) {
    ObjectRef out;
    const double e1[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
    const double e2[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
    const double p[3] = {r.d[1] * e2[2] - r.d[2] * e2[1], r.d[2] * e2[0] - r.d[0] * e2[2],
                         r.d[0] * e2[1] - r.d[1] * e2[0]};
    const double det = dot3(e1, p);
    if (det == 0.0 || !std::isfinite(det)) return out;
    const double tv[3] = {r.o[0] - a.x, r.o[1] - a.y, r.o[2] - a.z};
    const double u = dot3(tv, p) / det;
    const double q[3] = {tv[1] * e1[2] - tv[2] * e1[1], tv[2] * e1[0] - tv[0] * e1[2], tv[0] * e1[1] - tv[1] * e1[0]};
    const double v = dot3(r.d, q) / det;
    const double t = dot3(e2, q) / det;
    const double w = 1.0 - u - v;
    out.t = t;
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double cosine = std::fabs(det) / std::sqrt(dot3(n, n) * dot3(r.d, r.d));  // |det| = |d||n||cos|
    out.t_sensitivity = 1.0 / std::max(cosine, 1e-9);
    const double area2 = std::sqrt(dot3(n, n));  // twice the area; height to edge i = area2 / |edge i|
    auto len = [](const double* e) { return std::sqrt(dot3(e, e)); };
    const double e3[3] = {e2[0] - e1[0], e2[1] - e1[1], e2[2] - e1[2]};  // v1 -> v2, opposite v0 (w)
    const double su = delta * len(e2) / area2, sv = delta * len(e1) / area2, sw = delta * len(e3) / area2;
    const bool in_t = t >= r.tmin && t <= r.tmax;
    out.strict = u >= 0 && v >= 0 && w >= 0 && in_t;
    out.near = u >= -su && v >= -sv && w >= -sw && t >= r.tmin - tau && t <= r.tmax + tau;
    out.robust = out.strict && u > su && v > sv && w > sw && t >= r.tmin + tau && t <= r.tmax - tau;
    return out;
}

// The stable quadratic in long double: the nearer root in the interval, else the farther. Near: the closest
// approach within r + delta; robust: within r - delta.
ObjectRef sphere(const RayD& r, const Sphere& sp, double delta, double tau) {
    ObjectRef out;
    using L = long double;
    const L f[3] = {L(r.o[0]) - sp.center.x, L(r.o[1]) - sp.center.y, L(r.o[2]) - sp.center.z};
    const L d[3] = {r.d[0], r.d[1], r.d[2]};
    const L a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (!(a > 0)) return out;
    const L b = f[0] * d[0] + f[1] * d[1] + f[2] * d[2];
    const L rr = L(sp.radius) * sp.radius;
    L g2 = 0;  // |f - (b/a) d|^2: the closest approach, without cancellation
    for (int k = 0; k < 3; ++k) {
        const L g = f[k] - (b / a) * d[k];
        g2 += g * g;
    }
    const L disc = rr - g2;
    const L dl = delta;
    const bool near_disc = disc >= -(2 * L(sp.radius) * dl + dl * dl);
    if (!near_disc) return out;
    const L root = std::sqrt(std::max<L>(disc, 0) * a);
    const L qv = -(b + (b >= 0 ? root : -root));
    const L c = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - rr;
    L t0 = qv / a, t1 = qv != 0 ? c / qv : t0;
    if (t0 > t1) std::swap(t0, t1);
    // Strict: the first root in [tmin, tmax] (independent of tau and delta); near: with the interval widened by tau.
    const double lo = r.tmin, hi = r.tmax, a0 = double(t0), a1 = double(t1);
    const double ts = a0 >= lo ? a0 : a1, tn = a0 >= lo - tau ? a0 : a1;
    out.strict = disc >= 0 && ts >= lo && ts <= hi;
    out.t = out.strict ? ts : tn;
    out.near = out.strict || (tn >= lo - tau && tn <= hi + tau);
    out.robust = out.strict && disc > 2 * L(sp.radius) * dl && ts >= lo + tau && ts <= hi - tau;
    return out;
}

// The slab interval [tn, tf] of the box grown by grow[k] on axis k (negative: shrunk); false when empty. A zero
// direction component keeps the slab when the origin lies in it.
bool slab_interval(const RayD& r, const Aabb& bx, const double grow[3], double* tn, double* tf) {
    *tn = -kInf;
    *tf = kInf;
    for (int k = 0; k < 3; ++k) {
        const double lo = double(bx.lo[k]) - grow[k], hi = double(bx.hi[k]) + grow[k];
        if (r.d[k] == 0.0) {
            if (r.o[k] < lo || r.o[k] > hi) return false;
            continue;
        }
        double a = (lo - r.o[k]) / r.d[k], b = (hi - r.o[k]) / r.d[k];
        if (a > b) std::swap(a, b);
        *tn = std::max(*tn, a);
        *tf = std::min(*tf, b);
    }
    return *tn <= *tf;
}

// Slabs in double; near: the box grown by delta, robust: a hit of the box shrunk by delta.
ObjectRef box(const RayD& r, const Aabb& bx, double delta, double tau) {
    ObjectRef out;
    auto slabs = [&](double grow, double* tn, double* tf) {
        const double g[3] = {grow, grow, grow};
        return slab_interval(r, bx, g, tn, tf);
    };
    double tn, tf;
    if (slabs(delta, &tn, &tf)) {
        const double t = tn >= r.tmin - tau ? tn : tf;
        out.near = t >= r.tmin - tau && t <= r.tmax + tau;
        out.t = t;
    }
    if (slabs(0.0, &tn, &tf)) {
        const double t = tn >= r.tmin ? tn : tf;
        out.t = t;
        out.strict = t >= r.tmin && t <= r.tmax;
        double tn2, tf2;
        out.robust = out.strict && slabs(-delta, &tn2, &tf2) && t >= r.tmin + tau && t <= r.tmax - tau;
    }
    out.near = out.near || out.strict;
    return out;
}

ObjectRef plane(const RayD& r, const Plane& p) {
    ObjectRef out;
    const double n[3] = {p.normal.x, p.normal.y, p.normal.z};
    const double dn = dot3(r.d, n);
    if (dn == 0.0) return out;
    const double pm[3] = {p.point.x - r.o[0], p.point.y - r.o[1], p.point.z - r.o[2]};
    out.t = dot3(pm, n) / dn;
    out.strict = out.near = out.robust = out.t >= r.tmin && out.t <= r.tmax;
    return out;
}

bool enters(const RayD& r, const Aabb& b, double s) {
    double grow[3];
    for (int k = 0; k < 3; ++k) {
        const double mag = std::max({std::fabs(double(b.lo[k])), std::fabs(double(b.hi[k])), std::fabs(r.o[k])});
        grow[k] = s * (double(b.hi[k]) - b.lo[k] + mag) + 1e-30;
    }
    double tn, tf;
    if (!slab_interval(r, b, grow, &tn, &tf)) return false;
    // The interval with a loose margin: this only skips instances the ray cannot come near.
    return tf >= r.tmin - 1e-3 * (1.0 + std::fabs(tf)) && tn <= r.tmax + 1e-3 * (1.0 + std::fabs(tn));
}

std::size_t prim_count(const Geometry& g) {
    if (const auto* m = std::get_if<Mesh>(&g)) return m->triangles.size();
    if (const auto* s = std::get_if<SphereSet>(&g)) return s->spheres.size();
    return std::get<BoxSet>(g).boxes.size();
}

}  // namespace

std::string_view name(SceneLabel l) {
    switch (l) {
    case SceneLabel::agree: return "agree";
    case SceneLabel::tie: return "tie";
    case SceneLabel::false_miss: return "false_miss";
    case SceneLabel::false_hit: return "false_hit";
    case SceneLabel::farther_hit: return "farther_hit";
    case SceneLabel::t_error: return "t_error";
    }
    return "?";
}

std::string to_string(const SceneTally& t) {
    std::ostringstream s;
    for (int i = 0; i < 6; ++i) s << (i ? " " : "") << name(SceneLabel(i)) << "=" << t.count[i];
    s << " (marginal=" << t.marginal << ")";
    return s.str();
}

SceneReferencer::SceneReferencer(const SceneDesc& scene) : scene_(&scene) {
    validate(scene);
    for (const Geometry& g : scene.geometries) {
        Aabb b;
        if (const auto* m = std::get_if<Mesh>(&g)) {
            b = m->bounds();
        } else if (const auto* s = std::get_if<SphereSet>(&g)) {
            for (const Sphere& sp : s->spheres) b.grow(sphere_bounds(sp));
        } else {
            for (const Aabb& x : std::get<BoxSet>(g).boxes) b.grow(x);
        }
        bounds_.push_back(b);
    }
    for (const Instance& in : scene.instances) {
        const auto& m = in.transform.m;
        double a[3][3];
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) a[i][k] = m[i][k];
        const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        InstanceD d;
        double inv[3][3];
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) {
                const int i1 = (k + 1) % 3, i2 = (k + 2) % 3, k1 = (i + 1) % 3, k2 = (i + 2) % 3;
                inv[i][k] = (a[i1][k1] * a[i2][k2] - a[i1][k2] * a[i2][k1]) / det;  // cofactor transpose
            }
        double na = 0, ni = 0;
        for (int i = 0; i < 3; ++i) {
            na = std::max(na, std::fabs(a[i][0]) + std::fabs(a[i][1]) + std::fabs(a[i][2]));
            ni = std::max(ni, std::fabs(inv[i][0]) + std::fabs(inv[i][1]) + std::fabs(inv[i][2]));
            for (int k = 0; k < 3; ++k) d.inv[i][k] = inv[i][k];
            d.inv[i][3] = -(inv[i][0] * m[0][3] + inv[i][1] * m[1][3] + inv[i][2] * m[2][3]);
        }
        d.cond = std::max(1.0, na * ni);
        inst_.push_back(d);
    }
}

double SceneReferencer::cond(std::uint32_t inst) const { return inst < inst_.size() ? inst_[inst].cond : 1.0; }

// One primitive of a geometry against an object-space ray.
ObjectRef SceneReferencer::shape(const RayD& r, const Geometry& g, std::uint32_t prim, double delta, double tau) {
    if (const auto* m = std::get_if<Mesh>(&g)) {
        const Triangle& tr = m->triangles[prim];
        return triangle(r, m->positions[tr[0]], m->positions[tr[1]], m->positions[tr[2]], delta, tau);
    }
    if (const auto* sp = std::get_if<SphereSet>(&g)) return sphere(r, sp->spheres[prim], delta, tau);
    return box(r, std::get<BoxSet>(g).boxes[prim], delta, tau);
}

// The object with its margins: a first pass finds t (strict and t do not depend on the margins), the second uses
// tau and delta at that t. delta bounds how far float rounding of the object-space ray (cond roundings of its
// origin and of t d) can move the hit point.
ObjectRef SceneReferencer::object_in(const Ray& ray, const RayD& r, std::uint32_t inst, std::uint32_t prim) const {
    const InstanceD& in = inst_[inst];
    const Geometry& g = scene_->geometries[scene_->instances[inst].geometry];
    const double on = std::max({std::fabs(r.o[0]), std::fabs(r.o[1]), std::fabs(r.o[2])});
    const double dn = std::max({std::fabs(r.d[0]), std::fabs(r.d[1]), std::fabs(r.d[2])});
    const double t = shape(r, g, prim, 0.0, 0.0).t, tf = std::isfinite(t) ? t : 0.0;
    const double tau = (tolerance(ray, tf) + tolerance(ray, 0.0)) * in.cond;
    return shape(r, g, prim, kNearDelta * in.cond * (on + std::fabs(tf) * dn), tau);
}

ObjectRef SceneReferencer::object(const Ray& ray, std::uint32_t inst, std::uint32_t prim) const {
    const RayD w = world_ray(ray);
    if (inst >= inst_.size()) {
        const std::size_t k = inst - inst_.size();
        if (k >= scene_->planes.size() || prim != k) return {};
        return plane(w, scene_->planes[k]);
    }
    if (prim >= prim_count(scene_->geometries[scene_->instances[inst].geometry])) return {};
    return object_in(ray, object_ray(inst_[inst], w), inst, prim);
}

SceneReference SceneReferencer::closest(const Ray& ray) const {
    SceneReference out;
    out.valid = prepare(ray).valid;
    if (!out.valid) return out;
    const RayD w = world_ray(ray);
    auto consider = [&](std::uint32_t inst, std::uint32_t prim, const ObjectRef& o) {
        if (!o.strict) return;
        if (o.t < out.t || (o.t == out.t && (inst < out.inst || (inst == out.inst && prim < out.prim)))) {
            out.t = o.t;
            out.inst = inst;
            out.prim = prim;
            out.robust = o.robust;
            out.t_sensitivity = o.t_sensitivity;
        }
    };
    for (std::uint32_t i = 0; i < inst_.size(); ++i) {
        const InstanceD& in = inst_[i];
        const RayD r = object_ray(in, w);
        const std::uint32_t geom = scene_->instances[i].geometry;
        if (!enters(r, bounds_[geom], kNearSlack * in.cond)) continue;
        const Geometry& g = scene_->geometries[geom];
        const std::size_t n = prim_count(g);
        for (std::uint32_t p = 0; p < n; ++p) {
            const ObjectRef quick = shape(r, g, p, 0.0, 0.0);  // strict and t only
            if (quick.strict && quick.t <= out.t) consider(i, p, object_in(ray, r, i, p));
        }
    }
    for (std::uint32_t k = 0; k < scene_->planes.size(); ++k)
        consider(std::uint32_t(inst_.size()) + k, k, plane(w, scene_->planes[k]));
    if (out.hit()) out.tau = tolerance(ray, out.t) * cond(out.inst);
    return out;
}

SceneReferencer::Verdict SceneReferencer::classify(const Ray& ray, const SceneReference& ref, const SceneHit& h) const {
    Verdict v;
    if (!ref.valid || !ref.hit()) {
        if (!h.hit()) return v;
        v.label = SceneLabel::false_hit;
        v.marginal = ref.valid && object(ray, h.inst, h.prim).near;
        return v;
    }
    if (!h.hit()) {
        v.label = SceneLabel::false_miss;
        v.marginal = !ref.robust;
        return v;
    }
    const double tau = std::max(ref.tau, tolerance(ray, ref.t) * cond(h.inst));
    if (h.inst == ref.inst && h.prim == ref.prim) {
        if (std::fabs(double(h.t) - ref.t) > tau * ref.t_sensitivity) v.label = SceneLabel::t_error;
        return v;
    }
    const ObjectRef o = object(ray, h.inst, h.prim);
    const double tau_o = tau * std::max(ref.t_sensitivity, o.t_sensitivity);
    if (!o.near || o.t < ref.t - tau_o) {
        v.label = SceneLabel::false_hit;
        v.marginal = o.near;
        return v;
    }
    if (o.t > ref.t + tau_o) {
        v.label = SceneLabel::farther_hit;
        v.marginal = !ref.robust || !o.strict;
        return v;
    }
    v.label = std::fabs(double(h.t) - o.t) > tau * o.t_sensitivity ? SceneLabel::t_error : SceneLabel::tie;
    return v;
}

}  // namespace simdbvh::reference
