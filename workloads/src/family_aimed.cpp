// SPDX-License-Identifier: MIT
// The aimed families: watertight (closed icosphere and torus, origins inside,
// aimed at every vertex and edge midpoint), offsets (the same translated by
// 1e0..1e7) and direction-scale (the icosphere rays with scaled directions).
#include "family_parts.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "simdbvh/workloads/scenes.h"

namespace simdbvh::workloads::detail {

namespace {

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
        a.origins.push_back(Vec3{major_r * std::cos(phi), major_r * std::sin(phi), 0.0f} +
                            in_ball(rng, 0.5f * minor_r));
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

}  // namespace

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
            r.dir = {float(std::ldexp(double(t.x) - double(org.x), e)),
                     float(std::ldexp(double(t.y) - double(org.y), e)),
                     float(std::ldexp(double(t.z) - double(org.z), e))};
            if (r.dir == Vec3{}) continue;  // every component rounded to zero
            c.rays.push_back(r);
            c.expect.push_back(RayExpect{Expect::hit});
        }
        out.push_back(std::move(c));
    }
    return out;
}

}  // namespace simdbvh::workloads::detail
