#include "simdbvh/kernels/mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "simdbvh/kernels/error.h"

namespace simdbvh {

void validate(const Mesh& mesh) {
    const std::size_t nv = mesh.positions.size();
    if (mesh.triangles.size() >= kMaxTriangles)
        throw Error("mesh has " + std::to_string(mesh.triangles.size()) + " triangles > max " +
                    std::to_string(kMaxTriangles - 1));
    // The common case in two linear passes the compiler vectorizes (no
    // gather through the indices): every index in range, every position
    // finite. Otherwise the per-triangle pass below finds what to report
    // (a non-finite position no triangle uses is no error).
    std::uint32_t max_index = 0;
    for (const Triangle& t : mesh.triangles) max_index = std::max(max_index, std::max(t[0], std::max(t[1], t[2])));
    constexpr float kMax = std::numeric_limits<float>::max();
    bool finite = true;
    for (const Vec3& p : mesh.positions)
        finite &= int(std::fabs(p.x) <= kMax) & int(std::fabs(p.y) <= kMax) & int(std::fabs(p.z) <= kMax);
    if ((mesh.triangles.empty() || max_index < nv) && finite) return;
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
