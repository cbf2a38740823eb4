// SPDX-License-Identifier: MIT
// simdbvh accuracy, the inside/outside panel: run and report (inside_panel.h).
#include "lab.h"
#include "inside_panel.h"

#include <chrono>
#include <cmath>
#include <functional>
#include <sstream>
#include <tuple>

#include "common.h"
#include "inside_points.h"
#include "open3d_inside.h"
#include "simdbvh/query/inside.h"
#include "simdbvh/query/inside_wide.h"
#include "simdbvh/reference/cgal.h"
#include "simdbvh/reference/embree.h"
#include "simdbvh/workloads/points.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh::lab {

namespace {

constexpr const char* kOpen3dMethod = "Open3D (compute_occupancy)";
constexpr double kOpen3dTimeoutSeconds = 600;  // the worker's whole run (the full panel takes seconds)

struct PointSet {
    std::string name;
    std::vector<Vec3> points;
};

double seconds_of(const std::function<void()>& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return seconds_since(t0);
}

// A mesh and its point families.
struct MeshCase {
    std::string name;
    Mesh mesh;
    std::vector<PointSet> sets;
};

// `o3d`: Open3D's answers for the case's sets (null: no Open3D rows).
void run_mesh(const MeshCase& mc, bool embree, const Open3dAnswer* o3d, std::vector<InsideRow>& rows) {
    const Mesh& mesh = mc.mesh;
    const Bvh8 bvh = Bvh8::build(mesh);  // the CLI's default tree for inside (every tree gives the same sides)
    std::unique_ptr<reference::EmbreeScene> emb[2];
    if (embree)
        for (int robust = 0; robust < 2; ++robust) {
            reference::EmbreeOptions o;
            o.robust = robust == 1;
            o.threads = 1;
            o.count_filter = true;
            emb[robust] = std::make_unique<reference::EmbreeScene>(mesh, o);
        }
    for (std::size_t k = 0; k < mc.sets.size(); ++k) {
        const PointSet& set = mc.sets[k];
        progress("inside/outside: " + mc.name + ", " + set.name + " (" + std::to_string(set.points.size()) + " points)",
                 true);
        const std::vector<Side> ref = reference::cgal_sides(mesh, set.points);
        std::size_t surface = 0;
        for (Side s : ref) surface += s == Side::surface;
        auto tally = [&](const std::string& method, double seconds, const std::function<Side(std::size_t)>& side) {
            InsideRow r{mc.name, set.name, method, set.points.size() - surface, surface, 0, seconds, {}};
            for (std::size_t i = 0; i < ref.size(); ++i)
                if (ref[i] != Side::surface && side(i) != ref[i]) ++r.wrong;
            rows.push_back(r);
        };
        // Along +z, the ray the families are built to break (through vertices
        // and along edges), with both rules; and the default ray (shortest).
        for (auto [rule, ray, name] :
             {std::tuple{InsideOptions::Rule::winding, CountRay::plus_z, "simdbvh (winding)"},
              std::tuple{InsideOptions::Rule::parity, CountRay::plus_z, "simdbvh (parity)"},
              std::tuple{InsideOptions::Rule::winding, CountRay::shortest, "simdbvh (winding, shortest ray)"}}) {
            std::vector<PointSide> out(set.points.size());
            InsideOptions o;
            o.rule = rule;
            o.ray = ray;
            const double s = seconds_of([&] { classify_points(bvh, set.points, out, o); });
            tally(name, s, [&](std::size_t i) { return out[i].side; });
        }
        for (int robust = 0; robust < 2 && embree; ++robust) {
            std::vector<std::uint32_t> count(set.points.size());
            const double s = seconds_of([&] {
                for (std::size_t i = 0; i < set.points.size(); ++i)
                    count[i] = emb[robust]->count_hits(
                        Ray{set.points[i], 0.0f, {0.0f, 0.0f, 1.0f}, std::numeric_limits<float>::infinity()});
            });
            tally(robust ? "Embree robust (hit parity)" : "Embree (hit parity)", s,
                  [&](std::size_t i) { return count[i] % 2 ? Side::inside : Side::outside; });
        }
        if (!o3d) continue;
        const Open3dAnswer& a = o3d[k];
        if (a.error.empty()) tally(kOpen3dMethod, a.seconds, [&](std::size_t i) { return a.sides[i]; });
        else rows.push_back({mc.name, set.name, kOpen3dMethod, set.points.size() - surface, surface, 0, 0, a.error});
    }
}

// Open3D's answers for every set of every case, in order; empty (with a message) when it is not there.
std::vector<Open3dAnswer> run_open3d(const std::vector<MeshCase>& cases) {
    std::vector<Open3dJob> jobs;
    for (const MeshCase& mc : cases)
        for (const PointSet& set : mc.sets) jobs.push_back({&mc.mesh, set.points});
    progress("inside/outside: Open3D compute_occupancy, " + std::to_string(jobs.size()) +
                 " point sets (scripts/open3d/inside_worker.py) ...",
             true);
    Open3dRun run = run_open3d_occupancy(jobs, kOpen3dTimeoutSeconds);
    if (!run.available) progress("inside/outside: Open3D rows left out: " + run.message, true);
    return std::move(run.answers);
}

}  // namespace

