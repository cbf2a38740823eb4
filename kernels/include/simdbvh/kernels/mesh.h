#pragma once
// The scene model: an indexed triangle mesh, float3 positions and uint32
// triangles. A triangle's id is its index in `triangles`.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "simdbvh/kernels/error.h"  // simdbvh::Error, thrown by everything declared here
#include "simdbvh/kernels/aabb.h"

namespace simdbvh {

using Triangle = std::array<std::uint32_t, 3>;

// Triangle ids are uint32 and 0xFFFFFFFF marks a miss.
inline constexpr std::size_t kMaxTriangles = 0xFFFFFFFFu;

struct Mesh {
    std::vector<Vec3> positions;
    std::vector<Triangle> triangles;

    std::size_t size() const { return triangles.size(); }
    Vec3 vertex(std::size_t tri, int k) const { return positions[triangles[tri][k]]; }
    Aabb bounds() const {
        Aabb b;
        for (const Triangle& t : triangles)
            for (int k = 0; k < 3; ++k) b.grow(positions[t[k]]);
        return b;
    }
};

// Throws simdbvh::Error naming the first triangle with an out-of-range index
// or the first non-finite vertex that a triangle uses.
void validate(const Mesh& mesh);

}  // namespace simdbvh
