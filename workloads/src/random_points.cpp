// Random query points.
#include "rng.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/workloads/points.h"

namespace simdbvh::workloads {

std::vector<Vec3> random_points(const Aabb& bounds, std::size_t count, std::uint64_t seed, float margin) {
    if (bounds.is_empty()) throw Error("cannot place query points around an empty scene (no triangles)");
    std::vector<Vec3> points(count);
    const Vec3 e = bounds.extent();
    detail::Rng rng(seed);
    for (Vec3& p : points)
        for (int k = 0; k < 3; ++k) p[k] = bounds.lo[k] + e[k] * rng.uniform(-margin, 1.0f + margin);
    return points;
}

}  // namespace simdbvh::workloads
