// Built-in scene descriptions: instances-N, spheres-N, room.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "simdbvh/kernels/error.h"
#include "simdbvh/workloads/scene_desc.h"
#include "simdbvh/workloads/scenes.h"
#include "rng.h"
#include "simdbvh/io/internal/text.h"

namespace simdbvh::workloads {

namespace {

Aabb mesh_bounds(const Mesh& m) {
    Aabb b;
    for (const Vec3& p : m.positions) b.grow(p);
    return b;
}

// "base-N" with N a positive decimal number.
std::optional<std::size_t> count_of(std::string_view s, std::string_view base) {
    if (s.size() <= base.size() + 1 || s.substr(0, base.size()) != base || s[base.size()] != '-') return std::nullopt;
    std::size_t v = 0;
    const char* b = s.data() + base.size() + 1;
    auto [p, ec] = std::from_chars(b, s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size() || v == 0) return std::nullopt;
    return v;
}

// Placed on the floor (y = 0) at `pos`, scaled to `height`, rotated about y.
Affine3 stand(const Mesh& m, Vec3 pos, float height, double degrees) {
    const Aabb b = mesh_bounds(m);
    const float s = height / (b.hi.y - b.lo.y);
    const Vec3 base{0.5f * (b.lo.x + b.hi.x), b.lo.y, 0.5f * (b.lo.z + b.hi.z)};
    return Affine3::translation(pos) * Affine3::rotation({0, 1, 0}, degrees * std::numbers::pi / 180.0) *
           Affine3::scaling(s) * Affine3::translation(Vec3{} - base);
}

}  // namespace

SceneDesc instances_scene(const Mesh& mesh, std::size_t n, std::uint64_t seed) {
    SceneDesc s;
    const Aabb b = mesh_bounds(mesh);
    const float diag = length(b.extent());
    const Vec3 c = b.center();
    s.geometries.push_back(mesh);
    detail::Rng rng(seed);
    const float half = 0.75f * diag * std::cbrt(float(n));
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 axis{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
        const double angle = rng.uniform(0.0f, 2.0f * float(std::numbers::pi));
        const float scale = rng.uniform(0.5f, 1.5f);
        const Vec3 pos{rng.uniform(-half, half), rng.uniform(-half, half), rng.uniform(-half, half)};
        const Vec3 safe_axis = dot(axis, axis) > 1e-6f ? axis : Vec3{0, 1, 0};
        s.instances.push_back({0, Affine3::translation(pos) * Affine3::rotation(safe_axis, angle) *
                                      Affine3::scaling(scale) * Affine3::translation(Vec3{} - c)});
    }
    return s;
}

SceneDesc spheres_scene(std::size_t n, std::uint64_t seed) {
    SceneDesc s;
    SphereSet set;
    detail::Rng rng(seed);
    const float spacing = 1.0f / std::cbrt(float(n));
    for (std::size_t i = 0; i < n; ++i)
        set.spheres.push_back({{rng.uniform(), rng.uniform(), rng.uniform()}, spacing * rng.uniform(0.1f, 0.5f)});
    s.geometries.push_back(std::move(set));
    s.instances.push_back({0, Affine3{}});
    return s;
}

SceneDesc room_scene() {
    SceneDesc s;
    s.planes = {{{0, 0, 0}, {0, 1, 0}}, {{0, 0, -4}, {0, 0, 1}}, {{-4, 0, 0}, {1, 0, 0}}, {{4, 0, 0}, {-1, 0, 0}}};
    const Mesh bunny = load_scene("bunny"), teapot = load_scene("teapot");
    s.geometries.push_back(bunny);   // 0
    s.geometries.push_back(teapot);  // 1
    s.geometries.push_back(
        BoxSet{{Aabb{{-3.5f, 0, -3.5f}, {-2.5f, 1, -2.5f}}, Aabb{{2.2f, 0, -3.6f}, {3.6f, 0.6f, -2.2f}},
                Aabb{{2.6f, 0.6f, -3.2f}, {3.2f, 1.4f, -2.6f}}}});  // 2
    s.geometries.push_back(SphereSet{{Sphere{{-1.0f, 0.5f, 1.5f}, 0.5f}, Sphere{{2.5f, 0.35f, 1.0f}, 0.35f},
                                      Sphere{{0.0f, 2.5f, -3.0f}, 0.6f}}});  // 3
    s.instances.push_back({0, stand(bunny, {-1.5f, 0, -1.0f}, 1.5f, 0)});
    s.instances.push_back({1, stand(teapot, {1.5f, 0, -1.0f}, 1.0f, 30)});
    s.instances.push_back({1, stand(teapot, {0.5f, 0, 1.5f}, 0.7f, 120)});
    s.instances.push_back({2, Affine3{}});
    s.instances.push_back({3, Affine3{}});
    return s;
}

// A family's name ("instances-" or "spheres-" and anything without a '/' or a
// '.', which no mesh file's path lacks) is a built-in name whatever follows the
// dash, so that a bad count gets the family's message, not a mesh loader's.
bool is_builtin_scene(std::string_view name) {
    if (name == "room") return true;
    if (name.find_first_of("/.") != std::string_view::npos) return false;
    return name.starts_with("instances-") || name.starts_with("spheres-");
}

SceneDesc builtin_scene(std::string_view name) {
    constexpr std::size_t kMaxCount = 10'000'000;
    if (name == "room") return room_scene();
    for (std::string_view base : {"instances", "spheres"}) {
        if (!name.starts_with(base) || name.size() == base.size() || name[base.size()] != '-') continue;
        const auto n = count_of(name, base);
        if (!n || *n > kMaxCount)
            throw Error("scene " + io::detail::quote(name) + ": the count N of " + std::string(base) +
                        "-N must be a whole number from 1 to 10000000");
        if (base == "instances") return instances_scene(load_scene("dragon"), *n);
        return spheres_scene(*n);
    }
    throw Error("unknown built-in scene " + io::detail::quote(name) + " (instances-N, spheres-N, room)");
}

SceneDesc load_scene_desc(std::string_view name) {
    if (is_builtin_scene(name)) return builtin_scene(name);
    const std::filesystem::path p{std::string(name)};
    if (p.extension() == ".json") return load_scene_json(p);
    SceneDesc s;
    s.geometries.push_back(load_scene(name));
    s.instances.push_back({0, Affine3{}});
    return s;
}

}  // namespace simdbvh::workloads
