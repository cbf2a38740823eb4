// Kept in its own object: only tests that generate rays pull in the BVH2.
#include "support/rays.h"

namespace test {

std::vector<simdbvh::Ray> rays(const simdbvh::Mesh& mesh, simdbvh::workloads::RayKind kind, std::size_t count,
                               std::uint64_t seed) {
    return simdbvh::workloads::generate_rays(mesh, kind, count, seed);
}

}  // namespace test
