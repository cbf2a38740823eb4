// SPDX-License-Identifier: MIT
#pragma once
// simdbvh bench --scene room|instances-N|spheres-N|FILE.json, the run: the
// two-level scene (BVH8 bottom levels, instance bounds by corners and by child
// corners) against Embree's instanced scene on the same rays, one thread;
// against both flattened (meshes only, when it fits); bytes; agreement with the
// brute force and with Embree; analytic spheres against tessellated ones
// (icosphere levels 0..5); planes kept out of the tree against planes put in it
// as large flat boxes; the sphere precision study (sphere_precision.h).
#include <string>
#include <vector>

#include "lab.h"
#include "bench_run.h"
#include "sphere_precision.h"
#include "simdbvh/reference/scene_reference.h"
#include "simdbvh/scene/scene.h"

namespace simdbvh::lab {

struct SceneSpeedRow {
    std::string method;      // "BVH8 scene (child-corners)", "Embree instanced", ...
    std::string rays;        // primary | incoherent
    std::string query;       // closest | any
    double mrays_per_s = 0;  // median of c.reps after a warm-up, methods interleaved
};

struct SceneBuildRow {
    std::string method;
    double build_ms = 0;     // median of c.build_reps builds after an untimed first one
    std::size_t bytes = 0;   // ours: SceneStats::bytes; Embree: its device memory (buffers + BVHs)
    bool estimated = false;  // a flattened row too large to build: bytes are the bottom trees' bytes per
                             // triangle times the flattened triangles, nothing timed
};

// Closest hits of one method against ours (BVH8, child corners) on one ray kind.
struct SceneAgreementRow {
    std::string method, rays;
    std::size_t count = 0;
    std::size_t same = 0;          // same hit/miss, and the same instance, geometry and primitive
    std::size_t same_bits = 0;     // ... and t, u, v bit for bit (brute force: must be all)
    std::size_t other_object = 0;  // both hit, different objects
    std::size_t only_ours = 0;     // we hit, it missed
    std::size_t only_theirs = 0;   // it hit, we missed
    // Rays where the two differ (hit/miss, object, or t beyond the reference tolerance), refereed by the double
    // scene reference (reference/scene_reference.h), at most kMaxRefereed of them: both answers classified.
    std::size_t differ = 0, refereed = 0;
    reference::SceneTally ours, theirs;
};

inline constexpr std::size_t kMaxRefereed = 2000;

// Analytic spheres against the same spheres tessellated (level 0..5: 20 * 4^level triangles each).
struct TessellationRow {
    std::string method;  // "analytic", "Embree SPHERE_POINT", "icosphere-L"
    int level = -1;      // -1: analytic
    std::size_t triangles = 0, bytes = 0;
    double mrays_primary = 0, mrays_incoherent = 0;
    double same_sphere = 0;  // fraction of rays hitting the same sphere as the analytic test (or both missing)
    double median_err = 0, max_err = 0;  // | |p - c| - r | / r at the hit point, over the rays it hit
};

struct PlaneRow {
    std::string method;  // "BVH8, planes out", "BVH8, planes in (flat boxes)", "Embree, ..."
    std::string rays;
    double mrays_per_s = 0;
    std::size_t count = 0, same_t = 0;  // rays whose hit t (or miss) equals the same method's planes-out t bit for bit
};

struct SceneDescBenchResults {
    std::string scene;
    SceneStats stats;  // ours, child corners
    std::size_t rays = 0;
    std::vector<SceneBuildRow> builds;
    std::vector<SceneSpeedRow> speed;
    std::vector<SceneAgreementRow> agreement;
    std::vector<TessellationRow> tessellation;  // empty without sphere sets
    std::size_t tessellation_spheres = 0;
    std::vector<PlaneRow> planes;  // empty without axis-aligned planes
    std::size_t planes_in_tree = 0;
    std::vector<SpherePrecisionRow> sphere_precision;  // empty without sphere sets
};

// The largest flattened scene the bench builds (triangles); larger ones get an estimated bytes row.
inline constexpr std::size_t kMaxFlattenedTriangles = 16'000'000;

SceneDescBenchResults run_scene_desc_bench(const BenchConfig& c, const SceneDesc& desc);

}  // namespace simdbvh::lab
