// Tracing and describing a saved tree: the file is loaded (mapped, checked)
// and traced like a built one; nothing is built.
#include "saved.h"

#include <chrono>
#include <cstdio>

#include "common.h"
#include "printable.h"
#include "simdbvh/store/store.h"

namespace simdbvh::cli {
namespace {

template <class T>
std::unique_ptr<Tracer> make_saved_tracer(const std::string& file, const MethodSpec& s) {
    const auto t0 = std::chrono::steady_clock::now();
    T bvh = load<T>(file);
    return std::make_unique<TreeTracer<T>>(std::move(bvh), s, seconds_since(t0) * 1e3);
}

}  // namespace

bool is_saved_scene(const std::string& name) { return is_saved_file(name); }

std::unique_ptr<Tracer> load_saved_tracer(const std::string& file, MethodSpec& spec, bool method_given) {
    const SavedInfo in = inspect(file);
    const std::string method = "bvh" + std::to_string(in.width);
    if (method_given && spec.method != method)
        throw Error(printable(file) + ": holds a " + kind_name(in) + ", not the --method " + spec.method +
                    " asked for (omit --method to trace what it holds)");
    spec.method = method;
    spec.wide.quantized_nodes = in.quantized;
    if (in.width == 2) return make_saved_tracer<Bvh2>(file, spec);
    return with_width(in.width, [&](auto n) -> std::unique_ptr<Tracer> {
        return make_saved_tracer<BvhN<decltype(n)::value>>(file, spec);
    });
}

int info_saved(const std::string& file) {
    const SavedInfo in = inspect(file);
    // A full load checks the checksum and the structure: info says the file is sound, not only its header.
    const auto t0 = std::chrono::steady_clock::now();
    if (in.width == 2) (void)load<Bvh2>(file);
    else with_width(in.width, [&](auto n) { (void)load<BvhN<decltype(n)::value>>(file); });
    const double load_ms = seconds_since(t0) * 1e3;
    const Aabb& b = in.bounds;
    std::printf("saved file   %s\n", printable(file).c_str());
    std::printf("format       version %u, %llu bytes, checksum ok (load %.1f ms)\n", in.version,
                static_cast<unsigned long long>(in.file_bytes), load_ms);
    std::printf("tree         %s\n", kind_name(in).c_str());
    std::printf("triangles    %llu\n", static_cast<unsigned long long>(in.triangles));
    std::printf("vertices     %llu\n", static_cast<unsigned long long>(in.vertices));
    std::printf("mesh hash    %016llx\n", static_cast<unsigned long long>(in.mesh_hash));
    std::printf("bounds       [%g %g %g] - [%g %g %g]\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
    std::printf("bytes        nodes %llu, quantized nodes %llu, triangles %llu, mesh %llu\n",
                static_cast<unsigned long long>(in.node_bytes), static_cast<unsigned long long>(in.qnode_bytes),
                static_cast<unsigned long long>(in.block_bytes), static_cast<unsigned long long>(in.mesh_bytes));
    if (in.width == 2) {
        const BuildStats& s = in.bvh2_stats;
        std::printf("bvh2         %s, %d bins, max leaf %d\n", std::string(name(in.build.builder)).c_str(),
                    in.build.bins, in.build.max_leaf_size);
        std::printf(
            "  build ms        %.1f\n  nodes           %zu\n  leaves          %zu\n  depth           %d\n"
            "  SAH cost        %.3f\n  bytes/triangle  %.1f\n",
            s.build_ms, s.nodes, s.leaves, s.depth, s.sah_cost, s.bytes_per_triangle);
    } else {
        const WideStats& e = in.wide_stats;
        std::printf("bvh%d         %s collapse, max leaf %d%s\n", in.width, std::string(name(in.wide.collapse)).c_str(),
                    in.wide.max_leaf_size, in.quantized ? ", quantized nodes" : "");
        std::printf(
            "  build ms        %.1f (collapse + pack)\n  nodes           %zu\n  leaves          %zu\n"
            "  triangle blocks %zu\n  depth           %d\n  SAH cost        %.3f\n  bytes/triangle  %.1f\n"
            "  fill rate       %.1f%%\n",
            e.build_ms, e.nodes, e.leaves, e.blocks, e.depth, e.sah_cost, e.bytes_per_triangle, 100.0 * e.fill_rate);
    }
    return 0;
}

}  // namespace simdbvh::cli
