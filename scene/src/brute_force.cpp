// The scene reference: no hierarchy at any level. Every instance sees the
// world ray through object_ray() with the same float inverse as the build,
// every primitive of its geometry is tested (meshes: bvh2's brute force), and
// the planes are tested with the same function as the traversal.
#include <variant>

#include "simdbvh/kernels/error.h"
#include "scene_trace-inl.h"

namespace simdbvh {

namespace {

template <bool kAnyHit, class Prim>
Hit brute_shapes(const std::vector<Prim>& prims, const Ray& ray) {
    const PreparedRay r = prepare(ray);
    if (!r.valid) return {};
    Hit best;
    best.t = r.tmax;
    const scene::detail::ShapeLeaf<Prim> leaf{prims.data(), nullptr};
    if constexpr (kAnyHit) leaf.any(r, 0, std::uint32_t(prims.size()), best, nullptr);
    else leaf.closest(r, 0, std::uint32_t(prims.size()), best, nullptr);
    return best.hit() ? to_caller(r, best) : Hit{};
}

template <bool kAnyHit>
Hit brute_geometry(const Geometry& g, const Ray& obj) {
    if (const Mesh* m = std::get_if<Mesh>(&g))
        return kAnyHit ? brute_force_occluded(*m, obj) : brute_force_intersect(*m, obj);
    if (const SphereSet* s = std::get_if<SphereSet>(&g)) return brute_shapes<kAnyHit>(s->spheres, obj);
    return brute_shapes<kAnyHit>(std::get<BoxSet>(g).boxes, obj);
}

template <bool kAnyHit>
SceneHit brute(const SceneDesc& scene, const std::vector<Affine3>& inv, const Ray& ray) {
    const PreparedRay pr = prepare(ray);
    if (!pr.valid) return {};
    const std::uint32_t ni = std::uint32_t(scene.instances.size());
    SceneHit best = scene::detail::trace_planes<kAnyHit>(scene.planes, pr, ni);
    if (kAnyHit && best.hit()) return best;
    for (std::uint32_t i = 0; i < ni; ++i) {
        const std::uint32_t g = scene.instances[i].geometry;
        const Hit h = brute_geometry<kAnyHit>(scene.geometries[g], object_ray(inv[i], ray));
        if (h.hit() && closer(h.t, i, h.prim, best)) {
            best = SceneHit{h.t, h.u, h.v, h.prim, g, i};
            if (kAnyHit) return best;
        }
    }
    return best;
}

template <bool kAnyHit>
void brute_span(const SceneDesc& scene, std::span<const Ray> rays, std::span<SceneHit> hits) {
    simdbvh::detail::check_size(hits.size(), rays.size(), "hits");
    validate(scene);
    std::vector<Affine3> inv;
    for (const Instance& in : scene.instances) inv.push_back(invert(in.transform).inv);
    for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = brute<kAnyHit>(scene, inv, rays[i]);
}

}  // namespace

void brute_force_intersect(const SceneDesc& scene, std::span<const Ray> rays, std::span<SceneHit> hits) {
    brute_span<false>(scene, rays, hits);
}
void brute_force_occluded(const SceneDesc& scene, std::span<const Ray> rays, std::span<SceneHit> hits) {
    brute_span<true>(scene, rays, hits);
}

}  // namespace simdbvh
