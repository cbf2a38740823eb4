// SPDX-License-Identifier: MIT
// simdbvh accuracy, the inside/outside panel: run and report (inside_panel.h).
#include "inside_panel.h"

#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <sstream>

#include "common.h"
#include "simdbvh/bvh2/inside.h"
#include "simdbvh/bvh8/inside.h"
#include "simdbvh/compare/cgal.h"
#include "simdbvh/compare/embree.h"
#include "simdbvh/scene/points.h"
#include "simdbvh/scene/scenes.h"

namespace simdbvh::cli {

namespace {

struct PointSet {
    std::string name;
    std::vector<Vec3> points;
};

// The surface of [0, k]^3 split into unit squares, two triangles each, welded,
// facing outward: every coordinate an integer, so rays along +z from points
// with integer x and y run exactly through vertices, and with one of them a
// half integer, along edges.
Mesh cube_grid(int k) {
    Mesh m;
    std::map<std::array<int, 3>, std::uint32_t> index;
    auto vertex = [&](int x, int y, int z) {
        auto [it, added] = index.try_emplace({x, y, z}, std::uint32_t(m.positions.size()));
        if (added) m.positions.push_back({float(x), float(y), float(z)});
        return it->second;
    };
    // axis a is the face normal's axis; (u, v) the other two in right-handed order.
    for (int a = 0; a < 3; ++a) {
        const int u = (a + 1) % 3, v = (a + 2) % 3;
        for (int side = 0; side < 2; ++side)
            for (int i = 0; i < k; ++i)
                for (int j = 0; j < k; ++j) {
                    auto at = [&](int di, int dj) {
                        int c[3];
                        c[a] = side * k;
                        c[u] = i + di;
                        c[v] = j + dj;
                        return vertex(c[0], c[1], c[2]);
                    };
                    const std::uint32_t p00 = at(0, 0), p10 = at(1, 0), p11 = at(1, 1), p01 = at(0, 1);
                    if (side == 1) {  // normal +a: u x v = a
                        m.triangles.push_back({p00, p10, p11});
                        m.triangles.push_back({p00, p11, p01});
                    } else {
                        m.triangles.push_back({p00, p11, p10});
                        m.triangles.push_back({p00, p01, p11});
                    }
                }
    }
    return m;
}

// Points whose +z rays pass through vertices (integer x, y) and along edges
// (one half integer), at every level z + 0.5 and outside the box too.
std::vector<Vec3> lattice_points(int k) {
    std::vector<Vec3> p;
    for (int x2 = -2; x2 <= 2 * k + 2; ++x2)
        for (int y2 = -2; y2 <= 2 * k + 2; ++y2) {
            if (x2 % 2 != 0 && y2 % 2 != 0) continue;  // at least one integer coordinate
            for (int z = -1; z <= k; ++z) p.push_back({0.5f * float(x2), 0.5f * float(y2), float(z) + 0.5f});
        }
    return p;
}

// For each vertex, the points just below and just above it on the vertical
// through it (their +z rays meet the vertex).
std::vector<Vec3> through_vertices(const Mesh& m, std::size_t max, float d) {
    std::vector<Vec3> p;
    for (std::size_t i = 0; i < m.positions.size() && p.size() < max; ++i) {
        const Vec3 v = m.positions[i];
        p.push_back({v.x, v.y, v.z - d});
        p.push_back({v.x, v.y, v.z + d});
    }
    return p;
}

// Triangle centroids moved off the surface along the normal, both ways, by
// `ulps` units in the last place of the centroid's largest coordinate.
std::vector<Vec3> near_surface(const Mesh& m, std::size_t max, int ulps) {
    std::vector<Vec3> p;
    for (std::size_t t = 0; t < m.size() && p.size() < max; ++t) {
        const Vec3 a = m.vertex(t, 0), b1 = m.vertex(t, 1), c = m.vertex(t, 2);
        const double ux = b1.x - a.x, uy = b1.y - a.y, uz = b1.z - a.z, vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
        double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
        const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
        if (!(len > 0)) continue;
        nx /= len, ny /= len, nz /= len;
        const double cx = (double(a.x) + b1.x + c.x) / 3, cy = (double(a.y) + b1.y + c.y) / 3,
                     cz = (double(a.z) + b1.z + c.z) / 3;
        const float big = float(std::max({std::fabs(cx), std::fabs(cy), std::fabs(cz)}));
        const double ulp = double(std::nextafter(big, INFINITY)) - double(big);
        for (double s : {-1.0, 1.0}) {
            const double o = s * ulps * ulp;
            p.push_back({float(cx + o * nx), float(cy + o * ny), float(cz + o * nz)});
        }
    }
    return p;
}

double seconds_of(const std::function<void()>& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return seconds_since(t0);
}

void run_mesh(const std::string& mesh_name, const Mesh& mesh, const std::vector<PointSet>& sets, bool embree,
              std::vector<InsideRow>& rows) {
    const Bvh8 bvh = Bvh8::build(mesh);  // the CLI's default tree for inside (every tree gives the same sides)
    std::unique_ptr<compare::EmbreeScene> emb[2];
    if (embree)
        for (int robust = 0; robust < 2; ++robust) {
            compare::EmbreeOptions o;
            o.robust = robust == 1;
            o.threads = 1;
            o.count_filter = true;
            emb[robust] = std::make_unique<compare::EmbreeScene>(mesh, o);
        }
    for (const PointSet& set : sets) {
        progress("inside/outside: " + mesh_name + ", " + set.name + " (" + std::to_string(set.points.size()) +
                     " points)",
                 true);
        const std::vector<Side> ref = compare::cgal_sides(mesh, set.points);
        std::size_t surface = 0;
        for (Side s : ref) surface += s == Side::surface;
        auto tally = [&](const std::string& method, double seconds, const std::function<Side(std::size_t)>& side) {
            InsideRow r{mesh_name, set.name, method, set.points.size() - surface, surface, 0, seconds};
            for (std::size_t i = 0; i < ref.size(); ++i)
                if (ref[i] != Side::surface && side(i) != ref[i]) ++r.wrong;
            rows.push_back(r);
        };
        for (auto rule : {InsideOptions::Rule::winding, InsideOptions::Rule::parity}) {
            std::vector<PointSide> out(set.points.size());
            InsideOptions o;
            o.rule = rule;
            const double s = seconds_of([&] { classify_points(bvh, set.points, out, o); });
            tally(rule == InsideOptions::Rule::winding ? "simdbvh (winding)" : "simdbvh (parity)", s,
                  [&](std::size_t i) { return out[i].side; });
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
    }
}

}  // namespace

std::vector<InsideRow> run_inside_panel(bool quick, bool embree) {
    std::vector<InsideRow> rows;
    if (!compare::have_cgal()) {
        progress("inside/outside panel skipped: this build has no CGAL (libcgal-dev)", true);
        return rows;
    }
    const std::size_t n = quick ? 4000 : 40000;
    const int k = quick ? 6 : 12;
    const Mesh cubes = cube_grid(k);
    run_mesh("cube-grid-" + std::to_string(k), cubes,
             {{"through vertices and edges", lattice_points(k)},
              {"uniform", scene::random_points(cubes.bounds(), n, 5)},
              {"2 ulps off the surface", near_surface(cubes, n, 2)}},
             embree, rows);
    const Mesh sphere = scene::icosphere(quick ? 3 : 5);
    run_mesh(quick ? "icosphere-3" : "icosphere-5", sphere,
             {{"through vertices", through_vertices(sphere, n, 0.01f)},
              {"uniform", scene::random_points(sphere.bounds(), n, 6)},
              {"2 ulps off the surface", near_surface(sphere, n, 2)}},
             embree, rows);
    return rows;
}

Json inside_json(const std::vector<InsideRow>& rows) {
    Json a = Json::array();
    for (const InsideRow& r : rows)
        a.push_back({{"mesh", r.mesh},
                     {"family", r.family},
                     {"method", r.method},
                     {"points", r.points},
                     {"on_surface", r.on_surface},
                     {"wrong", r.wrong},
                     {"seconds", r.seconds},
                     {"us_per_point", r.points + r.on_surface ? 1e6 * r.seconds / double(r.points + r.on_surface) : 0.0}});
    return a;
}

std::string inside_markdown(const std::vector<InsideRow>& rows, bool chart) {
    std::ostringstream s;
    s << "\n## inside/outside: where methods fail\n\n";
    if (rows.empty()) return s.str() + "Not run (no CGAL in this build, or --family without --inside).\n";
    s << "Reference: CGAL's Side_of_triangle_mesh (exact predicates); points it puts on the surface are left out. "
         "simdbvh: one ray along +z per point, exact crossings (docs/exact_crossings.md), winding or parity rule. "
         "Embree: the parity of the hits `rtcIntersect1` reports along +z with a counting filter that rejects each "
         "hit (Open3D's RaycastingScene counts intersections this way). One thread.\n\n";
    Table t({"mesh", "points", "method", "compared", "on surface", "wrong", "wrong %", "us/point"}, "lllrrrrr");
    for (const InsideRow& r : rows)
        t.row({r.mesh, r.family, r.method, std::to_string(r.points), std::to_string(r.on_surface),
               std::to_string(r.wrong), fmt("%.3g", r.points ? 100.0 * double(r.wrong) / double(r.points) : 0.0),
               fmt("%.3g", r.points + r.on_surface ? 1e6 * r.seconds / double(r.points + r.on_surface) : 0.0)});
    s << t.markdown();
    if (chart) s << "\n![inside/outside: wrong answers and time per point](inside_outside.png)\n";
    return s.str();
}

}  // namespace simdbvh::cli