std::vector<InsideRow> run_inside_panel(bool quick, bool embree, bool open3d) {
    std::vector<InsideRow> rows;
    if (!reference::have_cgal()) {
        progress("inside/outside panel skipped: this build has no CGAL (libcgal-dev)", true);
        return rows;
    }
    const std::size_t n = quick ? 4000 : 40000;
    const int k = quick ? 6 : 12;
    std::vector<MeshCase> cases(2);
    cases[0].name = "cube-grid-" + std::to_string(k);
    cases[0].mesh = cube_grid(k);
    const Mesh& cubes = cases[0].mesh;
    cases[0].sets = {{"through vertices and edges", lattice_points(k)},
                     {"diagonal rays through vertices", diagonal_through_vertices(cubes, n)},
                     {"uniform", workloads::random_points(cubes.bounds(), n, 5)},
                     {"2 ulps off the surface", near_surface(cubes, n, 2)}};
    cases[1].name = quick ? "icosphere-3" : "icosphere-5";
    cases[1].mesh = workloads::icosphere(quick ? 3 : 5);
    const Mesh& sphere = cases[1].mesh;
    cases[1].sets = {{"through vertices", through_vertices(sphere, n, 0.01f)},
                     {"diagonal rays through vertices", diagonal_through_vertices(sphere, n)},
                     {"uniform", workloads::random_points(sphere.bounds(), n, 6)},
                     {"2 ulps off the surface", near_surface(sphere, n, 2)}};
    const std::vector<Open3dAnswer> o3d = open3d ? run_open3d(cases) : std::vector<Open3dAnswer>{};
    std::size_t job = 0;
    for (const MeshCase& mc : cases) {
        run_mesh(mc, embree, o3d.empty() ? nullptr : &o3d[job], rows);
        job += mc.sets.size();
    }
    return rows;
}

Json inside_json(const std::vector<InsideRow>& rows) {
    Json a = Json::array();
    for (const InsideRow& r : rows) {
        const bool ok = r.failed.empty();
        const std::size_t all = r.points + r.on_surface;
        a.push_back({{"mesh", r.mesh},
                     {"family", r.family},
                     {"method", r.method},
                     {"points", r.points},
                     {"on_surface", r.on_surface},
                     {"wrong", ok ? Json(r.wrong) : Json()},
                     {"seconds", ok ? Json(r.seconds) : Json()},
                     {"us_per_point", ok ? Json(all ? 1e6 * r.seconds / double(all) : 0.0) : Json()},
                     {"failed", ok ? Json() : Json(r.failed)}});
    }
    return a;
}

std::string inside_markdown(const std::vector<InsideRow>& rows, bool chart) {
    std::ostringstream s;
    s << "\n## inside/outside: where methods fail\n\n";
    if (rows.empty()) return s.str() + "Not run (no CGAL in this build, or --family without --inside).\n";
    s << "Reference: CGAL's Side_of_triangle_mesh (exact predicates); points it puts on the surface are left out. "
         "Points: through vertices (and edges): +z rays exactly through vertices (and along edges); diagonal rays "
         "through vertices: v - d(1, 1, 1) and v + d(1, 1, 1) for each vertex v (d a power of two near 2^-8 of "
         "the extent; a point is kept only when it is exact in float), so the (1, 1, 1) ray from v - d(1, 1, 1), "
         "the ray Open3D casts, runs exactly through v (on the cube grid their +z rays also run along the squares' "
         "diagonal edges); uniform in the bounds; triangle centroids 2 ulps off the surface. "
         "simdbvh: one ray per point, exact crossings (docs/exact_crossings.md), winding or parity rule, along +z "
         "(the ray the vertex and edge families are built to break) or along the default shortest ray (toward the "
         "nearest face of the bounds). "
         "Embree: the parity of the hits `rtcIntersect1` reports along +z with a counting filter that rejects each "
         "hit. Open3D: `RaycastingScene.compute_occupancy` (Debian's python3-open3d 0.16 with the ray-mask shim, "
         "docs/open3d.md) in a Python worker (scripts/open3d/inside_worker.py): the parity of its "
         "`count_intersections` along (1, 1, 1), which skips a hit on the triangle it counted last or at the same "
         "t. One thread (Open3D: OMP_NUM_THREADS=1, nthreads=1). Time: the query only, after the build (ours and "
         "Embree: the first call; Open3D: the second call, the first, untimed, commits its scene). A failed row: "
         "the worker died on those points.\n\n";
    Table t({"mesh", "points", "method", "compared", "on surface", "wrong", "wrong %", "us/point"}, "lllrrrrr");
    for (const InsideRow& r : rows) {
        const std::size_t all = r.points + r.on_surface;
        if (!r.failed.empty()) {
            t.row({r.mesh, r.family, r.method, std::to_string(r.points), std::to_string(r.on_surface),
                   "failed: " + r.failed, "-", "-"});
            continue;
        }
        t.row({r.mesh, r.family, r.method, std::to_string(r.points), std::to_string(r.on_surface),
               std::to_string(r.wrong), fmt("%.3g", r.points ? 100.0 * double(r.wrong) / double(r.points) : 0.0),
               fmt("%.3g", all ? 1e6 * r.seconds / double(all) : 0.0)});
    }
    s << t.markdown();
    if (chart) s << "\n![inside/outside: wrong answers and time per point](inside_outside.png)\n";
    return s.str();
}

}  // namespace simdbvh::lab
