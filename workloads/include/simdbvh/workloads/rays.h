#pragma once
// Deterministic, seeded ray generation (the ray and hit files: simdbvh/io/ray_files.h).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <span>
#include <string_view>
#include <vector>

#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::workloads {

// What renderers and simulators send. primary, incoherent and diffuse are the bench's default rows; the others
// are the distributions it was not tuned on: diffuse bounces in a random order, shadow rays from the primary
// hits toward a point light and toward points of an area light (finite tmax, any hit is the query),
// ambient-occlusion rays (cosine bounces with a short tmax) and a LiDAR spin from a point inside the bounds.
enum class RayKind : std::uint8_t { primary, incoherent, diffuse, diffuse_shuffled, shadow, area_shadow, ao, lidar };
inline constexpr RayKind kRayKinds[] = {
    RayKind::primary, RayKind::incoherent,  RayKind::diffuse, RayKind::diffuse_shuffled,
    RayKind::shadow,  RayKind::area_shadow, RayKind::ao,      RayKind::lidar};
std::string_view name(RayKind k);
std::optional<RayKind> parse_ray_kind(std::string_view s);
// "primary, incoherent, ...": every kind's name, for messages.
std::string ray_kind_names();
// True for the kinds made from the primary rays' closest hits (diffuse, shadow, AO).
bool needs_primary_hits(RayKind k);

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
// The bounces in a seeded random order (Fisher-Yates, the library's own PRNG): the same rays, no coherence.
std::vector<Ray> shuffled(std::vector<Ray> rays, std::uint64_t seed);
// From each primary hit (origin offset along the normal, as diffuse_rays) toward the point light of
// light_position(bounds), or toward a point drawn uniformly on the square area light of side the bounds'
// half-diagonal centred there (area = true); tmax stops short of the light.
Vec3 light_position(const Aabb& bounds);
std::vector<Ray> shadow_rays(const Mesh& mesh, std::span<const Ray> primary, std::span<const Hit> hits,
                             std::size_t count, std::uint64_t seed, bool area);
// Cosine-weighted bounces from the primary hits with tmax a tenth of the bounds' half-diagonal.
std::vector<Ray> ao_rays(const Mesh& mesh, std::span<const Ray> primary, std::span<const Hit> hits, std::size_t count,
                         std::uint64_t seed);
// A spinning 64-beam LiDAR at the bounds' centre (beams from -25 to +15 degrees of elevation about +y), in
// firing order: every beam of one azimuth step, then the next step, ceil(count / 64) steps per revolution.
std::vector<Ray> lidar_rays(const Aabb& bounds, std::size_t count);
// Convenience: builds a BVH2 internally for the kinds made from primary hits.
std::vector<Ray> generate_rays(const Mesh& mesh, RayKind kind, std::size_t count, std::uint64_t seed);

}  // namespace simdbvh::workloads
