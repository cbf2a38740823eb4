#pragma once
// Ray helpers for tests (these need the BVH2 for diffuse rays).
#include <cstdint>
#include <vector>

#include "simdbvh/kernels/mesh.h"
#include "simdbvh/workloads/rays.h"

namespace test {

std::vector<simdbvh::Ray> rays(const simdbvh::Mesh& mesh, simdbvh::workloads::RayKind kind, std::size_t count,
                               std::uint64_t seed);

}  // namespace test
