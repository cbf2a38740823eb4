// SPDX-License-Identifier: MIT
#pragma once
// The inside/outside panel's meshes and point families (inside_panel.h): an
// integer-coordinate cube grid and points built to break parity counting.
// A library of their own so the tests can rebuild the panel's exact cases.
#include <cstddef>
#include <vector>

#include "lab.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::lab {

// The surface of [0, k]^3 split into unit squares, two triangles each, welded,
// facing outward: every coordinate an integer, so rays along +z from points
// with integer x and y run exactly through vertices, and with one of them a
// half integer, along edges.
Mesh cube_grid(int k);

// Points whose +z rays pass through vertices (integer x, y) and along edges
// (one half integer), at every level z + 0.5 and outside the box too.
std::vector<Vec3> lattice_points(int k);

// For each vertex, the points just below and just above it on the vertical
// through it (their +z rays meet the vertex); at most `max` points.
std::vector<Vec3> through_vertices(const Mesh& m, std::size_t max, float d);

// For each vertex v, the points v - d(1, 1, 1) (its ray along (1, 1, 1), the
// one Open3D's compute_occupancy casts, meets v) and v + d(1, 1, 1), with d
// the power of two at or below 2^-8 of the largest extent of the bounds. A
// point is kept only when its three coordinates are exact in float, so that
// v - p = d(1, 1, 1) holds exactly; at most `max` points.
std::vector<Vec3> diagonal_through_vertices(const Mesh& m, std::size_t max);

// Triangle centroids moved off the surface along the normal, both ways, by
// `ulps` units in the last place of the centroid's largest coordinate; at most `max` points.
std::vector<Vec3> near_surface(const Mesh& m, std::size_t max, int ulps);

}  // namespace simdbvh::lab
