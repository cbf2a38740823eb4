#include "support/huge_meshes.h"

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace test {

using simdbvh::Mesh;
using simdbvh::Ray;
using simdbvh::Vec3;

namespace {

void add_triangle(Mesh& m, Vec3 a, Vec3 b, Vec3 c) {
    const auto base = std::uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {a, b, c});
    m.triangles.push_back({base, base + 1, base + 2});
}

// Corner k of the +-3e38 cube: sign of axis i from bit i.
Vec3 corner(int k) {
    const float s = 3e38f;
    return {k & 1 ? s : -s, k & 2 ? s : -s, k & 4 ? s : -s};
}

}  // namespace

Mesh huge_triangle_mesh() {
    Mesh m;
    add_triangle(m, {-1e19f, -1e19f, 0}, {1e19f, -1e19f, 0}, {0, 1e19f, 0});
    for (int i = 0; i < 8; ++i) {
        const float x = 1.0f + float(i), y = 1.0f + 0.5f * float(i);
        add_triangle(m, {x, y, 1}, {x + 0.9f, y, 1}, {x, y + 0.9f, 1});
    }
    return m;
}

Mesh extreme_mesh() {
    Mesh m = huge_triangle_mesh();
    const float d = 1e37f;
    for (int k = 0; k < 8; ++k) {
        const Vec3 c = corner(k);
        // Inward from the corner so every vertex stays finite.
        const float sx = c.x > 0 ? -1.0f : 1.0f, sy = c.y > 0 ? -1.0f : 1.0f;
        for (int j = 0; j < 4; ++j) {
            const float o = d * float(j);
            add_triangle(m, {c.x + sx * o, c.y, c.z}, {c.x + sx * (o + d), c.y, c.z},
                         {c.x + sx * o, c.y + sy * d, c.z});
        }
    }
    return m;
}

std::vector<Ray> huge_mesh_rays(const Mesh& mesh) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    std::vector<Ray> rays;
    // Straight down over the small triangles (and the huge one around them).
    for (int i = 0; i <= 48; ++i)
        for (int j = 0; j <= 24; ++j)
            rays.push_back(Ray{{0.5f + 0.2f * float(i), 0.5f + 0.25f * float(j), 10.0f}, 0.0f, {0, 0, -1}, kInf});
    // Slanted and from below, every octant through the origin region.
    std::uint32_t s = 12345;
    auto rnd = [&] {
        s = s * 1664525u + 1013904223u;
        return float(s >> 8) * 0x1p-24f;
    };
    for (int i = 0; i < 2000; ++i) {
        const Vec3 o{20.0f * rnd() - 5.0f, 20.0f * rnd() - 5.0f, 40.0f * rnd() - 20.0f};
        // A point inside small triangle k (mostly a hit, unless another is in the way).
        const int k = int(8.0f * rnd()) & 7;
        float u = rnd(), v = rnd();
        if (u + v > 1.0f) {
            u = 1.0f - u;
            v = 1.0f - v;
        }
        const Vec3 t{1.0f + float(k) + 0.9f * u, 1.0f + 0.5f * float(k) + 0.9f * v, 1.0f};
        Vec3 d = t - o;
        if (i % 4 == 3) d = Vec3{rnd() - 0.5f, rnd() - 0.5f, rnd() - 0.5f};
        rays.push_back(Ray{o, 0.0f, d, kInf});
    }
    // Onto the corner clusters of extreme_mesh(), when present.
    if (mesh.bounds().hi.x > 1e38f) {
        for (int k = 0; k < 8; ++k) {
            const Vec3 c = corner(k);
            const float sx = c.x > 0 ? -1.0f : 1.0f, sy = c.y > 0 ? -1.0f : 1.0f;
            const float dz = c.z > 0 ? -1.0f : 1.0f;  // from inside the cube towards the corner plane
            for (int i = 0; i < 40; ++i)
                for (int j = 0; j < 10; ++j) {
                    const Vec3 o{c.x + sx * 1e36f * (0.5f + float(i)), c.y + sy * 1e36f * (0.5f + float(j)),
                                 c.z - dz * 2e37f};
                    rays.push_back(Ray{o, 0.0f, {0.01f * float(i % 3), -0.01f * float(j % 3), dz}, kInf});
                }
        }
    }
    return rays;
}

void write_obj(const std::filesystem::path& file, const Mesh& mesh) {
    std::ofstream out(file);
    char buf[128];
    for (const Vec3& p : mesh.positions) {
        std::snprintf(buf, sizeof buf, "v %.9g %.9g %.9g\n", double(p.x), double(p.y), double(p.z));
        out << buf;
    }
    for (const auto& t : mesh.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
    if (!out) throw std::runtime_error("cannot write " + file.string());
}

}  // namespace test
