// Watertightness on a closed icosphere (built here: a subdivided icosahedron),
// rays from the centre aimed at every vertex and every edge midpoint, with the
// mesh and origin translated by 0, 1e3, 1e5, 1e7 (in double, rounded to float).
// Watertight (every ISA): zero misses. Moller-Trumbore: leaks counted, reported.
#include <array>
#include <cmath>
#include <iostream>
#include <map>
#include <utility>
#include <vector>

#include "kernel_test_util.h"
#include "support/sanitizer.h"

namespace simdbvh {
namespace {

struct DMesh {
    std::vector<std::array<double, 3>> pos;
    std::vector<std::array<std::uint32_t, 3>> tri;
};

// Icosahedron subdivided `levels` times, vertices on the sphere of radius `radius`.
DMesh icosphere(int levels, double radius) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    DMesh m;
    m.pos = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
             {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    m.tri = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    auto project = [&](std::array<double, 3> p) {
        const double l = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        return std::array<double, 3>{p[0] / l, p[1] / l, p[2] / l};
    };
    for (auto& p : m.pos) p = project(p);
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            const auto& pa = m.pos[a];
            const auto& pb = m.pos[b];
            m.pos.push_back(project({pa[0] + pb[0], pa[1] + pb[1], pa[2] + pb[2]}));
            return mid[key] = std::uint32_t(m.pos.size() - 1);
        };
        std::vector<std::array<std::uint32_t, 3>> next;
        for (const auto& f : m.tri) {
            const std::uint32_t a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
            next.push_back({f[0], a, c});
            next.push_back({f[1], b, a});
            next.push_back({f[2], c, b});
            next.push_back({a, b, c});
        }
        m.tri = std::move(next);
    }
    for (auto& p : m.pos)
        for (double& x : p) x *= radius;
    return m;
}

Vec3 to_float(const std::array<double, 3>& p, double offset) {
    return {float(p[0] + offset), float(p[1] + offset), float(p[2] + offset)};
}

class Watertight : public testing::TestWithParam<Isa> {};

TEST_P(Watertight, IcosphereFromTheCentreNoLeaks) {
    const Isa isa = GetParam();
    SIMDBVH_SKIP_IF_UNSUPPORTED(isa);
    // Radius 100: at offset 1e7 the float spacing is 1, so the sphere stays a
    // closed surface around the centre (edges ~5 units long at 4 levels).
    const DMesh mesh = icosphere(4, 100.0);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    {
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> seen;
        for (const auto& f : mesh.tri)
            for (int k = 0; k < 3; ++k) {
                const auto e = std::minmax(f[k], f[(k + 1) % 3]);
                if (seen[e]++ == 0) edges.push_back(e);
            }
    }
    ASSERT_EQ(mesh.tri.size(), 5120u);
    ASSERT_EQ(edges.size(), 7680u);
    for (double offset : {0.0, 1e3, 1e5, 1e7}) {
        std::vector<kernels::Tri1> tris;
        for (std::size_t i = 0; i < mesh.tri.size(); ++i) {
            const auto& f = mesh.tri[i];
            tris.push_back({to_float(mesh.pos[f[0]], offset), to_float(mesh.pos[f[1]], offset),
                            to_float(mesh.pos[f[2]], offset), std::uint32_t(i)});
        }
        const std::vector<Tri8> blocks = test::pack_tri8(tris);
        const Vec3 org = to_float({0, 0, 0}, offset);
        // (every vertex and edge; every 8th under a sanitizer: support/sanitizer.h)
        std::vector<Ray> rays;
        for (std::size_t v = 0; v < mesh.pos.size(); v += ::test::kSanitizerStride) {
            const Vec3 target = to_float(mesh.pos[v], offset);
            rays.push_back(Ray{org, 0, target - org, std::numeric_limits<float>::infinity()});
        }
        const std::size_t n_vertex_rays = rays.size();
        for (std::size_t e = 0; e < edges.size(); e += ::test::kSanitizerStride) {
            const auto [a, b] = edges[e];
            const auto& pa = mesh.pos[a];
            const auto& pb = mesh.pos[b];
            const Vec3 target = to_float({(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2, (pa[2] + pb[2]) / 2}, offset);
            rays.push_back(Ray{org, 0, target - org, std::numeric_limits<float>::infinity()});
        }
        for (TriangleTest test : {TriangleTest::watertight, TriangleTest::moller}) {
            std::vector<Hit> hits(rays.size());
            kernels::intersect_tri8(rays, blocks, test, hits, isa);
            ASSERT_EQ(kernels::last_isa_used(), isa);
            std::size_t leak_v = 0, leak_e = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) {
                if (hits[i].hit()) {
                    ASSERT_FALSE(std::isnan(hits[i].t) || std::isnan(hits[i].u) || std::isnan(hits[i].v));
                    continue;
                }
                (i < n_vertex_rays ? leak_v : leak_e)++;
            }
            const std::string tag = std::string(test == TriangleTest::watertight ? "watertight" : "moller") +
                                    "_offset_" + std::to_string(static_cast<long long>(offset));
            RecordProperty(tag + "_vertex_leaks", static_cast<int>(leak_v));
            RecordProperty(tag + "_edge_leaks", static_cast<int>(leak_e));
            std::cout << "[" << name(isa) << "] " << tag << ": " << leak_v << "/" << n_vertex_rays
                      << " vertex rays and " << leak_e << "/" << rays.size() - n_vertex_rays << " edge rays leak\n";
            if (test == TriangleTest::watertight) {
                EXPECT_EQ(leak_v, 0u) << "offset " << offset;
                EXPECT_EQ(leak_e, 0u) << "offset " << offset;
            }
        }
    }
}

INSTANTIATE_TEST_SUITE_P(AllIsas, Watertight, testing::ValuesIn(kAllIsas), test::isa_param_name);

}  // namespace
}  // namespace simdbvh
