// info and trace for scene descriptions: load (built-in or JSON), build the
// two-level scene, report its sizes, trace a ray file into a scene hit file.
#include "scene_cmds.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>

#include "common.h"
#include "image.h"
#include "outputs.h"
#include "printable.h"
#include "simdbvh/kernels/error.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/io/ray_files.h"
#include "simdbvh/workloads/scene_desc.h"
#include "simdbvh/io/scene_hits.h"

namespace simdbvh::cli {

namespace {

int scene_width(const MethodSpec& spec) {
    if (spec.width()) return spec.width();
    // bvh2 and auto (the defaults of info and trace): a scene's bottom-level trees are BVH8s.
    if (spec.method == "bvh2" || spec.method == "auto" || spec.method == "brute") return 8;
    throw UsageError("scenes run on --method bvh4, bvh8, bvh16 or brute (not " + spec.method + ")");
}

SceneOptions scene_options(const MethodSpec& spec, InstanceBounds bounds) {
    SceneOptions so;
    so.bounds = bounds;
    so.bottom = spec.build;
    so.wide = spec.wide;
    so.top = spec.build;
    return so;
}

template <int N>
void print_info(const SceneDesc& desc, const MethodSpec& spec, InstanceBounds bounds) {
    progress("building the scene (BVH" + std::to_string(N) + " bottom levels) ...");
    const SceneBvhN<N> s = SceneBvhN<N>::build(desc, scene_options(spec, bounds));
    const SceneStats& st = s.stats();
    std::printf("geometries   %zu\ninstances    %zu\nplanes       %zu\n", st.geometries, st.instances, st.planes);
    std::printf("primitives   %zu (each geometry once)\n", st.primitives);
    std::printf("flattened    %zu primitives (every instance baked into the world)\n", st.instanced_primitives);
    std::printf("width        %d (bottom levels of meshes)\n", N);
    std::printf("bounds       %s\n", bounds == InstanceBounds::corners ? "corners" : "child-corners");
    std::printf("box volume   corners %.6g  child-corners %.6g (sum over instances)\n", st.volume_corners,
                st.volume_child_corners);
    std::printf("bytes        %zu (bottom levels + top level + instances)\n", st.bytes);
    std::printf("bytes/inst   %zu\n", st.bytes_per_instance);
    std::printf("max cond     %.3g\n", st.max_cond);
    std::printf("build ms     %.1f\n", st.build_ms);
}

template <int N>
void trace_with(const SceneDesc& desc, const MethodSpec& spec, InstanceBounds bounds, std::span<const Ray> rays,
                std::span<SceneHit> hits, bool any, double* build_ms) {
    const SceneBvhN<N> s = SceneBvhN<N>::build(desc, scene_options(spec, bounds));
    *build_ms = s.stats().build_ms;
    progress("tracing ...");
    any ? occluded(s, rays, hits, {.isa = spec.isa, .threads = spec.threads})
        : intersect(s, rays, hits, {.isa = spec.isa, .threads = spec.threads});
}

// A light colour per instance (a hash of its id); planes light grey.
Vec3 tint(const SceneHit& h) {
    if (h.geom == kNoGeometry) return {0.8f, 0.8f, 0.8f};
    std::uint32_t x = h.inst * 0x9E3779B1u + 0x7F4A7C15u;
    x ^= x >> 15;
    x *= 0x2C1B3C6Du;
    x ^= x >> 12;
    return {0.45f + 0.55f * float(x & 255) / 255.0f, 0.45f + 0.55f * float((x >> 8) & 255) / 255.0f,
            0.45f + 0.55f * float((x >> 16) & 255) / 255.0f};
}

}  // namespace

bool is_scene_desc(const std::string& name) {
    return workloads::is_builtin_scene(name) || (name.size() > 5 && name.substr(name.size() - 5) == ".json");
}

void refuse_mesh_options(const Options& o, const std::string& name) {
    // What the scene layer has no choice of: its triangle and box tests are its own, it has no Embree
    // settings, packets, reordering or counters, and loads no mesh with --drop-invalid.
    for (const char* opt : {"test", "box", "quality", "robust", "packets", "reorder", "stats", "drop-invalid",
                            "expected-rays", "heatmap"})
        if (o.has(opt))
            throw UsageError(std::string("--") + opt + " does not apply to scenes (" + name +
                             "; room, instances-N, spheres-N and *.json run on the scene layer)");
}

InstanceBounds parse_instance_bounds(const Options& o) {
    const std::string b = o.get("instance-bounds", "child-corners");
    if (b == "corners") return InstanceBounds::corners;
    if (b == "child-corners") return InstanceBounds::child_corners;
    throw UsageError("unknown --instance-bounds '" + b + "' (corners, child-corners)");
}

int info_scene(const std::string& name, const MethodSpec& spec, InstanceBounds bounds) {
    const int width = scene_width(spec);
    progress("loading " + name + " ...");
    const SceneDesc desc = workloads::load_scene_desc(name);
    std::printf("scene        %s\n", printable(name).c_str());
    std::printf("isa          %s\n", std::string(simdbvh::name(spec.isa)).c_str());
    with_width(width, [&](auto n) { print_info<decltype(n)::value>(desc, spec, bounds); });
    return 0;
}

int trace_scene(const Options& o, const std::string& name, const std::string& rays_file, const std::string& out,
                const MethodSpec& spec, bool any, InstanceBounds bounds) {
    const int width = scene_width(spec);
    refuse_mesh_options(o, name);
    check_outputs({{"--out", out}}, {.files = {{"--rays", rays_file}}, .scenes = {{"--scene", name}}});
    const auto rays = io::read_rays(rays_file);  // a bad ray file fails before any expensive work
    progress("loading " + name + " ...");
    const SceneDesc desc = workloads::load_scene_desc(name);
    std::vector<SceneHit> hits(rays.size());
    double build_ms = 0;
    const auto t0 = std::chrono::steady_clock::now();
    if (spec.method == "brute") {
        any ? brute_force_occluded(desc, rays, hits) : brute_force_intersect(desc, rays, hits);
    } else {
        with_width(width,
                   [&](auto n) { trace_with<decltype(n)::value>(desc, spec, bounds, rays, hits, any, &build_ms); });
    }
    const double secs = seconds_since(t0) - build_ms / 1e3;
    io::write_scene_hits(out, hits);
    std::size_t n_hit = 0;
    for (const SceneHit& h : hits) n_hit += h.hit();
    std::cout << "scene " << name << "  method " << (spec.method == "brute" ? "brute" : "bvh" + std::to_string(width))
              << "  isa " << simdbvh::name(spec.isa) << "  query " << (any ? "any" : "closest") << "  threads "
              << spec.threads << "\n"
              << "rays " << rays.size() << "  hits " << n_hit << "  build " << build_ms << " ms  trace " << secs * 1e3
              << " ms\nwrote " << hits.size() << " scene hits (24-byte records) to " << out << "\n";
    return 0;
}

Mesh scene_bounds_proxy(const std::string& name) {
    const SceneDesc desc = workloads::load_scene_desc(name);
    const Aabb b = world_bounds(desc);
    if (b.is_empty()) throw Error(name + ": the scene has no bounded part (planes only): no rays to aim");
    Mesh m;
    m.positions = {b.lo, b.hi};
    m.triangles = {{0, 1, 1}};  // degenerate: only its bounds matter
    return m;
}

Image render_scene_image(const std::string& name, const MethodSpec& spec, InstanceBounds bounds, int w, int h) {
    const int width = scene_width(spec);
    const SceneDesc desc = workloads::load_scene_desc(name);
    const workloads::Camera cam = workloads::scene_camera(desc, w, h);
    const auto rays = workloads::primary_rays(cam);
    std::vector<SceneHit> hits(rays.size());
    double build_ms = 0;
    if (spec.method == "brute") brute_force_intersect(desc, rays, hits);
    else
        with_width(width,
                   [&](auto n) { trace_with<decltype(n)::value>(desc, spec, bounds, rays, hits, false, &build_ms); });
    Image img{w, h, std::vector<std::uint8_t>(std::size_t(w) * std::size_t(h) * 3, 0)};
    for (std::size_t i = 0; i < hits.size(); ++i) {
        if (!hits[i].hit()) continue;
        const Vec3 n = hit_normal(desc, rays[i], hits[i]);
        const float ln = length(n), ld = length(rays[i].dir);
        const float c = ln > 0 && ld > 0 ? std::fabs(dot(n, rays[i].dir)) / (ln * ld) : 0.0f;
        const float shade = 0.15f + 0.85f * c;
        const Vec3 col = tint(hits[i]) * shade;
        for (int k = 0; k < 3; ++k) img.rgb[3 * i + k] = std::uint8_t(std::clamp(255.0f * col[k], 0.0f, 255.0f));
    }
    return img;
}

int render_scene(const std::string& name, const MethodSpec& spec, InstanceBounds bounds, int w, int h,
                 const std::string& out) {
    const int width = scene_width(spec);
    write_png(out, render_scene_image(name, spec, bounds, w, h));
    std::cout << "scene " << name << "  method " << (spec.method == "brute" ? "brute" : "bvh" + std::to_string(width))
              << "  isa " << simdbvh::name(spec.isa) << "  wrote " << w << "x" << h << " render to " << out << "\n";
    return 0;
}

}  // namespace simdbvh::cli
