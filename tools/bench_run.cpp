// SPDX-License-Identifier: MIT
// simdbvh bench, the run. Fair comparison: the same rays and mesh for every
// method; an untimed warm-up trace before each timed row, then the median of
// c.reps traces; builds: the first (cold) and the median of c.build_reps more
// (warm), for every method, Embree included.
#include "bench_run.h"

#include <algorithm>

#include "common.h"
#include "methods.h"
#include "simdbvh/scene/rays.h"

namespace simdbvh::cli {

namespace {

using scene::RayKind;
constexpr RayKind kKinds[] = {RayKind::primary, RayKind::incoherent, RayKind::diffuse};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

// The rays of one scene and the brute-force reference on the first `sample` of each kind.
struct BenchRays {
    std::vector<std::vector<Ray>> rays;
    std::vector<std::vector<Hit>> closest, any;  // reference per kind
};

BenchRays make_rays(const BenchConfig& c, const Mesh& mesh) {
    BenchRays b;
    for (RayKind k : kKinds) {
        progress("generating " + std::to_string(c.rays) + " " + std::string(scene::name(k)) + " rays", true);
        b.rays.push_back(scene::generate_rays(mesh, k, c.rays, 42));
    }
    progress("brute-force reference on " + std::to_string(c.sample) + " rays per kind (" +
                 std::to_string(c.threads_all) + " threads)",
             true);
    MethodSpec spec;
    spec.method = "brute";
    spec.threads = c.threads_all;
    auto brute = make_tracer(mesh, spec);
    b.closest.resize(3);
    b.any.resize(3);
    for (int k = 0; k < 3; ++k) {
        const std::size_t s = std::min(c.sample, b.rays[k].size());
        b.closest[k].resize(s);
        b.any[k].resize(s);
        brute->trace(std::span(b.rays[k]).first(s), b.closest[k], false, nullptr);
        brute->trace(std::span(b.rays[k]).first(s), b.any[k], true, nullptr);
    }
    return b;
}

// brute, bvh2, bvhN per supported ISA, Embree medium/high x default/robust.
std::vector<MethodSpec> bench_methods(bool trees_only) {
    std::vector<MethodSpec> methods;
    MethodSpec m;
    m.method = "brute";
    if (!trees_only) methods.push_back(m);
    m.method = "bvh2";
    methods.push_back(m);
    for (const char* wide : kWideMethods)
        for (Isa isa : kAllIsas) {
            if (!supported(isa)) {
                progress("skipping " + std::string(wide) + "/" + std::string(name(isa)) + ": this CPU lacks it", true);
                continue;
            }
            m.method = wide;
            m.isa = isa;
            methods.push_back(m);
        }
    if (trees_only) return methods;
    for (const char* q : {"medium", "high"})
        for (bool robust : {false, true}) {
            m = MethodSpec{};
            m.method = "embree";
            m.quality = q;
            m.robust = robust;
            methods.push_back(m);
        }
    return methods;
}

// One method built with `threads`: the cold tracer (kept for tracing) and the warm build times.
struct Built {
    std::unique_ptr<Tracer> tracer;
    double cold_ms = 0, warm_ms = 0, collapse_ms = 0;
};

Built build_method(const Mesh& mesh, MethodSpec spec, int threads, int warm_reps) {
    spec.threads = threads;
    spec.build.threads = threads;
    progress("building " + spec.label() + " (" + std::to_string(threads) + " thread" + (threads > 1 ? "s)" : ")"), true);
    Built b;
    b.tracer = make_tracer(mesh, spec);
    b.cold_ms = b.tracer->build_ms;
    std::vector<double> warm, collapse;
    for (int r = 0; r < (spec.method == "brute" ? 0 : warm_reps); ++r) {
        auto again = make_tracer(mesh, spec);
        warm.push_back(again->build_ms);
        collapse.push_back(again->collapse_ms);
    }
    b.warm_ms = warm.empty() ? b.cold_ms : median(warm);
    b.collapse_ms = collapse.empty() ? b.tracer->collapse_ms : median(collapse);
    return b;
}

// Median Mrays/s of c.reps timed traces after one untimed warm-up.
double time_rays(Tracer& t, std::span<const Ray> rays, std::span<Hit> hits, bool any, int reps) {
    t.trace(rays, hits, any, nullptr);
    std::vector<double> mr;
    for (int r = 0; r < reps; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        t.trace(rays, hits, any, nullptr);
        mr.push_back(double(rays.size()) / seconds_since(t0) / 1e6);
    }
    return median(mr);
}

// The traversal counters per ray on the first c.stats_rays rays (our trees only).
void count_visits(Tracer& t, std::span<const Ray> rays, bool any, Record& rec) {
    std::vector<Hit> hits(rays.size());
    TraceStats st;
    t.trace(rays, hits, any, &st);
    if (!st.rays) return;
    rec.nodes_per_ray = double(st.nodes_visited) / double(st.rays);
    rec.box_tests_per_ray = double(st.box_tests) / double(st.rays);
}

class MethodBench {
public:
    MethodBench(const BenchConfig& c, const Mesh& mesh, const std::string& scene, const BenchRays& rays)
        : c_(c), mesh_(mesh), scene_(scene), r_(rays), hits_(c.rays) {}

