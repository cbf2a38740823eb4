// Geometric normals of scene hits and the scene's bounded extent (pictures).
#include <cmath>
#include <optional>
#include <vector>

#include "simdbvh/scene/scene.h"
#include "geometry_bounds.h"

namespace simdbvh {

namespace {

Vec3 object_normal(const Geometry& g, const Ray& obj, const SceneHit& h) {
    const Vec3 p = obj.org + obj.dir * h.t;
    if (const Mesh* m = std::get_if<Mesh>(&g)) {
        const Vec3 a = m->vertex(h.prim, 0), b = m->vertex(h.prim, 1), c = m->vertex(h.prim, 2);
        return cross(b - a, c - a);
    }
    if (const SphereSet* s = std::get_if<SphereSet>(&g)) return p - s->spheres[h.prim].center;
    const Aabb& box = std::get<BoxSet>(g).boxes[h.prim];
    int axis = 0;
    float best = INFINITY, sign = 1.0f;
    for (int a = 0; a < 3; ++a)
        for (float side : {-1.0f, 1.0f}) {
            const float d = std::fabs(p[a] - (side < 0 ? box.lo[a] : box.hi[a]));
            if (d < best) {
                best = d;
                axis = a;
                sign = side;
            }
        }
    Vec3 n{};
    n[axis] = sign;
    return n;
}

}  // namespace

Vec3 hit_normal(const SceneDesc& scene, const Ray& world, const SceneHit& h) {
    if (!h.hit()) return {};
    if (h.geom == kNoGeometry) return scene.planes.at(h.prim).normal;
    const Instance& in = scene.instances.at(h.inst);
    const Affine3 inv = invert(in.transform).inv;
    const Vec3 n = object_normal(scene.geometries.at(h.geom), object_ray(inv, world), h);
    // World normal = A^-T n: column c of A^-1 dotted with n.
    Vec3 w;
    for (int c = 0; c < 3; ++c) w[c] = inv.m[0][c] * n.x + inv.m[1][c] * n.y + inv.m[2][c] * n.z;
    return w;
}

// Each geometry's bounds are computed once, however many instances use it
// (instances-1000: one walk over the dragon's vertices, not a thousand, which
// took seconds and 43% of the scene bench's process).
Aabb world_bounds(const SceneDesc& scene) {
    std::vector<std::optional<Aabb>> of_geometry(scene.geometries.size());
    Aabb b;
    for (const Instance& in : scene.instances) {
        std::optional<Aabb>& g = of_geometry.at(in.geometry);
        if (!g) g = geometry_bounds(scene.geometries[in.geometry]);
        b.grow(transform_box(in.transform, *g));
    }
    return b;
}

}  // namespace simdbvh
