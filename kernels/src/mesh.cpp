#include "simdbvh/mesh.h"

#include <string>

#include "simdbvh/kernels/error.h"

namespace simdbvh {

void validate(const Mesh& mesh) {
    const std::size_t nv = mesh.positions.size();
    if (mesh.triangles.size() >= kMaxTriangles)
        throw Error("mesh has " + std::to_string(mesh.triangles.size()) + " triangles > max " +
                    std::to_string(kMaxTriangles - 1));
    std::size_t bad = 0, first_bad = 0;
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t idx = mesh.triangles[i][k];
            if (idx >= nv)
                throw Error("triangle " + std::to_string(i) + " has vertex index " + std::to_string(idx) +
                            " out of range (" + std::to_string(nv) + " vertices)");
            if (!is_finite(mesh.positions[idx])) {
                if (bad++ == 0) first_bad = i;
                break;
            }
        }
    }
    if (bad)
        throw Error(std::to_string(bad) + " triangles have a NaN or infinite vertex (first: triangle " +
                    std::to_string(first_bad) + ")");
}

}  // namespace simdbvh
