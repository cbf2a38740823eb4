// The box around a geometry's primitives (geometry_bounds.h).
#include "geometry_bounds.h"

#include "simdbvh/scene/shapes.h"

namespace simdbvh {

Aabb geometry_bounds(const Geometry& g) {
    Aabb b;
    if (const Mesh* m = std::get_if<Mesh>(&g)) {
        for (const Triangle& t : m->triangles)
            for (int k = 0; k < 3; ++k) b.grow(m->positions[t[k]]);
    } else if (const SphereSet* s = std::get_if<SphereSet>(&g)) {
        for (const Sphere& sp : s->spheres) b.grow(sphere_bounds(sp));
    } else {
        for (const Aabb& x : std::get<BoxSet>(g).boxes) b.grow(x);
    }
    return b;
}

}  // namespace simdbvh
