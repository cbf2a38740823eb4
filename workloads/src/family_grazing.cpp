// SPDX-License-Identifier: MIT
// The grazing family: a tessellated plane and rays at angles 1e-1..1e-6 rad
// and exactly 0 (coplanar and parallel).
#include "family_parts.h"

#include <cmath>

namespace simdbvh::workloads::detail {

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
            c.mesh.positions.push_back(
                Vec3{-1.0f + 2.0f * float(i) / float(g), 0.0f, -1.0f + 2.0f * float(j) / float(g)});
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
                r.org = {float(hx - ax * run), (k & 2) ? float(run * 1e-6) : ((k & 4) ? -0.0f : 0.0f),
                         float(hz - az * run)};
                c.rays.push_back(r);
                c.expect.push_back(RayExpect{Expect::miss});
            }
        }
    }
    return {std::move(c)};
}

}  // namespace simdbvh::workloads::detail
