#pragma once
// Procedural deformations for refit: the same triangles, moved vertices.
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::workloads {

// The mesh twisted about the vertical (y) axis through its bounds' centre:
// a vertex at height y turns by `radians` * (y - y_min) / (y_max - y_min)
// (0 at the bottom, `radians` at the top). Computed in double, rounded once;
// triangles unchanged. twist(m, 0) == m bit for bit.
Mesh twist(const Mesh& mesh, double radians);

}  // namespace simdbvh::workloads
