// Adversarial ray families (ACCURACY.md). Deterministic: own PRNG (SplitMix64),
// float math with + - * / sqrt sin cos; double only where a family says so
// (offsets are applied in double and rounded to float).
#include "simdbvh/scene/families.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <utility>

#include "rng.h"
#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/scene/rays.h"
#include "simdbvh/scene/scenes.h"

namespace simdbvh::scene {

using detail::Rng;

namespace {

constexpr float kTwoPi = 6.28318530717958648f;

std::string decade(double v) {  // 1e0, 1e3, ...
    int e = 0;
    while (v >= 10.0) { v /= 10.0; ++e; }
    return "1e" + std::to_string(e);
}

Vec3 translate(Vec3 p, double off) {
    return {float(double(p.x) + off), float(double(p.y) + off), float(double(p.z) + off)};
}

// A point strictly inside the unit ball scaled by r (rejection sampling).
Vec3 in_ball(Rng& rng, float r) {
    for (;;) {
        const Vec3 p{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
        if (dot(p, p) < 1.0f) return p * r;
    }
}

Vec3 unit_vector(Rng& rng) {
    const float z = 1.0f - 2.0f * rng.uniform();
    const float phi = kTwoPi * rng.uniform();
    const float s = std::sqrt(std::fmax(0.0f, 1.0f - z * z));
    return {s * std::cos(phi), s * std::sin(phi), z};
}

// Targets of the watertight family: every vertex, then every edge midpoint
// (each undirected edge once, in first-seen order).
std::vector<Vec3> vertex_and_edge_targets(const Mesh& m) {
    std::vector<Vec3> out(m.positions);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    edges.reserve(m.triangles.size() * 3);
    for (const Triangle& t : m.triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            edges.emplace_back(std::min(a, b), std::max(a, b));
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    for (const auto& [a, b] : edges) out.push_back((m.positions[a] + m.positions[b]) * 0.5f);
    return out;
}

// Origins and targets of a watertight case, before any offset.
struct Aimed {
    std::vector<Vec3> origins, targets;
};

Aimed aim_icosphere(const Mesh& m, std::uint64_t seed) {
    Aimed a;
    a.targets = vertex_and_edge_targets(m);
    Rng rng(seed);
    for (std::size_t i = 0; i < a.targets.size(); ++i) a.origins.push_back(i % 4 == 0 ? Vec3{} : in_ball(rng, 0.5f));
    return a;
}

// Torus targets: the origin is on the core circle at the target's azimuth,
// jittered inside half the tube radius.
Aimed aim_torus(const Mesh& m, float major_r, float minor_r, std::uint64_t seed) {
    Aimed a;
    a.targets = vertex_and_edge_targets(m);
    Rng rng(seed);
    for (const Vec3& t : a.targets) {
        const float phi = std::atan2(t.y, t.x) + rng.uniform(-0.05f, 0.05f);
        a.origins.push_back(Vec3{major_r * std::cos(phi), major_r * std::sin(phi), 0.0f} + in_ball(rng, 0.5f * minor_r));
    }
    return a;
}

// One case from aimed rays, translated by `off` in double: the mesh and the
// origins and targets are rounded to float after the translation; the
// direction is the difference of the translated floats, in double, rounded.
FamilyCase aimed_case(Family f, std::string name, const Mesh& mesh, const Aimed& a, double off, Expect e) {
    FamilyCase c;
    c.family = f;
    c.name = std::move(name);
    c.offset = off;
    c.mesh.triangles = mesh.triangles;
    c.mesh.positions.reserve(mesh.positions.size());
    for (const Vec3& p : mesh.positions) c.mesh.positions.push_back(translate(p, off));
    for (std::size_t i = 0; i < a.targets.size(); ++i) {
        const Vec3 o = translate(a.origins[i], off), t = translate(a.targets[i], off);
        Ray r;
        r.org = o;
        r.dir = {float(double(t.x) - double(o.x)), float(double(t.y) - double(o.y)), float(double(t.z) - double(o.z))};
        if (r.dir == Vec3{}) continue;  // the origin rounded onto the target
        c.rays.push_back(r);
        c.expect.push_back(RayExpect{e});
    }
    return c;
}

struct WatertightMeshes {
    Mesh sphere, ring;
    Aimed sphere_rays, ring_rays;
};

WatertightMeshes watertight_meshes(const FamilyOptions& o) {
    WatertightMeshes w;
    w.sphere = icosphere(o.quick ? 3 : 4);
    const int n = o.quick ? 32 : 64, m = o.quick ? 16 : 32;
    w.ring = torus(n, m, 1.0f, 0.35f);
    w.sphere_rays = aim_icosphere(w.sphere, o.seed * 31 + 1);
    w.ring_rays = aim_torus(w.ring, 1.0f, 0.35f, o.seed * 31 + 2);
    return w;
}

std::vector<FamilyCase> family_watertight(const FamilyOptions& o) {
    const WatertightMeshes w = watertight_meshes(o);
    std::vector<FamilyCase> out;
    out.push_back(aimed_case(Family::watertight, "watertight/icosphere", w.sphere, w.sphere_rays, 0.0, Expect::hit));
    out.push_back(aimed_case(Family::watertight, "watertight/torus", w.ring, w.ring_rays, 0.0, Expect::hit));
    return out;
}

// Translated copies: at large offsets the float mesh collapses (the float
// spacing at 1e7 is 1, the mesh's size), so the answer is the reference on
// the translated floats; "must hit" holds at small offsets only.
std::vector<FamilyCase> family_offsets(const FamilyOptions& o) {
    const WatertightMeshes w = watertight_meshes(o);
    std::vector<FamilyCase> out;
    for (double off = 1.0; off <= 1e7; off *= 10.0) {
        out.push_back(aimed_case(Family::offsets, "offsets/icosphere/" + decade(off), w.sphere, w.sphere_rays, off,
                                 Expect::reference));
        out.push_back(
            aimed_case(Family::offsets, "offsets/torus/" + decade(off), w.ring, w.ring_rays, off, Expect::reference));
    }
    return out;
}

// The icosphere's aimed rays with the direction (target - origin, in double)
// scaled by 2^e and rounded once to float: from 2^-149 (the smallest subnormal:
// most components round to zero, the ray turns axis-aligned) to 2^127 (the
// largest component near FLT_MAX). The origin is inside the closed sphere, so
// every ray must hit; where t exceeds FLT_MAX the hit is reported with t = +inf
// (kernels/ray.h).
std::vector<FamilyCase> family_direction_scale(const FamilyOptions& o) {
    const WatertightMeshes w = watertight_meshes(o);
    const Aimed& a = w.sphere_rays;
    std::vector<FamilyCase> out;
    for (int e : {-149, -145, -140, -130, -127, -120, -100, -64, -33, 0, 33, 64, 100, 120, 127}) {
        FamilyCase c;
        c.family = Family::direction_scale;
        c.name = "direction-scale/2^" + std::to_string(e);
        c.mesh = w.sphere;
        for (std::size_t i = 0; i < a.targets.size(); ++i) {
            const Vec3 org = a.origins[i], t = a.targets[i];
            Ray r;
            r.org = org;
            r.dir = {float(std::ldexp(double(t.x) - double(org.x), e)), float(std::ldexp(double(t.y) - double(org.y), e)),
                     float(std::ldexp(double(t.z) - double(org.z), e))};
            if (r.dir == Vec3{}) continue;  // every component rounded to zero
            c.rays.push_back(r);
            c.expect.push_back(RayExpect{Expect::hit});
        }
        out.push_back(std::move(c));
    }
    return out;
}

void append_quad(Mesh& m, Vec3 a, Vec3 b, Vec3 c, Vec3 d) {  // a b c d counter-clockwise
    const auto i = std::uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {a, b, c, d});
    m.triangles.push_back(Triangle{i, i + 1, i + 2});
    m.triangles.push_back(Triangle{i, i + 2, i + 3});
}

void append_box(Mesh& m, Vec3 lo, Vec3 hi) {
    auto p = [&](int i) { return Vec3{(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z}; };
    append_quad(m, p(0), p(2), p(3), p(1));  // z = lo
    append_quad(m, p(4), p(5), p(7), p(6));  // z = hi
    append_quad(m, p(0), p(1), p(5), p(4));  // y = lo
    append_quad(m, p(2), p(6), p(7), p(3));  // y = hi
    append_quad(m, p(0), p(4), p(6), p(2));  // x = lo
    append_quad(m, p(1), p(3), p(7), p(5));  // x = hi
}

// A 3 x 3 x 3 lattice of boxes [i, i + 0.5]^3 (their faces are the BVH's slab
// planes), rays along the axes and along face diagonals with +-0.0 in the
// other components, from lattice origins on those planes.
std::vector<FamilyCase> family_axis_aligned(const FamilyOptions& o) {
    FamilyCase c;
    c.family = Family::axis_aligned;
    c.name = "axis-aligned/boxes";
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) {
                const Vec3 lo{float(i), float(j), float(k)};
                append_box(c.mesh, lo, lo + Vec3{0.5f, 0.5f, 0.5f});
            }
    std::vector<Vec3> dirs;
    for (int axis = 0; axis < 3; ++axis)
        for (float s : {1.0f, -1.0f})
            for (float z1 : {0.0f, -0.0f})
                for (float z2 : {0.0f, -0.0f}) {
                    Vec3 d{z1, z1, z1};
                    d[axis] = s;
                    d[(axis + 1) % 3] = z1;
                    d[(axis + 2) % 3] = z2;
                    dirs.push_back(d);
                }
    for (int axis = 0; axis < 3; ++axis)  // face diagonals: one zero component
        for (float s1 : {1.0f, -1.0f})
            for (float s2 : {1.0f, -1.0f})
                for (float z : {0.0f, -0.0f}) {
                    Vec3 d;
                    d[axis] = z;
                    d[(axis + 1) % 3] = s1;
                    d[(axis + 2) % 3] = s2;
                    dirs.push_back(d);
                }
    const std::vector<float> coords = o.quick ? std::vector<float>{-1.0f, 0.0f, 0.5f, 1.0f, 2.5f}
                                              : std::vector<float>{-1.0f, 0.0f, 0.25f, 0.5f, 1.0f, 1.5f, 2.5f, 3.0f};
    for (float x : coords)
        for (float y : coords)
            for (float z : coords)
                for (const Vec3& d : dirs) {
                    Ray r;
                    r.org = {x, y, z};
                    r.dir = d;
                    c.rays.push_back(r);
                    c.expect.push_back(RayExpect{Expect::reference});
                }
    return {std::move(c)};
}

// Closest hits with the BVH2 (watertight, conservative): the primary rays of
// the surface-start family.
std::vector<Hit> trace(const Mesh& m, const std::vector<Ray>& rays) {
    const Bvh2 bvh = Bvh2::build(m);
    std::vector<Hit> hits(rays.size());
    intersect(bvh, rays, hits);
    return hits;
}

// Secondary rays from the hits of `primary`: the hit point from the
// barycentrics, offset along the geometric normal turned towards the incoming
// ray, directions cosine-weighted about that normal.
FamilyCase secondary_case(std::string name, Mesh mesh, const std::vector<Ray>& primary, double off,
                          std::size_t count, std::uint64_t seed) {
    FamilyCase c;
    c.family = Family::surface_start;
    c.name = std::move(name);
    c.offset = off;
    const std::vector<Hit> hits = trace(mesh, primary);
    Rng rng(seed);
    for (std::size_t i = 0; i < hits.size() && c.rays.size() < count; ++i) {
        const Hit& h = hits[i];
        if (!h.hit()) continue;
        const Vec3 v0 = mesh.vertex(h.prim, 0), v1 = mesh.vertex(h.prim, 1), v2 = mesh.vertex(h.prim, 2);
        const Vec3 p = v0 * (1.0f - h.u - h.v) + v1 * h.u + v2 * h.v;
        Vec3 n = cross(v1 - v0, v2 - v0);
        if (!(dot(n, n) > 0.0f) || !std::isfinite(dot(n, n))) continue;
        n = normalize(n);
        if (dot(n, primary[i].dir) > 0.0f) n = n * -1.0f;
        // Cosine-weighted direction about n (Malley), basis by Duff et al. 2017.
        const float sg = std::copysign(1.0f, n.z);
        const float a = -1.0f / (sg + n.z), b = n.x * n.y * a;
        const Vec3 t{1.0f + sg * n.x * n.x * a, sg * b, -sg * n.x}, bt{b, sg + n.y * n.y * a, -n.y};
        const float r = std::sqrt(rng.uniform()), phi = kTwoPi * rng.uniform();
        const float dz = std::sqrt(std::fmax(0.0f, 1.0f - r * r));
        Vec3 d = t * (r * std::cos(phi)) + bt * (r * std::sin(phi)) + n * dz;
        if (!(dot(d, n) > 0.0f)) d = n;
        Ray s;
        s.org = offset_ray_origin(p, n);
        s.dir = normalize(d);
        c.rays.push_back(s);
        c.expect.push_back(RayExpect{Expect::no_self_hit, h.prim});
    }
    c.mesh = std::move(mesh);
    return c;
}

std::vector<FamilyCase> family_surface_start(const FamilyOptions& o) {
    const std::size_t n = o.quick ? 3000 : 20000;
    std::vector<FamilyCase> out;
    // Inside an icosphere (bounces cross to the far side), at 0 and at 1e4.
    for (double off : {0.0, 1e4}) {
        Mesh m = icosphere(4);
        for (Vec3& p : m.positions) p = translate(p, off);
        const Vec3 c = translate(Vec3{}, off);
        Rng rng(o.seed * 131 + 7);
        std::vector<Ray> primary;
        for (std::size_t i = 0; i < n; ++i) {
            Ray r;
            r.org = c + in_ball(rng, 0.3f);
            r.dir = unit_vector(rng);
            primary.push_back(r);
        }
        out.push_back(secondary_case(off == 0.0 ? "surface-start/icosphere" : "surface-start/icosphere/" + decade(off),
                                     std::move(m), primary, off, n, o.seed * 131 + 8));
    }
    // A random soup: arbitrary orientations and sizes.
    Mesh soup = random_soup(o.quick ? 2000 : 10000, o.seed * 131 + 9);
    const auto primary = incoherent_rays(soup.bounds(), n, o.seed * 131 + 10);
    out.push_back(secondary_case("surface-start/soup", std::move(soup), primary, 0.0, n, o.seed * 131 + 11));
    return out;
}

// A tessellated plane y = 0 over [-1, 1]^2; rays reach it at angle theta
// after a horizontal run of 0.4 (t = h / sin(theta) from the float ray), or
// run parallel to it (theta = 0) in it (coplanar) or above it: misses.
std::vector<FamilyCase> family_grazing(const FamilyOptions& o) {
    FamilyCase c;
    c.family = Family::grazing;
    c.name = "grazing/plane";
    const int g = o.quick ? 16 : 64;
    for (int i = 0; i <= g; ++i)
        for (int j = 0; j <= g; ++j)
            c.mesh.positions.push_back(Vec3{-1.0f + 2.0f * float(i) / float(g), 0.0f, -1.0f + 2.0f * float(j) / float(g)});
    for (int i = 0; i < g; ++i)
        for (int j = 0; j < g; ++j) {
            const auto a = std::uint32_t(i * (g + 1) + j), b = a + 1, cc = a + std::uint32_t(g + 1), d = cc + 1;
            c.mesh.triangles.push_back(Triangle{a, b, d});
            c.mesh.triangles.push_back(Triangle{a, d, cc});
        }
    Rng rng(o.seed * 17 + 3);
    const int per_angle = o.quick ? 128 : 1024;
    const double run = 0.4;
    for (double theta : {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 0.0}) {
        for (int k = 0; k < per_angle; ++k) {
            const double phi = double(kTwoPi) * double(rng.uniform());
            const double hx = double(rng.uniform(-0.5f, 0.5f)), hz = double(rng.uniform(-0.5f, 0.5f));
            const double ax = std::cos(phi), az = std::sin(phi);
            Ray r;
            if (theta > 0.0) {
                r.dir = {float(ax * std::cos(theta)), float(-std::sin(theta)), float(az * std::cos(theta))};
                const double h = run * std::tan(theta);
                r.org = {float(hx - ax * run), float(h), float(hz - az * run)};
                // From the float ray: t = h / sin(theta) = -o.y / d.y.
                c.rays.push_back(r);
                c.expect.push_back(RayExpect{Expect::hit, kInvalidPrim, -double(r.org.y) / double(r.dir.y)});
            } else {
                r.dir = {float(ax), (k & 1) ? -0.0f : 0.0f, float(az)};
                r.org = {float(hx - ax * run), (k & 2) ? float(run * 1e-6) : ((k & 4) ? -0.0f : 0.0f), float(hz - az * run)};
                c.rays.push_back(r);
                c.expect.push_back(RayExpect{Expect::miss});
            }
        }
    }
    return {std::move(c)};
}

// Fans of needles: apex at the origin, k base points on x = 1 spaced 1/aspect
// apart. Rays aim at points on the interior shared edges and at the needles'
// centroids from both sides; axis-aligned fans must be hit, rotated (and
// translated) fans are checked against the reference.
std::vector<FamilyCase> family_needles(const FamilyOptions& o) {
    std::vector<FamilyCase> out;
    const int k = o.quick ? 16 : 64;
    for (double aspect = 10.0; aspect <= 1e7; aspect *= 10.0) {
        for (int rotated = 0; rotated < 2; ++rotated) {
            FamilyCase c;
            c.family = Family::needles;
            c.name = "needles/aspect" + decade(aspect) + (rotated ? "/rotated" : "");
            // Rotation about (1, 2, 3)/|.| by 0.7 rad, then a translation, in double.
            const double ux = 1 / std::sqrt(14.0), uy = 2 / std::sqrt(14.0), uz = 3 / std::sqrt(14.0);
            const double ca = std::cos(0.7), sa = std::sin(0.7);
            auto place = [&](double x, double y, double z) -> Vec3 {
                if (!rotated) return {float(x), float(y), float(z)};
                const double d = ux * x + uy * y + uz * z;
                const double cx = uy * z - uz * y, cy = uz * x - ux * z, cz = ux * y - uy * x;
                return {float(x * ca + cx * sa + ux * d * (1 - ca) + 0.25),
                        float(y * ca + cy * sa + uy * d * (1 - ca) - 0.5),
                        float(z * ca + cz * sa + uz * d * (1 - ca) + 0.125)};
            };
            const double w = 1.0 / aspect;
            c.mesh.positions.push_back(place(0, 0, 0));
            for (int j = 0; j <= k; ++j) c.mesh.positions.push_back(place(1.0, (j - k / 2) * w, 0));
            for (int j = 0; j < k; ++j) c.mesh.triangles.push_back(Triangle{0, std::uint32_t(j + 1), std::uint32_t(j + 2)});
            const Expect e = rotated ? Expect::reference : Expect::hit;
            for (int side = 0; side < 2; ++side) {
                const double oz = side ? -1.0 : 1.0, ox = side ? 0.4 : 0.5;
                const Vec3 org = place(ox, 0, oz);
                auto aim = [&](double x, double y) {
                    const Vec3 t = place(x, y, 0);
                    Ray r;
                    r.org = org;
                    r.dir = {float(double(t.x) - double(org.x)), float(double(t.y) - double(org.y)),
                             float(double(t.z) - double(org.z))};
                    c.rays.push_back(r);
                    c.expect.push_back(RayExpect{e});
                };
                // Interior shared edges and centroids, away from the fan's sides. A
                // rotated fan's vertices are rounded after the rotation (~6e-8 at
                // 1), which moves its sides by up to a needle's width at aspect
                // 1e7: its aims keep to the middle half and s >= 0.3 so that the
                // target is inside the float fan too.
                const int j0 = rotated ? k / 4 : 2, j1 = rotated ? k - k / 4 : k - 2;
                for (int j = j0; j <= j1; ++j)
                    for (double s : {0.1, 0.3, 0.5, 0.7, 0.9})
                        if (!rotated || s >= 0.3) aim(s, s * (j - k / 2) * w);
                for (int j = j0; j < j1; ++j) aim(2.0 / 3.0, (2.0 / 3.0) * ((j - k / 2) + 0.5) * w);  // centroids
            }
            out.push_back(std::move(c));
        }
    }
    return out;
}

// Degenerate scenes: the builder must terminate under the depth cap and
// degenerate triangles must never be hit.
std::vector<FamilyCase> family_degenerate(const FamilyOptions& o) {
    const std::size_t n = o.quick ? 500 : 4000;
    const std::size_t nrays = o.quick ? 2000 : 10000;
    std::vector<FamilyCase> out;
    auto finish = [&](FamilyCase c, std::uint64_t seed) {
        c.family = Family::degenerate;
        c.rays = incoherent_rays(c.mesh.bounds(), nrays, seed);
        c.expect.assign(c.rays.size(), RayExpect{Expect::reference});
        out.push_back(std::move(c));
    };
    Rng rng(o.seed * 7 + 5);
    {  // n copies of one triangle (same vertices, and same positions at new indices)
        FamilyCase c;
        c.name = "degenerate/duplicates";
        c.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        for (std::size_t i = 0; i < n; ++i) {
            if (i % 2) c.mesh.triangles.push_back(Triangle{0, 1, 2});
            else {
                const auto b = std::uint32_t(c.mesh.positions.size());
                c.mesh.positions.insert(c.mesh.positions.end(), {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
                c.mesh.triangles.push_back(Triangle{b, b + 1, b + 2});
            }
        }
        finish(std::move(c), o.seed * 7 + 6);
    }
    {  // zero-area: points and collinear triangles, plus a few ordinary ones
        FamilyCase c;
        c.name = "degenerate/zero-area";
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3 a{rng.uniform(), rng.uniform(), rng.uniform()};
            const Vec3 b{rng.uniform(), rng.uniform(), rng.uniform()};
            const auto base = std::uint32_t(c.mesh.positions.size());
            if (i % 10 == 0) {  // ordinary
                c.mesh.positions.insert(c.mesh.positions.end(), {a, b, a + Vec3{0.05f, 0.0f, 0.05f}});
            } else if (i % 3 == 0) {  // a point
                c.mesh.positions.insert(c.mesh.positions.end(), {a, a, a});
            } else {  // collinear: an endpoint repeated, or the midpoint
                c.mesh.positions.insert(c.mesh.positions.end(), {a, b, (i % 3 == 1) ? a : (a + b) * 0.5f});
            }
            c.mesh.triangles.push_back(Triangle{base, base + 1, base + 2});
        }
        finish(std::move(c), o.seed * 7 + 7);
    }
    {  // equal centroids: every triangle's box is [0, 1]^3 (a = 0, b = 1, c inside)
        FamilyCase c;
        c.name = "degenerate/equal-centroids";
        for (std::size_t i = 0; i < n; ++i) {
            const auto base = std::uint32_t(c.mesh.positions.size());
            c.mesh.positions.insert(c.mesh.positions.end(),
                                    {{0, 0, 0}, {1, 1, 1}, {rng.uniform(), rng.uniform(), rng.uniform()}});
            c.mesh.triangles.push_back(Triangle{base, base + 1, base + 2});
        }
        finish(std::move(c), o.seed * 7 + 8);
    }
    {  // all of it at once
        FamilyCase c;
        c.name = "degenerate/mixed";
        for (std::size_t i = 0; i < 3; ++i) {
            const Mesh& m = out[i].mesh;
            const auto base = std::uint32_t(c.mesh.positions.size());
            c.mesh.positions.insert(c.mesh.positions.end(), m.positions.begin(), m.positions.end());
            for (const Triangle& t : m.triangles) c.mesh.triangles.push_back(Triangle{t[0] + base, t[1] + base, t[2] + base});
        }
        finish(std::move(c), o.seed * 7 + 9);
    }
    return out;
}

std::vector<FamilyCase> family_random(const FamilyOptions& o) {
    FamilyCase c;
    c.family = Family::random;
    std::string scene = o.random_scene;
    if (scene.empty() && is_cached("dragon-res4")) scene = "dragon-res4";
    if (!scene.empty()) {
        c.mesh = load_scene(scene);
        c.name = "random/" + scene;
    } else {
        c.mesh = icosphere(4, 0.5f, {0.5f, 0.5f, 0.5f});
        const Mesh soup = random_soup(4000, o.seed * 3 + 1);
        const auto base = std::uint32_t(c.mesh.positions.size());
        c.mesh.positions.insert(c.mesh.positions.end(), soup.positions.begin(), soup.positions.end());
        for (const Triangle& t : soup.triangles) c.mesh.triangles.push_back(Triangle{t[0] + base, t[1] + base, t[2] + base});
        c.name = "random/icosphere+soup";
    }
    c.rays = incoherent_rays(c.mesh.bounds(), o.quick ? 2000 : 20000, o.seed * 3 + 2);
    c.expect.assign(c.rays.size(), RayExpect{Expect::reference});
    return {std::move(c)};
}

}  // namespace

std::string_view name(Family f) {
    switch (f) {
    case Family::watertight: return "watertight";
    case Family::offsets: return "offsets";
    case Family::axis_aligned: return "axis-aligned";
    case Family::surface_start: return "surface-start";
    case Family::grazing: return "grazing";
    case Family::needles: return "needles";
    case Family::degenerate: return "degenerate";
    case Family::random: return "random";
    case Family::direction_scale: return "direction-scale";
    }
    return "?";
}

std::optional<Family> parse_family(std::string_view s) {
    for (Family f : kAllFamilies)
        if (s == name(f)) return f;
    return std::nullopt;
}

std::string_view name(Expect e) {
    switch (e) {
    case Expect::reference: return "reference";
    case Expect::hit: return "hit";
    case Expect::miss: return "miss";
    case Expect::no_self_hit: return "no-self-hit";
    }
    return "?";
}

std::vector<FamilyCase> make_family(Family f, const FamilyOptions& o) {
    switch (f) {
    case Family::watertight: return family_watertight(o);
    case Family::offsets: return family_offsets(o);
    case Family::axis_aligned: return family_axis_aligned(o);
    case Family::surface_start: return family_surface_start(o);
    case Family::grazing: return family_grazing(o);
    case Family::needles: return family_needles(o);
    case Family::degenerate: return family_degenerate(o);
    case Family::random: return family_random(o);
    case Family::direction_scale: return family_direction_scale(o);
    }
    throw Error("unknown ray family");
}

Mesh torus(int n, int m, float major_r, float minor_r, Vec3 center) {
    if (n < 3 || m < 3) throw Error("torus needs at least 3 x 3 segments");
    Mesh t;
    for (int i = 0; i < n; ++i) {
        const float phi = kTwoPi * float(i) / float(n);
        for (int j = 0; j < m; ++j) {
            const float th = kTwoPi * float(j) / float(m);
            const float rr = major_r + minor_r * std::cos(th);
            t.positions.push_back(center + Vec3{rr * std::cos(phi), rr * std::sin(phi), minor_r * std::sin(th)});
        }
    }
    auto id = [&](int i, int j) { return std::uint32_t((i % n) * m + (j % m)); };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) {  // outward counter-clockwise
            t.triangles.push_back(Triangle{id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            t.triangles.push_back(Triangle{id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return t;
}

// Wachter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection"
// (Ray Tracing Gems, ch. 6): move p by 256 ulps along n per component; within
// 1/32 of the origin, by n / 65536.
Vec3 offset_ray_origin(Vec3 p, Vec3 n) {
    constexpr float kOrigin = 1.0f / 32.0f, kFloatScale = 1.0f / 65536.0f, kIntScale = 256.0f;
    Vec3 out;
    for (int k = 0; k < 3; ++k) {
        const auto of = std::int32_t(kIntScale * n[k]);
        const auto bits = std::bit_cast<std::int32_t>(p[k]);
        const float pi = std::bit_cast<float>(bits + (p[k] < 0.0f ? -of : of));
        out[k] = std::fabs(p[k]) < kOrigin ? p[k] + kFloatScale * n[k] : pi;
    }
    return out;
}

std::vector<unsigned char> encode_ply(const Mesh& mesh) {
    const std::string head = "ply\nformat binary_little_endian 1.0\ncomment simdbvh ray family\nelement vertex " +
                             std::to_string(mesh.positions.size()) +
                             "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                             std::to_string(mesh.triangles.size()) +
                             "\nproperty list uchar uint vertex_indices\nend_header\n";
    std::vector<unsigned char> bytes(head.begin(), head.end());
    bytes.reserve(head.size() + mesh.positions.size() * 12 + mesh.triangles.size() * 13);
    auto put = [&](const void* p, std::size_t n) {
        const auto* c = static_cast<const unsigned char*>(p);
        bytes.insert(bytes.end(), c, c + n);
    };
    static_assert(std::endian::native == std::endian::little);
    for (const Vec3& p : mesh.positions) put(&p, 12);
    for (const Triangle& t : mesh.triangles) {
        const unsigned char three = 3;
        put(&three, 1);
        put(t.data(), 12);
    }
    return bytes;
}

void write_ply(const std::filesystem::path& file, const Mesh& mesh) { write_file_atomic(file, encode_ply(mesh)); }

}  // namespace simdbvh::scene
