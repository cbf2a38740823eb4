// SPDX-License-Identifier: MIT
// The surface-start family: secondary rays from BVH2 hit points, offset
// along the geometric normal (Wachter and Binder, RT Gems ch. 6).
#include "family_parts.h"

#include <cmath>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh::workloads::detail {

namespace {

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
FamilyCase secondary_case(std::string name, Mesh mesh, const std::vector<Ray>& primary, double off, std::size_t count,
                          std::uint64_t seed) {
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

}  // namespace

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

}  // namespace simdbvh::workloads::detail