    // Every row of one method: kinds x queries x {1 thread, all cores (unless one_thread)}.
    void run(const MethodSpec& base, bool one_thread, std::vector<Record>& out) {
        Built one = build_method(mesh_, base, 1, c_.build_reps);
        Built all;
        const bool many = c_.threads_all > 1 && !one_thread;
        if (many) all = build_method(mesh_, base, c_.threads_all, base.method == "brute" ? 0 : c_.build_reps);
        for (int k = 0; k < 3; ++k)
            for (bool any : {false, true}) {
                out.push_back(row(base, one, all, *one.tracer, 1, k, any));
                if (many) out.push_back(row(base, one, all, *all.tracer, c_.threads_all, k, any));
            }
        progress("done " + base.label(), true);
    }

private:
    Record row(const MethodSpec& base, const Built& one, const Built& all, Tracer& t, int threads, int k, bool any) {
        const bool brute = base.method == "brute";
        // Brute force is timed on a small slice of the sample only (it is O(triangles) per ray).
        const std::size_t brute_n = std::min<std::size_t>(r_.closest[k].size(), 100);
        const std::span<const Ray> rs = brute ? std::span<const Ray>(r_.rays[k]).first(brute_n) : std::span<const Ray>(r_.rays[k]);
        const std::span<const Hit> ref =
            std::span<const Hit>(any ? r_.any[k] : r_.closest[k]).first(std::min(rs.size(), r_.closest[k].size()));
        Record rec;
        rec.scene = scene_;
        rec.method = base.method == "embree" ? base.label() : base.method;
        rec.isa = base.isa_name();
        rec.builder = base.builder_name();
        rec.width = base.method == "bvh2" ? 2 : base.width();
        rec.ray_kind = std::string(scene::name(kKinds[k]));
        rec.query = any ? "any" : "closest";
        rec.threads = threads;
        rec.mrays_per_s = time_rays(t, rs, std::span(hits_).first(rs.size()), any, brute ? 1 : c_.reps);
        rec.build_ms = one.cold_ms;
        rec.build_ms_warm = one.warm_ms;
        rec.build_ms_all = all.tracer ? all.cold_ms : one.cold_ms;
        rec.build_ms_all_warm = all.tracer ? all.warm_ms : one.warm_ms;
        rec.collapse_ms = one.collapse_ms;
        rec.bytes_per_triangle = t.bytes_per_triangle;
        rec.sah_cost = t.sah_cost;
        rec.rays = rs.size();
        rec.sample = ref.size();
        rec.tally = classify_sample(mesh_, std::span<const Ray>(r_.rays[k]).first(ref.size()), ref,
                                    std::span<const Hit>(hits_).first(ref.size()), any);
        rec.agreement = rec.tally.agreement_rate();
        if (rec.width && threads == 1)
            count_visits(t, std::span<const Ray>(r_.rays[k]).first(std::min(c_.stats_rays, r_.rays[k].size())), any, rec);
        return rec;
    }

    const BenchConfig& c_;
    const Mesh& mesh_;
    std::string scene_;
    const BenchRays& r_;
    std::vector<Hit> hits_;
};

}  // namespace

BenchResults run_bench(const BenchConfig& c, const Mesh& mesh, const std::vector<NamedMesh>& width_meshes) {
    BenchResults out;
    {
        const BenchRays rays = make_rays(c, mesh);
        MethodBench mb(c, mesh, c.scene, rays);
        for (const MethodSpec& m : bench_methods(false)) mb.run(m, false, out.records);
    }
    out.width_scene_sizes.emplace_back(c.scene, mesh.size());
    for (const Record& r : out.records)
        if (r.width && r.threads == 1) out.widths.push_back(r);
    for (const NamedMesh& w : width_meshes) {
        progress("wide-vs-binary scene: " + w.name, true);
        const BenchRays rays = make_rays(c, w.mesh);
        MethodBench mb(c, w.mesh, w.name, rays);
        for (const MethodSpec& m : bench_methods(true)) mb.run(m, true, out.widths);
        out.width_scene_sizes.emplace_back(w.name, w.mesh.size());
    }
    return out;
}

}  // namespace simdbvh::cli
