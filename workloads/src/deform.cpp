// twist(): the deforming sequence of the refit benchmark and tests.
#include "simdbvh/workloads/deform.h"

#include <cmath>

namespace simdbvh::workloads {

Mesh twist(const Mesh& mesh, double radians) {
    Mesh out = mesh;
    if (radians == 0.0 || mesh.positions.empty()) return out;
    Aabb b;
    for (const Vec3& p : mesh.positions) b.grow(p);
    const double cx = 0.5 * (double(b.lo.x) + double(b.hi.x)), cz = 0.5 * (double(b.lo.z) + double(b.hi.z));
    const double h = double(b.hi.y) - double(b.lo.y);
    for (Vec3& p : out.positions) {
        const double a = h > 0 ? radians * (double(p.y) - double(b.lo.y)) / h : radians;
        const double x = double(p.x) - cx, z = double(p.z) - cz, c = std::cos(a), s = std::sin(a);
        p.x = float(cx + c * x - s * z);
        p.z = float(cz + s * x + c * z);
    }
    return out;
}

}  // namespace simdbvh::workloads
