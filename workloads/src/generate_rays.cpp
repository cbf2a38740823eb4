// generate_rays: the one scene function that needs a BVH (diffuse rays trace
// their primary rays first). Kept apart so the rest links without bvh2.
#include <cmath>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/workloads/rays.h"

namespace simdbvh::workloads {

namespace {
// A square-ish image of at least `count` pixels: width = ceil(sqrt(count)).
void image_size(std::size_t count, int& w, int& h) {
    std::size_t s = std::size_t(std::sqrt(double(count)));
    while (s * s < count) ++s;
    while (s > 1 && (s - 1) * (s - 1) >= count) --s;
    w = int(s ? s : 1);
    h = int((count + std::size_t(w) - 1) / std::size_t(w));
    if (h < 1) h = 1;
}
}  // namespace

std::vector<Ray> generate_rays(const Mesh& mesh, RayKind kind, std::size_t count, std::uint64_t seed) {
    switch (kind) {
    case RayKind::incoherent: return incoherent_rays(mesh.bounds(), count, seed);
    case RayKind::lidar: return lidar_rays(mesh.bounds(), count);
    default: break;
    }
    int w = 1, h = 1;
    image_size(count, w, h);
    std::vector<Ray> rays = primary_rays(default_camera(mesh.bounds(), w, h));
    rays.resize(count);
    if (kind == RayKind::primary) return rays;
    const Bvh2 bvh = Bvh2::build(mesh);
    std::vector<Hit> hits(rays.size());
    intersect(bvh, rays, hits);
    switch (kind) {
    case RayKind::diffuse: return diffuse_rays(mesh, rays, hits, count, seed);
    case RayKind::diffuse_shuffled: return shuffled(diffuse_rays(mesh, rays, hits, count, seed), seed);
    case RayKind::shadow: return shadow_rays(mesh, rays, hits, count, seed, false);
    case RayKind::area_shadow: return shadow_rays(mesh, rays, hits, count, seed, true);
    case RayKind::ao: return ao_rays(mesh, rays, hits, count, seed);
    default: return rays;
    }
}

}  // namespace simdbvh::workloads
