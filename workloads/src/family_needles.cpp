// SPDX-License-Identifier: MIT
// The needles family: fans of very thin triangles, aspect 1e1..1e7.
#include "family_parts.h"

#include <cmath>

namespace simdbvh::workloads::detail {

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
            for (int j = 0; j < k; ++j)
                c.mesh.triangles.push_back(Triangle{0, std::uint32_t(j + 1), std::uint32_t(j + 2)});
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

}  // namespace simdbvh::workloads::detail
