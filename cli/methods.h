#pragma once
// The methods the CLI can run, behind one interface: auto (Accel: the method
// the cost model picks), brute, brute8, bvh2, bvh4, bvh8, bvh16 (the wide
// BVHs, all collapsed from the same BVH2), embree, spheres.
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "options.h"
#include "simdbvh/bvh8/bvh8.h"

namespace simdbvh::cli {

struct MethodSpec {
    std::string method = "bvh2";    // auto | brute | brute8 | bvh2 | bvh4 | bvh8 | bvh16 | embree | spheres
    std::size_t expected_rays = 0;  // auto: the rays the choice is made for
    Isa isa = Isa::scalar;          // the wide BVHs only (bvh2 and brute are scalar)
    bool isa_auto = false;          // no --isa: the wide BVHs choose by speed (bvh8.h, traversal_isa_choice)
    BuildOptions build;
    WideOptions wide;  // collapse options of bvh4, bvh8, bvh16 (--nodes quantized: label bvh8q/...)
    TriangleTest test = TriangleTest::watertight;
    Packets packets = Packets::automatic;  // the wide BVHs (and auto's): --packets auto | off | on
    Reorder reorder = Reorder::automatic;  // the wide BVHs (and auto's): --reorder auto | off | on
    BoxTest box = BoxTest::conservative;   // bvh2 only (bvh8 always conservative)
    std::string quality = "medium";        // embree: medium | high
    bool robust = false;                   // embree: RTC_SCENE_FLAG_ROBUST
    int threads = 1;                       // trace (and build) threads

    int width() const;          // 4, 8, 16 for bvh4, bvh8, bvh16; 0 for the others
    std::string label() const;  // e.g. "bvh8/avx2" ("bvh8" without --isa), "embree/medium/robust"
    // The ISA a trace of this query runs with (the wide trees without --isa: their choice for that query).
    std::string isa_name(bool any_hit = false) const;
    // Why that ISA, for the wide trees without --isa: " (forced)", " (timed on any-hit traces)", or " (the
    // widest detected, not timed: ...)"; "" for the other methods.
    std::string isa_note(bool any_hit) const;
    std::string builder_name() const;
};

class Tracer {
public:
    virtual ~Tracer() = default;
    virtual void trace(std::span<const Ray> rays, std::span<Hit> hits, bool any_hit, TraceStats* stats) = 0;
    // The ISA the last traces of this query ran with (auto: that of the method it built).
    virtual std::string ran_isa(const MethodSpec& spec, bool any_hit) const { return spec.isa_name(any_hit); }
    double build_ms = 0;
    double collapse_ms = 0;  // the wide BVHs: collapse + pack (part of build_ms)
    double bytes_per_triangle = 0;
    double sah_cost = 0;
    int depth = 0;
    std::size_t nodes = 0;
    std::string chosen;  // auto: what it chose and why (the predicted time of every candidate)
};

// The trace options of a tree method: the spec's tests, the counters (one thread when counting), --isa's ISA
// (unset without it: by speed).
TraceOptions trace_options(const MethodSpec& s, TraceStats* stats);

// One trace of a tree built or loaded for `spec` (the tracers of methods.cpp and saved.cpp): the wide trees
// with --isa's ISA, or by speed without it; the binary trees (BVH2, the sphere hierarchy) on their one path.
template <class Tree>
void trace_tree(const Tree& tree, const MethodSpec& spec, std::span<const Ray> rays, std::span<Hit> hits, bool any,
                TraceStats* stats) {
    const TraceOptions o = trace_options(spec, stats);
    any ? occluded(tree, rays, hits, o) : intersect(tree, rays, hits, o);
}

// A tracer over one built or loaded tree: trace_tree traces it, its stats give the figures; build_ms is what
// the caller timed (a build, or a load), else the time the tree's own stats give.
template <class Tree>
class TreeTracer final : public Tracer {
public:
    TreeTracer(Tree tree, const MethodSpec& s) : TreeTracer(std::move(tree), s, 0.0) {
        build_ms = tree_.stats().build_ms;
    }
    TreeTracer(Tree tree, const MethodSpec& s, double ms) : spec_(s), tree_(std::move(tree)) {
        build_ms = ms;
        const auto& st = tree_.stats();
        bytes_per_triangle = st.bytes_per_triangle;
        sah_cost = st.sah_cost;
        depth = st.depth;
        nodes = st.nodes;
    }
    void trace(std::span<const Ray> rays, std::span<Hit> hits, bool any, TraceStats* stats) override {
        trace_tree(tree_, spec_, rays, hits, any, stats);
    }

private:
    MethodSpec spec_;
    Tree tree_;
};

// The wide methods, narrowest first.
std::vector<std::string> wide_methods();  // the registry's wide trees, narrowest first
bool is_wide(const std::string& method);

// Options every tracing command accepts: --method --isa --builder --bins
// --collapse --nodes --test --box --quality --robust --threads.
void add_method_options(std::set<std::string>& valued, std::set<std::string>& flags);
// `fallback`: the method without --method (trace: auto).
MethodSpec parse_method(const Options& o, const std::string& fallback = "bvh2");
std::unique_ptr<Tracer> make_tracer(const Mesh& mesh, const MethodSpec& spec);

}  // namespace simdbvh::cli
