#pragma once
// Adversarial ray families (docs/accuracy.md, "Families of rays that make methods
// fail"): deterministic, seeded scenes and rays, each ray with the answer
// docs/accuracy.md gives for it (must hit, must miss, no self-hit, or "ask the
// double reference"). A family has one or more cases; a case is one mesh and
// the rays traced against it.
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "simdbvh/kernels/hit.h"
#include "simdbvh/kernels/ray.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::workloads {

enum class Family : std::uint8_t {
    watertight,       // closed icosphere and torus, origins inside, aimed at every vertex and edge midpoint
    offsets,          // the watertight cases translated by 1e0..1e7 (in double, rounded to float)
    axis_aligned,     // axis directions with +-0.0 elsewhere, origins exactly on vertex and slab planes
    surface_start,    // secondary rays from hit points offset along Ng (Wachter and Binder, RT Gems ch. 6)
    grazing,          // tessellated plane, angles 1e-1..1e-6 rad and exactly 0 (coplanar and parallel)
    needles,          // fans of very thin triangles, aspect 1e1..1e7
    degenerate,       // duplicates, zero-area triangles, equal centroids
    random,           // incoherent rays on a real mesh (or a procedural stand-in)
    direction_scale,  // the watertight icosphere rays with directions scaled by 2^-149 .. 2^127
};
inline constexpr Family kAllFamilies[] = {Family::watertight,    Family::offsets, Family::axis_aligned,
                                          Family::surface_start, Family::grazing, Family::needles,
                                          Family::degenerate,    Family::random,  Family::direction_scale};
// "watertight", "offsets", "axis-aligned", "surface-start", "grazing", "needles", "degenerate", "random",
// "direction-scale".
std::string_view name(Family f);
std::optional<Family> parse_family(std::string_view s);

enum class Expect : std::uint8_t {
    reference,    // whatever the double reference says
    hit,          // must hit (a closed surface around the origin, a connected fan, a plane below the ray)
    miss,         // must miss (coplanar or parallel to the plane)
    no_self_hit,  // must not hit `source`, the triangle the ray starts on
};
std::string_view name(Expect e);

struct RayExpect {
    Expect kind = Expect::reference;
    std::uint32_t source = kInvalidPrim;                  // no_self_hit: the starting triangle
    double t = std::numeric_limits<double>::quiet_NaN();  // grazing: h / sin(theta), from the float ray
};

struct FamilyCase {
    Family family = Family::watertight;
    std::string name;   // "watertight/icosphere", "offsets/torus/1e3", "needles/aspect1e7", ...
    double offset = 0;  // offsets (and surface-start at an offset): the translation along (1, 1, 1)
    Mesh mesh;
    std::vector<Ray> rays;
    std::vector<RayExpect> expect;  // one per ray
};

struct FamilyOptions {
    bool quick = false;  // smaller meshes and fewer rays (seconds, for tests and --quick)
    std::uint64_t seed = 1;
    // random: a scene name or mesh file (load_scene); empty: dragon-res4 when
    // cached, else a procedural stand-in (icosphere-4 plus a 4,000-triangle soup).
    std::string random_scene;
};

// Every case of a family. Deterministic for a given seed and options.
std::vector<FamilyCase> make_family(Family f, const FamilyOptions& opts = {});

// Procedural pieces the families use.
// Closed torus around the z axis: major radius R, minor radius r, n x m quads (2 n m triangles).
Mesh torus(int n, int m, float major_radius = 1.0f, float minor_radius = 0.35f, Vec3 center = {});
// The float offset point of Wachter and Binder (RT Gems ch. 6) for a hit point p with normal n. `scale`
// (the scene size) scales the absolute offset used near the origin, so that scaling a scene by 2^k scales
// every offset exactly.
Vec3 offset_ray_origin(Vec3 p, Vec3 n, float scale = 1.0f);

}  // namespace simdbvh::workloads
