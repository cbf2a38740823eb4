// SPDX-License-Identifier: MIT
#pragma once
// simdbvh accuracy, the inside/outside panel (docs/open3d.md): "where methods
// fail". Closed meshes and point families built to break parity counting
// (rays through vertices and along edges of an integer-coordinate mesh,
// points just off the surface, uniform points), each point's side from CGAL's
// exact Side_of_triangle_mesh as the reference, and every method's wrong
// answers and time per point: ours (exact, winding and parity rules) and the
// parity of Embree's hit count along +z (how Open3D and trimesh users count
// crossings), default and robust, and Open3D's RaycastingScene.compute_occupancy
// itself (open3d_inside.h: a Python worker on the same meshes and points).
#include <string>
#include <vector>

#include "lab.h"
#include "report.h"

namespace simdbvh::lab {

struct InsideRow {
    std::string mesh, family, method;
    std::size_t points = 0;      // points compared (CGAL's surface points left out)
    std::size_t on_surface = 0;  // CGAL: ON_BOUNDARY (not compared)
    std::size_t wrong = 0;       // side differs from CGAL's (ours: "surface" for a point CGAL puts off it, too)
    double seconds = 0;          // one thread, all `points` (surface ones included)
    std::string failed;          // non-empty: the method did not answer (Open3D's worker died: how); no wrong, no time
};

// Empty (with a message) when the build has no CGAL. `open3d`: add Open3D's rows (left out, with a
// message, when /usr/bin/python3 cannot import open3d).
std::vector<InsideRow> run_inside_panel(bool quick, bool embree, bool open3d);

Json inside_json(const std::vector<InsideRow>& rows);
std::string inside_markdown(const std::vector<InsideRow>& rows, bool chart);

}  // namespace simdbvh::lab
