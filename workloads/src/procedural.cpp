// Procedural scenes: icosphere, random triangle soup, fractal terrain with
// clustered objects. Deterministic: own PRNG, float math with + - * / sqrt.
#include <cmath>
#include <unordered_map>

#include "rng.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh::workloads {

using detail::Rng;

namespace {

// Appends an icosphere to `mesh` (shared vertices; counter-clockwise seen from outside).
void append_icosphere(Mesh& mesh, int level, float radius, Vec3 center) {
    const float t = 1.6180339887498949f;  // golden ratio
    const Vec3 base[12] = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    static const std::uint32_t faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                               {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                               {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                               {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    std::vector<Vec3> pos;
    pos.reserve(10 * (std::size_t(1) << (2 * level)) + 2);
    for (const Vec3& v : base) pos.push_back(normalize(v));
    std::vector<Triangle> tris;
    for (const auto& f : faces) tris.push_back(Triangle{f[0], f[1], f[2]});
    std::unordered_map<std::uint64_t, std::uint32_t> mid;
    for (int l = 0; l < level; ++l) {
        mid.clear();
        mid.reserve(tris.size() * 2);
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const std::uint64_t key = a < b ? (std::uint64_t(a) << 32 | b) : (std::uint64_t(b) << 32 | a);
            auto [it, inserted] = mid.try_emplace(key, std::uint32_t(pos.size()));
            if (inserted) pos.push_back(normalize((pos[a] + pos[b]) * 0.5f));
            return it->second;
        };
        std::vector<Triangle> next;
        next.reserve(tris.size() * 4);
        for (const Triangle& tr : tris) {
            const std::uint32_t a = midpoint(tr[0], tr[1]), b = midpoint(tr[1], tr[2]), c = midpoint(tr[2], tr[0]);
            next.push_back(Triangle{tr[0], a, c});
            next.push_back(Triangle{tr[1], b, a});
            next.push_back(Triangle{tr[2], c, b});
            next.push_back(Triangle{a, b, c});
        }
        tris.swap(next);
    }
    const auto off = std::uint32_t(mesh.positions.size());
    for (const Vec3& p : pos) mesh.positions.push_back(center + p * radius);
    for (const Triangle& tr : tris) mesh.triangles.push_back(Triangle{tr[0] + off, tr[1] + off, tr[2] + off});
}

// An axis-aligned box, 12 triangles, outward counter-clockwise.
void append_box(Mesh& mesh, Vec3 lo, Vec3 hi) {
    const auto o = std::uint32_t(mesh.positions.size());
    for (int i = 0; i < 8; ++i)
        mesh.positions.push_back(Vec3{(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    static const std::uint32_t q[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                          {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& f : q) {
        mesh.triangles.push_back(Triangle{o + f[0], o + f[1], o + f[2]});
        mesh.triangles.push_back(Triangle{o + f[0], o + f[2], o + f[3]});
    }
}

// Value noise on an integer lattice, smoothstep-interpolated, in [0, 1).
float value_noise(float x, float y, std::uint64_t seed) {
    const float fx = std::floor(x), fy = std::floor(y);
    const auto ix = std::int64_t(fx), iy = std::int64_t(fy);
    float tx = x - fx, ty = y - fy;
    tx = tx * tx * (3.0f - 2.0f * tx);
    ty = ty * ty * (3.0f - 2.0f * ty);
    auto h = [&](std::int64_t a, std::int64_t b) { return detail::hash01(std::uint64_t(a), std::uint64_t(b), seed); };
    const float a = h(ix, iy), b = h(ix + 1, iy), c = h(ix, iy + 1), d = h(ix + 1, iy + 1);
    const float ab = a + (b - a) * tx, cd = c + (d - c) * tx;
    return ab + (cd - ab) * ty;
}

// fBm: 7 octaves of value noise, lacunarity 2, gain 0.5; about [-1, 1].
float fbm(float x, float y, std::uint64_t seed) {
    float sum = 0.0f, amp = 1.0f, freq = 1.0f;
    for (int o = 0; o < 7; ++o) {
        sum += amp * (2.0f * value_noise(x * freq, y * freq, seed + std::uint64_t(o)) - 1.0f);
        amp *= 0.5f;
        freq *= 2.0f;
    }
    return sum;
}

}  // namespace

Mesh icosphere(int level, float radius, Vec3 center) {
    if (level < 0 || level > 11) throw Error("icosphere level " + std::to_string(level) + " out of range 0..11");
    Mesh mesh;
    mesh.positions.reserve(10 * (std::size_t(1) << (2 * level)) + 2);
    mesh.triangles.reserve(20 * (std::size_t(1) << (2 * level)));
    append_icosphere(mesh, level, radius, center);
    return mesh;
}

Mesh random_soup(std::size_t triangles, std::uint64_t seed) {
    // 3 new vertices per triangle: 3 n must fit the uint32 vertex indices (checked before allocating).
    if (triangles > 0xFFFFFFFFull / 3)
        throw Error("soup of " + std::to_string(triangles) + " triangles: its " +
                    std::to_string(3 * std::uint64_t(triangles)) + " vertices do not fit 32-bit indices (max " +
                    std::to_string(0xFFFFFFFFull / 3) + " triangles)");
    Rng rng(seed);
    Mesh mesh;
    mesh.positions.reserve(triangles * 3);
    mesh.triangles.reserve(triangles);
    // Triangle size ~ the mean spacing of n points in the unit cube.
    const float s = triangles ? std::fmin(0.5f, 1.5f / std::cbrt(float(triangles))) : 0.5f;
    for (std::size_t i = 0; i < triangles; ++i) {
        const Vec3 c{rng.uniform(0.5f * s, 1.0f - 0.5f * s), rng.uniform(0.5f * s, 1.0f - 0.5f * s),
                     rng.uniform(0.5f * s, 1.0f - 0.5f * s)};
        const auto b = std::uint32_t(mesh.positions.size());
        for (int k = 0; k < 3; ++k)
            mesh.positions.push_back(
                c + Vec3{rng.uniform(-0.5f, 0.5f), rng.uniform(-0.5f, 0.5f), rng.uniform(-0.5f, 0.5f)} * s);
        mesh.triangles.push_back(Triangle{b, b + 1, b + 2});
    }
    return mesh;
}

Mesh terrain(std::size_t min_triangles, std::uint64_t seed) {
    if (min_triangles >= kMaxTriangles / 2)
        throw Error("terrain of " + std::to_string(min_triangles) + " triangles > max");
    constexpr float kSize = 100.0f, kHeight = 12.0f, kFeature = 1.0f / 16.0f;  // noise cycles per unit
    // 85% of the budget to the heightfield (2 triangles per cell), the rest to objects.
    std::size_t g = 2;
    while (2 * g * g < min_triangles * 85 / 100) ++g;
    Mesh mesh;
    const std::size_t objects_budget = min_triangles > 2 * g * g ? min_triangles - 2 * g * g : 0;
    mesh.positions.reserve((g + 1) * (g + 1) + objects_budget);
    mesh.triangles.reserve(2 * g * g + objects_budget + 400);
    auto height = [&](float x, float z) { return kHeight * fbm(x * kFeature * 4.0f, z * kFeature * 4.0f, seed); };
    const float step = kSize / float(g);
    for (std::size_t j = 0; j <= g; ++j)
        for (std::size_t i = 0; i <= g; ++i) {
            const float x = float(i) * step, z = float(j) * step;
            mesh.positions.push_back(Vec3{x, height(x, z), z});
        }
    const auto row = std::uint32_t(g + 1);
    for (std::uint32_t j = 0; j < g; ++j)
        for (std::uint32_t i = 0; i < g; ++i) {  // +y facing: counter-clockwise seen from above
            const std::uint32_t a = j * row + i, b = a + 1, c = a + row, d = c + 1;
            mesh.triangles.push_back(Triangle{a, c, b});
            mesh.triangles.push_back(Triangle{b, c, d});
        }
    // Objects in a few clusters (uneven density): icospheres of levels 1..3 and boxes.
    Rng rng(seed * 0x2545F4914F6CDD1Dull + 7);
    constexpr int kClusters = 7;
    Vec3 centers[kClusters];
    float spread[kClusters];
    for (int k = 0; k < kClusters; ++k) {
        centers[k] = Vec3{rng.uniform(10.0f, 90.0f), 0.0f, rng.uniform(10.0f, 90.0f)};
        spread[k] = rng.uniform(1.0f, 8.0f);
    }
    while (mesh.triangles.size() < min_triangles) {
        const int k = int(rng.below(kClusters * (kClusters + 1) / 2));
        int c = 0, acc = 1;  // cluster c chosen with weight c + 1
        while (k >= acc) acc += ++c + 1;
        // Roughly Gaussian offsets: sum of three uniforms.
        const float dx = (rng.uniform() + rng.uniform() + rng.uniform() - 1.5f) * spread[c];
        const float dz = (rng.uniform() + rng.uniform() + rng.uniform() - 1.5f) * spread[c];
        const float x = std::fmin(kSize, std::fmax(0.0f, centers[c].x + dx));
        const float z = std::fmin(kSize, std::fmax(0.0f, centers[c].z + dz));
        const float r = rng.uniform(0.15f, 1.2f);
        const float y = height(x, z);
        if (rng.uniform() < 0.6f) {
            append_icosphere(mesh, 1 + int(rng.below(3)), r, Vec3{x, y + r * 0.7f, z});
        } else {
            const float hy = r * rng.uniform(0.5f, 3.0f);
            append_box(mesh, Vec3{x - r, y - 0.2f * r, z - r * 0.7f}, Vec3{x + r, y + hy, z + r * 0.7f});
        }
    }
    return mesh;
}

}  // namespace simdbvh::workloads
