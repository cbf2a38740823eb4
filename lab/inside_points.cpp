// SPDX-License-Identifier: MIT
// The inside/outside panel's meshes and point families (inside_points.h).
#include "lab.h"
#include "inside_points.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace simdbvh::lab {

Mesh cube_grid(int k) {
    Mesh m;
    std::map<std::array<int, 3>, std::uint32_t> index;
    auto vertex = [&](int x, int y, int z) {
        auto [it, added] = index.try_emplace({x, y, z}, std::uint32_t(m.positions.size()));
        if (added) m.positions.push_back({float(x), float(y), float(z)});
        return it->second;
    };
    // axis a is the face normal's axis; (u, v) the other two in right-handed order.
    for (int a = 0; a < 3; ++a) {
        const int u = (a + 1) % 3, v = (a + 2) % 3;
        for (int side = 0; side < 2; ++side)
            for (int i = 0; i < k; ++i)
                for (int j = 0; j < k; ++j) {
                    auto at = [&](int di, int dj) {
                        int c[3];
                        c[a] = side * k;
                        c[u] = i + di;
                        c[v] = j + dj;
                        return vertex(c[0], c[1], c[2]);
                    };
                    const std::uint32_t p00 = at(0, 0), p10 = at(1, 0), p11 = at(1, 1), p01 = at(0, 1);
                    if (side == 1) {  // normal +a: u x v = a
                        m.triangles.push_back({p00, p10, p11});
                        m.triangles.push_back({p00, p11, p01});
                    } else {
                        m.triangles.push_back({p00, p11, p10});
                        m.triangles.push_back({p00, p01, p11});
                    }
                }
    }
    return m;
}

std::vector<Vec3> lattice_points(int k) {
    std::vector<Vec3> p;
    for (int x2 = -2; x2 <= 2 * k + 2; ++x2)
        for (int y2 = -2; y2 <= 2 * k + 2; ++y2) {
            if (x2 % 2 != 0 && y2 % 2 != 0) continue;  // at least one integer coordinate
            for (int z = -1; z <= k; ++z) p.push_back({0.5f * float(x2), 0.5f * float(y2), float(z) + 0.5f});
        }
    return p;
}

std::vector<Vec3> through_vertices(const Mesh& m, std::size_t max, float d) {
    std::vector<Vec3> p;
    for (std::size_t i = 0; i < m.positions.size() && p.size() < max; ++i) {
        const Vec3 v = m.positions[i];
        p.push_back({v.x, v.y, v.z - d});
        p.push_back({v.x, v.y, v.z + d});
    }
    return p;
}

namespace {

// a + b when it is exact in double and in float (Knuth's TwoSum: s + err == a + b exactly).
bool exact_float_sum(double a, double b, float& out) {
    const double s = a + b, bb = s - a, err = (a - (s - bb)) + (b - bb);
    out = float(s);
    return err == 0 && double(out) == s;
}

}  // namespace

std::vector<Vec3> diagonal_through_vertices(const Mesh& m, std::size_t max) {
    std::vector<Vec3> p;
    if (m.positions.empty()) return p;
    const Vec3 e = m.bounds().extent();
    int exp = 0;
    std::frexp(double(std::max({e.x, e.y, e.z})), &exp);  // 2^(exp-1) <= extent < 2^exp
    const double d = std::ldexp(1.0, exp - 1 - 8);
    for (std::size_t i = 0; i < m.positions.size() && p.size() < max; ++i) {
        const Vec3 v = m.positions[i];
        for (double s : {-d, d}) {
            Vec3 q;
            if (exact_float_sum(v.x, s, q.x) && exact_float_sum(v.y, s, q.y) && exact_float_sum(v.z, s, q.z))
                p.push_back(q);
        }
    }
    return p;
}

std::vector<Vec3> near_surface(const Mesh& m, std::size_t max, int ulps) {
    std::vector<Vec3> p;
    for (std::size_t t = 0; t < m.size() && p.size() < max; ++t) {
        const Vec3 a = m.vertex(t, 0), b1 = m.vertex(t, 1), c = m.vertex(t, 2);
        const double ux = b1.x - a.x, uy = b1.y - a.y, uz = b1.z - a.z, vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
        double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
        const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
        if (!(len > 0)) continue;
        nx /= len, ny /= len, nz /= len;
        const double cx = (double(a.x) + b1.x + c.x) / 3, cy = (double(a.y) + b1.y + c.y) / 3,
                     cz = (double(a.z) + b1.z + c.z) / 3;
        const float big = float(std::max({std::fabs(cx), std::fabs(cy), std::fabs(cz)}));
        const double ulp = double(std::nextafter(big, INFINITY)) - double(big);
        for (double s : {-1.0, 1.0}) {
            const double o = s * ulps * ulp;
            p.push_back({float(cx + o * nx), float(cy + o * ny), float(cz + o * nz)});
        }
    }
    return p;
}

}  // namespace simdbvh::lab
