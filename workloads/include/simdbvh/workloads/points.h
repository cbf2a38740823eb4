#pragma once
// Random query points (their files: simdbvh/io/point_files.h).
#include <cstdint>
#include <vector>

#include "simdbvh/kernels/aabb.h"

namespace simdbvh::workloads {

// count points uniform in `bounds` grown by `margin` times its extent on every
// side (deterministic for a seed on every machine).
std::vector<Vec3> random_points(const Aabb& bounds, std::size_t count, std::uint64_t seed, float margin = 0.1f);

}  // namespace simdbvh::workloads
