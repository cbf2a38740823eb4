#pragma once
// The hit of a scene query (24 bytes): which instance, geometry and primitive,
// at which world-space t, with u, v on that primitive.
//
// u, v by primitive kind:
//   triangle: the barycentrics of v1, v2 (as Hit);
//   sphere:   longitude and colatitude of the hit normal n = (p - c) / r in
//             object space: u = (atan2(n.y, n.x) + pi) / (2 pi),
//             v = atan2(sqrt(n.x^2 + n.y^2), n.z) / pi (acos(n.z) / pi for a unit n),
//             both in [0, 1], atan2 a polynomial within 1.1e-14 of libm's (shapes.cpp);
//   box:      the hit face's coordinates: with face axis a and the other axes
//             a1 < a2 (in x, y, z order), u = (p[a1] - lo[a1]) / extent[a1],
//             v = (p[a2] - lo[a2]) / extent[a2], clamped to [0, 1] (0 for a flat extent);
//   plane:    0, 0.
// Ids: inst is the instance index; planes follow the instances (plane k has
// inst = instances + k, geom = kNoGeometry, prim = k).
#include <bit>
#include <cstdint>
#include <limits>

#include "simdbvh/kernels/hit.h"

namespace simdbvh {

inline constexpr std::uint32_t kNoGeometry = 0xFFFFFFFFu;

struct SceneHit {
    float t = std::numeric_limits<float>::infinity();
    float u = 0.0f;
    float v = 0.0f;
    std::uint32_t prim = kInvalidPrim;
    std::uint32_t geom = kNoGeometry;
    std::uint32_t inst = kInvalidPrim;

    constexpr bool hit() const { return prim != kInvalidPrim; }
};
static_assert(sizeof(SceneHit) == 24);

// Bit equality, as Hit's.
inline bool operator==(const SceneHit& a, const SceneHit& b) {
    return std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) &&
           std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
           std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v) && a.prim == b.prim &&
           a.geom == b.geom && a.inst == b.inst;
}

// The closest-hit order across a scene: smaller t, then the lower instance id,
// then the lower primitive id (within an instance the geometry's own rule).
constexpr bool closer(float t, std::uint32_t inst, std::uint32_t prim, const SceneHit& best) {
    return t < best.t || (t == best.t && (inst < best.inst || (inst == best.inst && prim < best.prim)));
}

}  // namespace simdbvh
