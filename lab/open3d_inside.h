// SPDX-License-Identifier: MIT
#pragma once
// Open3D's RaycastingScene.compute_occupancy as rows of the inside/outside
// panel (inside_panel.h). Open3D is Python only: a worker
// (scripts/open3d/inside_worker.py, run through run_python_script) answers every
// job in a child process, one thread, with the ray-mask shim Debian's Open3D
// needs (docs/open3d.md). A crash or a hang of the worker fails the job it was
// on (the rest run in a new worker), never the caller.
#include <span>
#include <string>
#include <vector>

#include "lab.h"
#include "simdbvh/query/inside.h"
#include "simdbvh/kernels/mesh.h"

namespace simdbvh::lab {

struct Open3dJob {
    const Mesh* mesh = nullptr;  // written once per distinct mesh; consecutive jobs on one mesh share its scene
    std::span<const Vec3> points;
};

struct Open3dAnswer {
    std::vector<Side> sides;  // Side::inside or Side::outside per point; empty when the job failed
    double seconds = 0;       // the timed compute_occupancy call (the scene built and committed before)
    std::string error;        // non-empty: the job failed, e.g. "killed by signal 6 (Aborted): <last stderr line>"
};

struct Open3dRun {
    bool available = true;  // false: python3 cannot import open3d (or does not start); `message` says so
    std::string message;
    std::vector<Open3dAnswer> answers;  // one per job when available
};

Open3dRun run_open3d_occupancy(std::span<const Open3dJob> jobs, double timeout_seconds);

// The worker's output for a job of `points` points: float64 little-endian seconds, then one byte per
// point, 1 inside, 0 outside. Throws simdbvh::Error on a wrong size, a byte other than 0 or 1, or seconds
// that are negative or not finite.
Open3dAnswer parse_occupancy(std::span<const unsigned char> bytes, std::size_t points);

}  // namespace simdbvh::lab
