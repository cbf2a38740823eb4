// SPDX-License-Identifier: MIT
// simdbvh bench, the run. Fair comparison: the same rays and mesh for every
// method; an untimed warm-up trace of every method before each row group, then
// c.reps timed traces, the methods interleaved, the median per method; builds:
// the first (cold) and the median of c.build_reps more (warm), for every
// method, Embree included.
#include "lab.h"
#include "bench_run.h"

#include <algorithm>
#include <chrono>

#include "common.h"
#include "methods.h"
#include "report.h"
#include "simdbvh/workloads/rays.h"

namespace simdbvh::lab {

namespace {

using workloads::RayKind;
constexpr RayKind kKinds[] = {RayKind::primary, RayKind::incoherent, RayKind::diffuse};

// The rays of one scene and the brute-force reference on the first `sample` of each kind.
struct BenchRays {
    std::vector<std::vector<Ray>> rays;
    std::vector<std::vector<Hit>> closest, any;  // reference per kind
};

BenchRays make_rays(const BenchConfig& c, const Mesh& mesh) {
    BenchRays b;
    for (RayKind k : kKinds) {
        progress("generating " + std::to_string(c.rays) + " " + std::string(workloads::name(k)) + " rays", true);
        b.rays.push_back(workloads::generate_rays(mesh, k, c.rays, 42));
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
    for (const std::string& wide : wide_methods())
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
    progress("building " + spec.label() + " (" + std::to_string(threads) + " thread" + (threads > 1 ? "s)" : ")"),
             true);
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

// The traversal counters per ray (our trees only).
void count_visits(Tracer& t, std::span<const Ray> rays, bool any, Record& rec) {
    std::vector<Hit> hits(rays.size());
    TraceStats st;
    t.trace(rays, hits, any, &st);
    if (!st.rays) return;
    rec.nodes_per_ray = double(st.nodes_visited) / double(st.rays);
    rec.box_tests_per_ray = double(st.box_tests) / double(st.rays);
}

// Every k-th ray, at most n (a primary set's first rows may all miss).
std::vector<Ray> spaced(const std::vector<Ray>& rays, std::size_t n) {
    std::vector<Ray> out;
    const std::size_t stride = std::max<std::size_t>(1, rays.size() / std::max<std::size_t>(1, n));
    for (std::size_t i = 0; i < rays.size() && out.size() < n; i += stride) out.push_back(rays[i]);
    return out;
}

// All methods on one scene. The methods are built first (cold, then warm) and
// kept; each row group (ray kind x query x thread count) then warms every
// method up and times the methods in turn, repetition by repetition, so a
// period of load from elsewhere on a shared machine falls on all of them
// instead of on one: the ratios within a run stay comparable.
class SceneBench {
public:
    SceneBench(const BenchConfig& c, const Mesh& mesh, const std::string& scene, const BenchRays& rays)
        : c_(c), mesh_(mesh), scene_(scene), r_(rays), hits_(c.rays) {
        for (const auto& k : r_.rays) stats_.push_back(spaced(k, c.stats_rays));
    }

    // Rows for kinds x queries x {1 thread, all cores (unless one_thread)}.
    void run(const std::vector<MethodSpec>& methods, bool one_thread, std::vector<Record>& out) {
        const bool many = c_.threads_all > 1 && !one_thread;
        std::vector<Built> one, all;
        for (const MethodSpec& m : methods) one.push_back(build_method(mesh_, m, 1, c_.build_reps));
        if (many)
            for (const MethodSpec& m : methods)
                all.push_back(build_method(mesh_, m, c_.threads_all, m.method == "brute" ? 0 : c_.build_reps));
        // What remains, from the groups timed so far (each group's share of the rows is the same).
        const int groups = (many ? 2 : 1) * 3 * 2;
        int done = 0;
        const auto t0 = std::chrono::steady_clock::now();
        for (int threads : {1, c_.threads_all}) {
            if (threads != 1 && !many) break;
            progress("timing " + std::to_string(methods.size()) + " methods on " + scene_ + ", " +
                         std::to_string(threads) + " thread" + (threads > 1 ? "s" : ""),
                     true);
            for (int k = 0; k < 3; ++k)
                for (bool any : {false, true}) {
                    group(methods, one, all, threads, k, any, out);
                    ++done;
                    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                    if (done < groups)
                        progress("  row group " + std::to_string(done) + "/" + std::to_string(groups) + " in " +
                                     fmt("%.0f", s) + " s; about " + fmt("%.0f", s / done * (groups - done)) +
                                     " s left for " + scene_ + "'s rows",
                                 true);
                }
        }
    }

private:
    // Brute force is timed on a small slice of the sample only (it is O(triangles) per ray).
    std::span<const Ray> rays_for(const MethodSpec& m, int k) const {
        if (m.method != "brute") return r_.rays[k];
        return std::span<const Ray>(r_.rays[k]).first(std::min<std::size_t>(r_.closest[k].size(), 100));
    }

    void group(const std::vector<MethodSpec>& methods, const std::vector<Built>& one, const std::vector<Built>& all,
               int threads, int k, bool any, std::vector<Record>& out) {
        auto tracer = [&](std::size_t i) -> Tracer& { return threads == 1 ? *one[i].tracer : *all[i].tracer; };
        auto trace = [&](std::size_t i) {
            const std::span<const Ray> rs = rays_for(methods[i], k);
            const auto t0 = std::chrono::steady_clock::now();
            tracer(i).trace(rs, std::span(hits_).first(rs.size()), any, nullptr);
            return double(rs.size()) / seconds_since(t0) / 1e6;
        };
        for (std::size_t i = 0; i < methods.size(); ++i) trace(i);  // untimed warm-up
        std::vector<std::vector<double>> mr(methods.size());
        for (int rep = 0; rep < c_.reps; ++rep)
            for (std::size_t i = 0; i < methods.size(); ++i)
                if (rep == 0 || methods[i].method != "brute") mr[i].push_back(trace(i));
        for (std::size_t i = 0; i < methods.size(); ++i) {
            Record rec = row(methods[i], one[i], all.empty() ? one[i] : all[i], tracer(i), threads, k, any);
            rec.mrays_per_s = median(mr[i]);
            out.push_back(std::move(rec));
        }
    }

    // Everything but the speed: builds, memory, counters, agreement on the sample.
    Record row(const MethodSpec& base, const Built& one, const Built& all, Tracer& t, int threads, int k, bool any) {
        const std::span<const Ray> rs = rays_for(base, k);
        const std::span<const Hit> ref =
            std::span<const Hit>(any ? r_.any[k] : r_.closest[k]).first(std::min(rs.size(), r_.closest[k].size()));
        Record rec;
        rec.scene = scene_;
        rec.method = base.method == "embree" ? base.label() : base.method;
        rec.isa = t.ran_isa(base, any);
        rec.builder = base.builder_name();
        rec.width = base.method == "bvh2" ? 2 : base.width();
        rec.ray_kind = std::string(workloads::name(kKinds[k]));
        rec.query = any ? "any" : "closest";
        rec.threads = threads;
        rec.build_ms = one.cold_ms;
        rec.build_ms_warm = one.warm_ms;
        rec.build_ms_all = all.cold_ms;
        rec.build_ms_all_warm = all.warm_ms;
        rec.collapse_ms = one.collapse_ms;
        rec.bytes_per_triangle = t.bytes_per_triangle;
        rec.sah_cost = t.sah_cost;
        rec.rays = rs.size();
        rec.sample = ref.size();
        const std::span<const Ray> sample = std::span<const Ray>(r_.rays[k]).first(ref.size());
        std::span<Hit> got = std::span(hits_).first(ref.size());
        t.trace(sample, got, any, nullptr);
        rec.tally = classify_sample(mesh_, sample, ref, got, any);
        rec.agreement = rec.tally.agreement_rate();
        if (rec.width && threads == 1) count_visits(t, stats_[std::size_t(k)], any, rec);
        return rec;
    }

    const BenchConfig& c_;
    const Mesh& mesh_;
    std::string scene_;
    const BenchRays& r_;
    std::vector<std::vector<Ray>> stats_;  // evenly spaced counter sample per kind
    std::vector<Hit> hits_;
};

}  // namespace

BenchResults run_bench(const BenchConfig& c, const Mesh& mesh, const std::vector<NamedMesh>& width_meshes) {
    BenchResults out;
    {
        const BenchRays rays = make_rays(c, mesh);
        SceneBench(c, mesh, c.scene, rays).run(bench_methods(false), false, out.records);
    }
    out.width_scene_sizes.emplace_back(c.scene, mesh.size());
    for (const Record& r : out.records)
        if (r.width && r.threads == 1) out.widths.push_back(r);
    for (const NamedMesh& w : width_meshes) {
        progress("wide-vs-binary scene: " + w.name, true);
        const BenchRays rays = make_rays(c, w.mesh);
        SceneBench(c, w.mesh, w.name, rays).run(bench_methods(true), true, out.widths);
        out.width_scene_sizes.emplace_back(w.name, w.mesh.size());
    }
    return out;
}

}  // namespace simdbvh::lab

namespace simdbvh::lab {

std::map<std::string, std::vector<AccuracyRow>> run_hard_families(int threads) {
    AccuracyConfig ac;
    ac.quick = true;
    ac.inside = false;
    ac.open3d = false;
    ac.threads = threads;
    ac.families.quick = true;
    ac.which.assign(std::begin(kHardFamilies), std::end(kHardFamilies));
    // Our default paths (the bvh2 first: the bit-for-bit baseline) and Embree's two.
    ac.only.push_back("bvh2/watertight/conservative");
    for (Isa isa : supported_isas()) ac.only.push_back("bvh8/" + std::string(name(isa)) + "/watertight/conservative");
    ac.only.push_back("embree/default");
    ac.only.push_back("embree/robust");
    return run_accuracy(ac).families;
}

std::string bench_label_of(const std::string& variant) {
    const std::string tail = "/watertight/conservative";
    if (variant.size() > tail.size() && variant.ends_with(tail)) return variant.substr(0, variant.size() - tail.size());
    // accuracy_variants' Embree rows use the default (medium) build quality.
    if (variant == "embree/default") return "embree/medium/default";
    if (variant == "embree/robust") return "embree/medium/robust";
    return {};
}

}  // namespace simdbvh::lab
