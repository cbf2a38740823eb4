// SPDX-License-Identifier: MIT
// The degenerate family: duplicates, zero-area triangles, equal centroids.
#include "family_parts.h"

#include "simdbvh/workloads/rays.h"

namespace simdbvh::workloads::detail {

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
            for (const Triangle& t : m.triangles)
                c.mesh.triangles.push_back(Triangle{t[0] + base, t[1] + base, t[2] + base});
        }
        finish(std::move(c), o.seed * 7 + 9);
    }
    return out;
}

}  // namespace simdbvh::workloads::detail
