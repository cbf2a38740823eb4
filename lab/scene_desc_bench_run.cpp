// SPDX-License-Identifier: MIT
// simdbvh bench on a scene description (scene_desc_bench_run.h). Every timed
// group: an untimed warm-up trace of every method, then c.reps rounds with the
// methods interleaved, the median per method; builds: one untimed, then the
// median of c.build_reps.
#include "lab.h"
#include "scene_desc_bench_run.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <memory>

#include "common.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/reference/embree.h"
#include "simdbvh/reference/embree_instances.h"
#include "simdbvh/reference/reference.h"
#include "simdbvh/workloads/scene_desc.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh::lab {

namespace {

using Clock = std::chrono::steady_clock;

// A traced method: closest or any hit of a ray span into its own buffer.
struct Method {
    std::string name;
    std::function<void(std::span<const Ray>, bool any)> trace;
    std::function<SceneHit(std::size_t)> hit;  // ray i's result of the last trace
};

double build_median(int reps, const std::function<double()>& build) {
    build();  // untimed (cold)
    std::vector<double> ms;
    for (int r = 0; r < std::max(1, reps); ++r) ms.push_back(build());
    return median(ms);
}

template <typename F>
double timed_ms(F&& f) {
    const auto t0 = Clock::now();
    f();
    return seconds_since(t0) * 1e3;
}

// Mrays/s per method on `rays` (medians; warm-up first, methods interleaved).
std::vector<double> time_methods(const std::vector<Method*>& ms, std::span<const Ray> rays, bool any, int reps) {
    for (Method* m : ms) m->trace(rays, any);
    std::vector<std::vector<double>> mr(ms.size());
    for (int rep = 0; rep < reps; ++rep)
        for (std::size_t i = 0; i < ms.size(); ++i) {
            const auto t0 = Clock::now();
            ms[i]->trace(rays, any);
            mr[i].push_back(double(rays.size()) / seconds_since(t0) / 1e6);
        }
    std::vector<double> out;
    for (auto& v : mr) out.push_back(median(v));
    return out;
}

bool meshes_only(const SceneDesc& d) {
    return std::all_of(d.geometries.begin(), d.geometries.end(),
                       [](const Geometry& g) { return std::holds_alternative<Mesh>(g); });
}

// Every instance baked into world triangles, and where each instance's triangles start.
Mesh flatten(const SceneDesc& d, std::vector<std::uint32_t>* first) {
    Mesh flat;
    for (const Instance& in : d.instances) {
        const Mesh& m = std::get<Mesh>(d.geometries[in.geometry]);
        first->push_back(std::uint32_t(flat.triangles.size()));
        const auto base = std::uint32_t(flat.positions.size());
        for (const Vec3& p : m.positions) flat.positions.push_back(transform_point(in.transform, p));
        for (const Triangle& t : m.triangles) flat.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    return flat;
}

// A flattened triangle id as the scene's (instance, geometry, primitive).
SceneHit scene_hit_of(const Hit& h, const SceneDesc& d, const std::vector<std::uint32_t>& first) {
    if (!h.hit()) return SceneHit{};
    const auto inst = std::uint32_t(std::upper_bound(first.begin(), first.end(), h.prim) - first.begin() - 1);
    return SceneHit{h.t, h.u, h.v, h.prim - first[inst], d.instances[inst].geometry, inst};
}

std::size_t wide_bytes(const Bvh8& b) {
    return b.nodes().size() * sizeof(Bvh8::Node) + b.blocks().size() * sizeof(Tri8);
}

Method scene_method(std::string name, const SceneBvhN<8>& s, std::vector<SceneHit>& buf) {
    return Method{std::move(name),
                  [&s, &buf](std::span<const Ray> rays, bool any) {
                      buf.resize(rays.size());
                      any ? occluded(s, rays, std::span<SceneHit>(buf), {.isa = active_isa()})
                          : intersect(s, rays, std::span<SceneHit>(buf), {.isa = active_isa()});
                  },
                  [&buf](std::size_t i) { return buf[i]; }};
}

Method embree_method(std::string name, const reference::EmbreeInstanceScene& e, std::vector<SceneHit>& buf) {
    return Method{std::move(name),
                  [&e, &buf](std::span<const Ray> rays, bool any) {
                      buf.resize(rays.size());
                      any ? e.occluded(rays, buf) : e.intersect(rays, buf);
                  },
                  [&buf](std::size_t i) { return buf[i]; }};
}

// Closest hits of `got` against ours (`ref`); the rays where they differ go to the double reference.
void agreement(const std::string& method, const std::string& kind, std::span<const Ray> rays, const Method& ref,
               const std::function<SceneHit(std::size_t)>& got, const reference::SceneReferencer* referee,
               std::vector<SceneAgreementRow>& out) {
    SceneAgreementRow a;
    a.method = method;
    a.rays = kind;
    a.count = rays.size();
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const SceneHit r = ref.hit(i), g = got(i);
        bool differ = false;
        if (r.hit() && !g.hit()) {
            ++a.only_ours;
            differ = true;
        } else if (!r.hit() && g.hit()) {
            ++a.only_theirs;
            differ = true;
        } else if (!r.hit() || (r.inst == g.inst && r.geom == g.geom && r.prim == g.prim)) {
            ++a.same;
            a.same_bits += r == g;
            differ = r.hit() && std::fabs(double(r.t) - double(g.t)) >
                                    reference::tolerance(rays[i], r.t) * (referee ? referee->cond(r.inst) : 1.0);
        } else {
            ++a.other_object;
            differ = true;
        }
        if (!differ) continue;
        ++a.differ;
        if (!referee || a.refereed >= kMaxRefereed) continue;
        ++a.refereed;
        const reference::SceneReference x = referee->closest(rays[i]);
        a.ours.add(referee->classify(rays[i], x, r));
        a.theirs.add(referee->classify(rays[i], x, g));
    }
    out.push_back(a);
}

// --- analytic against tessellated spheres -------------------------------------------------------------------

double sphere_error(const Ray& r, float t, const Sphere& s) {
    double len = 0;
    for (int k = 0; k < 3; ++k) {
        const double p = double(r.org[k]) + double(t) * double(r.dir[k]) - double(s.center[k]);
        len += p * p;
    }
    return std::fabs(std::sqrt(len) - double(s.radius)) / double(s.radius);
}

void tessellation(const BenchConfig& c, const SphereSet& all, SceneDescBenchResults& res) {
    const std::size_t k = std::min<std::size_t>(all.spheres.size(), 100);
    res.tessellation_spheres = k;
    SceneDesc analytic;
    analytic.geometries.push_back(SphereSet{{all.spheres.begin(), all.spheres.begin() + std::ptrdiff_t(k)}});
    analytic.instances.push_back({0, Affine3{}});
    const auto& spheres = std::get<SphereSet>(analytic.geometries[0]).spheres;
    const std::size_t n = std::min<std::size_t>(c.rays, 65536);
    const std::vector<Ray> primary = workloads::scene_camera_rays(analytic, n);
    const std::vector<Ray> incoherent = workloads::interior_rays(world_bounds(analytic), n, 5);

    constexpr int kLevels = 6;
    progress("tessellation: analytic spheres and icosphere levels 0.." + std::to_string(kLevels - 1), true);
    // Rows and methods in one order: ours analytic, Embree's analytic, the levels.
    std::vector<SceneBvhN<8>> trees;  // analytic, then the levels
    std::vector<TessellationRow> rows;
    std::vector<std::size_t> per_sphere;  // triangles per sphere (1 for analytic)
    trees.push_back(SceneBvhN<8>::build(analytic));
    const reference::EmbreeInstanceScene embree(analytic);
    rows.push_back({"analytic (ours)", -1, 0, trees.back().stats().bytes});
    rows.push_back({"Embree SPHERE_POINT", -1, 0, embree.bytes()});
    per_sphere = {1, 1};
    for (int level = 0; level < kLevels; ++level) {
        SceneDesc tess;
        Mesh m;
        for (const Sphere& s : spheres) {
            const Mesh one = workloads::icosphere(level, s.radius, s.center);
            const auto base = std::uint32_t(m.positions.size());
            m.positions.insert(m.positions.end(), one.positions.begin(), one.positions.end());
            for (const Triangle& t : one.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
        }
        const std::size_t tris = m.triangles.size();
        tess.geometries.push_back(std::move(m));
        tess.instances.push_back({0, Affine3{}});
        trees.push_back(SceneBvhN<8>::build(tess));
        rows.push_back({"icosphere-" + std::to_string(level), level, tris, trees.back().stats().bytes});
        per_sphere.push_back(tris / k);
    }
    std::vector<std::vector<SceneHit>> bufs(rows.size());
    std::vector<Method> methods;
    methods.push_back(scene_method(rows[0].method, trees[0], bufs[0]));
    methods.push_back(embree_method(rows[1].method, embree, bufs[1]));
    for (std::size_t i = 1; i < trees.size(); ++i)
        methods.push_back(scene_method(rows[i + 1].method, trees[i], bufs[i + 1]));
    std::vector<Method*> ptrs;
    for (Method& m : methods) ptrs.push_back(&m);
    const auto mp = time_methods(ptrs, primary, false, c.reps);
    const auto mi = time_methods(ptrs, incoherent, false, c.reps);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        rows[i].mrays_primary = mp[i];
        rows[i].mrays_incoherent = mi[i];
    }
    // Accuracy over both ray sets, against our analytic test.
    std::vector<std::vector<double>> errs(rows.size());
    std::vector<std::size_t> same(rows.size(), 0);
    for (const auto* rays : {&primary, &incoherent}) {
        for (Method& m : methods) m.trace(*rays, false);
        for (std::size_t i = 0; i < rays->size(); ++i) {
            const SceneHit ref = methods[0].hit(i);
            for (std::size_t j = 0; j < methods.size(); ++j) {
                const SceneHit h = methods[j].hit(i);
                const std::uint32_t sphere = h.hit() ? h.prim / std::uint32_t(per_sphere[j]) : kInvalidPrim;
                same[j] += h.hit() == ref.hit() && (!h.hit() || sphere == ref.prim);
                if (h.hit()) errs[j].push_back(sphere_error((*rays)[i], h.t, spheres[sphere]));
            }
        }
    }
    for (std::size_t j = 0; j < rows.size(); ++j) {
        rows[j].same_sphere = double(same[j]) / double(primary.size() + incoherent.size());
        rows[j].median_err = median(errs[j]);
        rows[j].max_err = errs[j].empty() ? 0.0 : *std::max_element(errs[j].begin(), errs[j].end());
    }
    res.tessellation = std::move(rows);
}

// --- planes kept out of the tree against planes put in it ---------------------------------------------------

int axis_of(const Vec3& n) {
    const int zeros = (n.x == 0.0f) + (n.y == 0.0f) + (n.z == 0.0f);
    if (zeros != 2) return -1;
    return n.x != 0.0f ? 0 : n.y != 0.0f ? 1 : 2;
}

void planes(const BenchConfig& c, const SceneDesc& desc, const std::vector<Ray> (&rays)[2],
            SceneDescBenchResults& res) {
    SceneDesc in = desc;
    in.planes.clear();
    BoxSet boxes;
    const Aabb b = world_bounds(desc);
    const Vec3 e = b.extent();
    float big = 0;
    for (int a = 0; a < 3; ++a) big = std::max({big, std::fabs(b.lo[a]), std::fabs(b.hi[a]), e[a]});
    const float half = 1000.0f * big;  // the plane as a flat box 2000x the scene's size across
    for (const Plane& p : desc.planes) {
        const int a = axis_of(p.normal);
        if (a < 0) {
            in.planes.push_back(p);
            continue;
        }
        Aabb box{{-half, -half, -half}, {half, half, half}};
        box.lo[a] = box.hi[a] = p.point[a];
        boxes.boxes.push_back(box);
    }
    res.planes_in_tree = boxes.boxes.size();
    if (boxes.boxes.empty()) return;
    in.geometries.push_back(boxes);
    in.instances.push_back({std::uint32_t(in.geometries.size() - 1), Affine3{}});
    progress("planes: kept out against put in the tree (" + std::to_string(boxes.boxes.size()) + " flat boxes)", true);
    const SceneBvhN<8> out_tree = SceneBvhN<8>::build(desc), in_tree = SceneBvhN<8>::build(in);
    const reference::EmbreeInstanceScene embree_out(desc), embree_in(in);
    std::vector<SceneHit> bufs[4];
    Method ms[4] = {scene_method("BVH8 scene, planes out", out_tree, bufs[0]),
                    scene_method("BVH8 scene, planes in (flat boxes)", in_tree, bufs[1]),
                    embree_method("Embree instanced, planes out", embree_out, bufs[2]),
                    embree_method("Embree instanced, planes in (flat quads)", embree_in, bufs[3])};
    std::vector<Method*> ptrs{&ms[0], &ms[1], &ms[2], &ms[3]};
    const char* kinds[2] = {"primary", "incoherent"};
    for (int k = 0; k < 2; ++k) {
        const auto mr = time_methods(ptrs, rays[k], false, c.reps);
        for (Method& m : ms) m.trace(rays[k], false);
        for (std::size_t j = 0; j < 4; ++j) {
            PlaneRow row{ms[j].name, kinds[k], mr[j], rays[k].size(), 0};
            for (std::size_t i = 0; i < rays[k].size(); ++i) {  // each "in" row against its own "out" row
                const SceneHit a = ms[j & ~std::size_t(1)].hit(i), h = ms[j].hit(i);
                row.same_t +=
                    a.hit() == h.hit() && std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(h.t);
            }
            res.planes.push_back(row);
        }
    }
}

}  // namespace

