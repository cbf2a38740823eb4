#pragma once
// Deterministic, seeded ray generation (the ray and hit files: simdbvh/io/ray_files.h).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::workloads {

enum class RayKind : std::uint8_t { primary, incoherent, diffuse };
std::string_view name(RayKind k);
std::optional<RayKind> parse_ray_kind(std::string_view s);

struct Camera {                    // pinhole, looking at the bounds' centre from a 3/4 view
    Vec3 eye, forward, right, up;  // right and up scaled to the half-extent of the image plane at distance 1
    int width = 0, height = 0;
};
Camera default_camera(const Aabb& bounds, int width, int height);
// One ray per pixel, row-major from the top-left.
std::vector<Ray> primary_rays(const Camera& cam);

// count rays of a kind. primary: a square-ish image with count pixels;
// incoherent: origins on a sphere around the bounds aimed at random interior
// points; diffuse: cosine-weighted bounces from primary hits (origin offset
// along the normal), which needs closest hits: `hits` of the primary rays.
std::vector<Ray> incoherent_rays(const Aabb& bounds, std::size_t count, std::uint64_t seed);
// Origins uniform in the box, directions uniform on the sphere (std::mt19937_64
// from `seed`): the incoherent rays of simdbvh bench --scene, which start among
// the objects.
std::vector<Ray> interior_rays(const Aabb& bounds, std::size_t count, std::uint64_t seed);
std::vector<Ray> diffuse_rays(const Mesh& mesh, std::span<const Ray> primary, std::span<const Hit> hits,
                              std::size_t count, std::uint64_t seed);
// Convenience: builds a BVH2 internally for diffuse rays.
std::vector<Ray> generate_rays(const Mesh& mesh, RayKind kind, std::size_t count, std::uint64_t seed);

}  // namespace simdbvh::workloads
