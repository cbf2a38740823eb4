// simdbvh build: build a tree once and save it with its mesh
// (docs/saved_format.md); `trace` and `info` then take the file as --scene.
#include <chrono>
#include <iostream>

#include "common.h"
#include "methods.h"
#include "outputs.h"
#include "saved.h"
#include "scene_cmds.h"
#include "simdbvh/io/output.h"
#include "simdbvh/store/store.h"

namespace simdbvh::cli {

namespace {

struct BuildConfig {
    std::string scene, out;
    MethodSpec spec;
};

struct Built {
    std::size_t triangles = 0;
    double build_ms = 0, save_ms = 0;
    std::uint64_t bytes = 0;
    double sah_cost = 0;
    std::size_t nodes = 0;
};

BuildConfig parse(const std::vector<std::string>& args) {
    std::set<std::string> valued{"scene", "out"}, flags;
    add_method_options(valued, flags);
    const Options o("build", args, valued, flags);
    BuildConfig c{o.require("scene"), o.require("out"), parse_method(o, "bvh8")};
    if (c.spec.method != "bvh2" && !is_wide(c.spec.method))
        throw UsageError("build saves --method bvh2, bvh4, bvh8 or bvh16 (not " + c.spec.method + ")");
    if (c.spec.method == "bvh2" && c.spec.wide.quantized_nodes)
        throw UsageError("--nodes quantized applies to bvh8 and bvh16");
    if (is_scene_desc(c.scene)) throw UsageError("build takes a mesh scene (not a scene of instances)");
    if (is_saved_scene(c.scene)) throw UsageError("--scene " + c.scene + " is already a saved tree");
    check_outputs({{"--out", c.out}}, {.scenes = {{"--scene", c.scene}}});
    return c;
}

template <class T>
Built build_and_save(const Mesh& mesh, const BuildConfig& c) {
    Built r;
    r.triangles = mesh.size();
    const auto t0 = std::chrono::steady_clock::now();
    T bvh;
    if constexpr (std::is_same_v<T, Bvh2>) {
        bvh = Bvh2::build(mesh, c.spec.build);
    } else {
        WideOptions wo = c.spec.wide;
        wo.threads = c.spec.build.threads;  // collapse + pack on the build's threads too
        bvh = T::build(mesh, c.spec.build, wo);
    }
    r.build_ms = seconds_since(t0) * 1e3;
    r.sah_cost = bvh.stats().sah_cost;
    r.nodes = bvh.stats().nodes;
    progress("saving " + c.out + " ...");
    const auto t1 = std::chrono::steady_clock::now();
    const auto bytes = save_bytes(bvh, mesh);
    io::write_file_atomic(c.out, bytes);
    r.save_ms = seconds_since(t1) * 1e3;
    r.bytes = bytes.size();
    return r;
}

Built run(const BuildConfig& c) {
    const Mesh mesh = load_scene_with_progress(c.scene);
    progress("building " + c.spec.label() + " ...");
    const std::string& m = c.spec.method;
    if (m == "bvh2") return build_and_save<Bvh2>(mesh, c);
    return with_width(c.spec.width(), [&](auto n) { return build_and_save<BvhN<decltype(n)::value>>(mesh, c); });
}

void report(const BuildConfig& c, const Built& r) {
    std::cout << "method " << c.spec.label() << (c.spec.wide.quantized_nodes ? " (quantized nodes)" : "")
              << "  threads " << c.spec.build.threads << "\n"
              << "triangles " << r.triangles << "  nodes " << r.nodes << "  SAH cost " << r.sah_cost << "\n"
              << "build " << r.build_ms << " ms  save " << r.save_ms << " ms\n"
              << "wrote " << r.bytes << " bytes to " << c.out << "\n";
}

}  // namespace

int cmd_build(const std::vector<std::string>& args) {
    const BuildConfig c = parse(args);
    report(c, run(c));
    return 0;
}

}  // namespace simdbvh::cli