SceneDescBenchResults run_scene_desc_bench(const BenchConfig& c, const SceneDesc& desc) {
    SceneDescBenchResults res;
    res.scene = c.scene;
    progress("building the scene and Embree's instanced scene", true);
    SceneOptions child, corners;
    corners.bounds = InstanceBounds::corners;
    SceneBvhN<8> ours, ours_corners;
    const double ms_child =
        build_median(c.build_reps, [&] { return timed_ms([&] { ours = SceneBvhN<8>::build(desc, child); }); });
    const double ms_corners = build_median(
        c.build_reps, [&] { return timed_ms([&] { ours_corners = SceneBvhN<8>::build(desc, corners); }); });
    std::unique_ptr<reference::EmbreeInstanceScene> embree;
    const double ms_embree = build_median(c.build_reps, [&] {
        embree.reset();
        return timed_ms([&] { embree = std::make_unique<reference::EmbreeInstanceScene>(desc); });
    });
    res.stats = ours.stats();
    res.builds.push_back({"BVH8 scene (child-corners)", ms_child, ours.stats().bytes});
    res.builds.push_back({"BVH8 scene (corners)", ms_corners, ours_corners.stats().bytes});
    res.builds.push_back({"Embree instanced", ms_embree, embree->bytes()});

    std::vector<SceneHit> bufs[3];
    std::vector<Hit> flat_hits, embree_flat_hits;
    std::vector<std::uint8_t> flat_occ;
    std::vector<Method> methods{scene_method("BVH8 scene (child-corners)", ours, bufs[0]),
                                scene_method("BVH8 scene (corners)", ours_corners, bufs[1]),
                                embree_method("Embree instanced", *embree, bufs[2])};
    // Flattened (meshes only): built and traced when it fits, else its bytes estimated.
    Bvh8 flat;
    std::unique_ptr<reference::EmbreeScene> embree_flat;
    std::vector<std::uint32_t> first;
    const std::size_t flat_tris = res.stats.instanced_primitives;
    if (meshes_only(desc) && desc.instances.size() > 1) {
        if (flat_tris <= kMaxFlattenedTriangles) {
            progress("flattening " + std::to_string(flat_tris) + " triangles", true);
            const Mesh mesh = flatten(desc, &first);
            const double ms_flat =
                build_median(c.build_reps, [&] { return timed_ms([&] { flat = Bvh8::build(mesh); }); });
            const double ms_eflat = build_median(c.build_reps, [&] {
                embree_flat.reset();
                return timed_ms([&] { embree_flat = std::make_unique<reference::EmbreeScene>(mesh); });
            });
            res.builds.push_back({"BVH8 flattened", ms_flat, wide_bytes(flat)});
            const auto& es = embree_flat->stats();
            res.builds.push_back({"Embree flattened", ms_eflat, std::size_t(es.buffer_bytes + es.bvh_bytes)});
            methods.push_back(Method{
                "BVH8 flattened",
                [&](std::span<const Ray> rays, bool any) {
                    flat_hits.resize(rays.size());
                    any ? occluded(flat, rays, std::span<Hit>(flat_hits), with_isa(TraceOptions{}, active_isa()))
                        : intersect(flat, rays, std::span<Hit>(flat_hits), with_isa(TraceOptions{}, active_isa()));
                },
                [&](std::size_t i) { return scene_hit_of(flat_hits[i], desc, first); }});
            methods.push_back(Method{"Embree flattened",
                                     [&](std::span<const Ray> rays, bool any) {
                                         if (any) {
                                             flat_occ.resize(rays.size());
                                             embree_flat->occluded(rays, flat_occ);
                                         } else {
                                             embree_flat_hits.resize(rays.size());
                                             embree_flat->intersect(rays, embree_flat_hits);
                                         }
                                     },
                                     [&](std::size_t i) { return scene_hit_of(embree_flat_hits[i], desc, first); }});
        } else {
            // Bytes per triangle of the bottom trees (as built here) times the flattened triangles.
            double tree_bytes = 0;
            for (const BottomLevel<8>& bl : ours.bottoms()) tree_bytes += double(wide_bytes(std::get<Bvh8>(bl.tree)));
            const double per_tri = tree_bytes / double(std::max<std::size_t>(1, res.stats.primitives));
            res.builds.push_back({"BVH8 flattened", 0, std::size_t(per_tri * double(flat_tris)), true});
        }
    }

    const Aabb box = world_bounds(desc);
    const std::vector<Ray> rays[2] = {workloads::scene_camera_rays(desc, c.rays),
                                      workloads::interior_rays(box, c.rays, 9)};
    res.rays = rays[1].size();
    const char* kinds[2] = {"primary", "incoherent"};
    std::vector<Method*> ptrs;
    for (Method& m : methods) ptrs.push_back(&m);
    for (int k = 0; k < 2; ++k)
        for (bool any : {false, true}) {
            progress(std::string("timing ") + kinds[k] + (any ? " any hit" : " closest hit"), true);
            const auto mr = time_methods(ptrs, rays[k], any, c.reps);
            for (std::size_t i = 0; i < methods.size(); ++i)
                res.speed.push_back({methods[i].name, kinds[k], any ? "any" : "closest", mr[i]});
        }

    // Agreement of the closest hits with ours (child corners): the brute force on a sample (it costs every
    // instanced primitive per ray), the others on every ray, their differences refereed in double.
    const reference::SceneReferencer referee(desc);
    for (int k = 0; k < 2; ++k) {
        for (Method& m : methods) m.trace(rays[k], false);
        for (std::size_t i = 1; i < methods.size(); ++i)
            agreement(methods[i].name, kinds[k], rays[k], methods[0], methods[i].hit, &referee, res.agreement);
        const double budget = 2e9 / double(std::max<std::size_t>(1, flat_tris + desc.planes.size()));
        const std::size_t n =
            std::min<std::size_t>({c.sample, rays[k].size(), std::max<std::size_t>(16, std::size_t(budget))});
        progress(std::string("brute force on ") + std::to_string(n) + " " + kinds[k] + " rays", true);
        std::vector<SceneHit> brute(n);
        brute_force_intersect(desc, std::span<const Ray>(rays[k]).first(n), brute);
        agreement(
            "brute force", kinds[k], std::span<const Ray>(rays[k]).first(n), methods[0],
            [&](std::size_t i) { return brute[i]; }, nullptr, res.agreement);
    }

    for (const Geometry& g : desc.geometries)
        if (const auto* s = std::get_if<SphereSet>(&g); s && !s->spheres.empty()) {
            tessellation(c, *s, res);
            progress("sphere precision study", true);
            res.sphere_precision = sphere_precision_study(c.quick ? 500 : 2000);
            break;
        }
    if (!desc.planes.empty()) planes(c, desc, rays, res);
    return res;
}

}  // namespace simdbvh::lab
