// Scene validation: every error names the offending item by its path.
#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include "simdbvh/kernels/error.h"
#include "simdbvh/scene/scene.h"
#include "simdbvh/scene/shapes.h"
#include "simdbvh/scene/transform.h"
#include "geometry_bounds.h"

namespace simdbvh {

namespace {

std::string at(const char* list, std::size_t i) { return std::string(list) + "[" + std::to_string(i) + "]"; }

bool finite_box(const Aabb& b) { return is_finite(b.lo) && is_finite(b.hi); }

void check_finite(Vec3 v, const std::string& path) {
    if (!is_finite(v)) throw Error(path + ": not finite");
}

// Checks geometry g and returns the box its bottom tree bounds it by (mesh
// vertices, padded sphere and box bounds), finite once the checks pass.
Aabb validate_geometry(const Geometry& g, const std::string& path) {
    Aabb bounds;
    if (const Mesh* m = std::get_if<Mesh>(&g)) {
        try {
            validate(*m);
        } catch (const Error& e) {
            throw Error(path + ".mesh: " + e.what());
        }
        bounds = geometry_bounds(g);
    } else if (const SphereSet* s = std::get_if<SphereSet>(&g)) {
        for (std::size_t i = 0; i < s->spheres.size(); ++i) {
            const std::string p = path + "." + at("spheres", i);
            check_finite(s->spheres[i].center, p + ".center");
            if (!std::isfinite(s->spheres[i].radius)) throw Error(p + ".radius: not finite");
            if (s->spheres[i].radius < 0.0f) throw Error(p + ".radius: negative");
            const Aabb b = sphere_bounds(s->spheres[i]);
            if (!finite_box(b)) throw Error(p + ": its bounds (center +- radius) exceed the float range");
            bounds.grow(b);
        }
    } else {
        const BoxSet& b = std::get<BoxSet>(g);
        for (std::size_t i = 0; i < b.boxes.size(); ++i) {
            const std::string p = path + "." + at("boxes", i);
            check_finite(b.boxes[i].lo, p + ".min");
            check_finite(b.boxes[i].hi, p + ".max");
            if (b.boxes[i].is_empty()) throw Error(p + ": min > max");
            const Aabb padded = padded_box(b.boxes[i]);
            if (!finite_box(padded)) throw Error(p + ": its padded bounds exceed the float range");
            bounds.grow(padded);
        }
    }
    return bounds;
}

}  // namespace

void validate(const SceneDesc& scene) {
    std::vector<Aabb> bounds;
    for (std::size_t i = 0; i < scene.geometries.size(); ++i)
        bounds.push_back(validate_geometry(scene.geometries[i], at("geometries", i)));
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& in = scene.instances[i];
        if (in.geometry >= scene.geometries.size())
            throw Error(at("instances", i) + ".geometry: no geometry " + std::to_string(in.geometry));
        try {
            invert(in.transform);
        } catch (const Error& e) {
            throw Error(at("instances", i) + "." + e.what());
        }
        // The world box must be finite floats: it is a top-level box (an
        // instance taken beyond the float range has a world box of +-inf or
        // NaN, which no hierarchy can order, and world points no float holds).
        const Aabb& g = bounds[in.geometry];
        if (!g.is_empty() && !finite_box(transform_box(in.transform, g)))
            throw Error(at("instances", i) + ".transform: takes " + at("geometries", in.geometry) +
                        " beyond the float range (its world bounds are not finite)");
    }
    for (std::size_t i = 0; i < scene.planes.size(); ++i) {
        const Plane& p = scene.planes[i];
        check_finite(p.point, at("planes", i) + ".point");
        check_finite(p.normal, at("planes", i) + ".normal");
        if (p.normal.x == 0.0f && p.normal.y == 0.0f && p.normal.z == 0.0f)
            throw Error(at("planes", i) + ".normal: zero");
    }
}

double volume(const Aabb& b) {
    if (b.is_empty()) return 0.0;
    return (double(b.hi.x) - double(b.lo.x)) * (double(b.hi.y) - double(b.lo.y)) * (double(b.hi.z) - double(b.lo.z));
}

}  // namespace simdbvh
