// SPDX-License-Identifier: MIT
// simdbvh bench --sweep, the run. Per scene: every method built with one
// thread and with all cores (a cold build, then the median of build_reps warm
// ones), then per ray kind and ray count the same rays traced by every method:
// an untimed warm-up of each, then reps rounds with the methods interleaved
// (load from elsewhere falls on all of them), the median per method. A trace
// expected (from the previous ray count) to take longer than budget_ms is timed
// on evenly spaced rays and scaled to the full count: trace time is linear in
// the rays, and the sweep stays at a few minutes. One-thread rows are pinned to one CPU.
#include "lab.h"
#include "sweep_run.h"

#include <sched.h>

#include <algorithm>
#include <cmath>

#include "common.h"
#include "methods.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

namespace simdbvh::lab {

namespace {

using workloads::RayKind;

double median_ms(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

std::vector<std::size_t> decades(std::size_t lo, std::size_t hi) {
    std::vector<std::size_t> out;
    for (std::size_t r = lo; r <= hi; r *= 10) out.push_back(r);
    return out;
}

std::vector<MethodSpec> sweep_methods(Isa isa) {
    std::vector<MethodSpec> out;
    for (AccelMethod m : kAccelMethods) {
        MethodSpec s;
        s.method = std::string(name(m));
        s.isa = isa;
        out.push_back(s);
    }
    MethodSpec e;  // Embree as a reference row (not a candidate of auto)
    e.method = "embree";
    out.push_back(e);
    return out;
}

// Every k-th ray, about n of them.
std::vector<Ray> every_kth(const std::vector<Ray>& rays, std::size_t n) {
    std::vector<Ray> out;
    const std::size_t stride = std::max<std::size_t>(1, (rays.size() + n - 1) / std::max<std::size_t>(1, n));
    for (std::size_t i = 0; i < rays.size(); i += stride) out.push_back(rays[i]);
    return out;
}

// One-thread rows run on the last CPU the process may use (as `taskset -c` would); the mask is restored for
// the all-core rows (threads inherit the mask of the thread that starts them).
class PinToLastCpu {
public:
    explicit PinToLastCpu(bool on) {
        CPU_ZERO(&saved_);
        if (!on || sched_getaffinity(0, sizeof saved_, &saved_) != 0) return;
        cpu_set_t one;
        CPU_ZERO(&one);
        for (int cpu = CPU_SETSIZE - 1; cpu >= 0; --cpu)
            if (CPU_ISSET(cpu, &saved_)) {
                CPU_SET(cpu, &one);
                break;
            }
        pinned_ = sched_setaffinity(0, sizeof one, &one) == 0;
    }
    ~PinToLastCpu() {
        if (pinned_) sched_setaffinity(0, sizeof saved_, &saved_);
    }
    PinToLastCpu(const PinToLastCpu&) = delete;
    PinToLastCpu& operator=(const PinToLastCpu&) = delete;

private:
    cpu_set_t saved_;
    bool pinned_ = false;
};

struct Built {
    std::unique_ptr<Tracer> tracer;
    double build_ms = 0;
};

Built build(const Mesh& mesh, MethodSpec spec, int threads, int warm_reps) {
    spec.threads = threads;
    spec.build.threads = threads;
    spec.wide.threads = threads;
    Built b{make_tracer(mesh, spec), 0};
    std::vector<double> warm;
    for (int r = 0; r < warm_reps; ++r) warm.push_back(make_tracer(mesh, spec)->build_ms);
    b.build_ms = warm.empty() ? b.tracer->build_ms : median_ms(warm);
    return b;
}

class SceneSweep {
public:
    SceneSweep(const SweepConfig& c, const SweepScene& s, const Mesh& mesh) : c_(c), s_(s), mesh_(mesh) {}

    void run(std::vector<SweepRow>& out) {
        const auto methods = sweep_methods(c_.isa);
        for (int threads : {1, c_.threads_all}) {
            if (threads != 1 && c_.threads_all == 1) break;
            const PinToLastCpu pin(threads == 1);
            progress("sweep " + s_.name + " (" + std::to_string(mesh_.size()) + " triangles), " +
                         std::to_string(threads) + " thread(s): building",
                     true);
            std::vector<Built> built;
            for (const MethodSpec& m : methods) built.push_back(build(mesh_, m, threads, c_.build_reps));
            for (RayKind kind : {RayKind::primary, RayKind::incoherent}) {
                std::vector<double> per_ray(methods.size(), 0.0);  // ms per ray at the previous count
                for (std::size_t n_rays : s_.rays) {
                    const auto rays = workloads::generate_rays(mesh_, kind, n_rays, 42);
                    group(methods, built, rays, kind, threads, per_ray, out);
                }
            }
        }
    }

private:
    void group(const std::vector<MethodSpec>& methods, const std::vector<Built>& built, const std::vector<Ray>& rays,
               RayKind kind, int threads, std::vector<double>& per_ray, std::vector<SweepRow>& out) {
        std::vector<std::vector<Ray>> subset(methods.size());
        std::vector<Hit> hits(rays.size());
        auto rays_of = [&](std::size_t i) -> const std::vector<Ray>& { return subset[i].empty() ? rays : subset[i]; };
        for (std::size_t i = 0; i < methods.size(); ++i)
            if (per_ray[i] * double(rays.size()) > c_.budget_ms)
                subset[i] = every_kth(rays, std::max<std::size_t>(1, std::size_t(c_.budget_ms / per_ray[i])));
        auto trace = [&](std::size_t i) {
            const auto t0 = std::chrono::steady_clock::now();
            built[i].tracer->trace(rays_of(i), std::span(hits).first(rays_of(i).size()), false, nullptr);
            return seconds_since(t0) * 1e3;
        };
        for (std::size_t i = 0; i < methods.size(); ++i) trace(i);  // untimed warm-up
        std::vector<std::vector<double>> ms(methods.size());
        for (int rep = 0; rep < c_.reps; ++rep)
            for (std::size_t i = 0; i < methods.size(); ++i) ms[i].push_back(trace(i));
        for (std::size_t i = 0; i < methods.size(); ++i) {
            SweepRow r;
            r.scene = s_.name;
            r.method = methods[i].method;
            r.ray_kind = std::string(workloads::name(kind));
            r.triangles = mesh_.size();
            r.rays = rays.size();
            r.held_out = s_.held_out;
            r.threads = threads;
            r.build_ms = built[i].build_ms;
            r.traced_rays = rays_of(i).size();
            const double t = median_ms(ms[i]);
            per_ray[i] = t / double(r.traced_rays);
            r.trace_ms = per_ray[i] * double(r.rays);
            out.push_back(r);
        }
    }

    const SweepConfig& c_;
    const SweepScene& s_;
    const Mesh& mesh_;
};

}  // namespace

// Fit scenes: random soups and icospheres over the decades; held-out scenes:
// the dragon at its resolutions, the bunny and the teapot (icospheres of odd
// levels and a soup instead when they are not cached), at ray counts between
// the decades.
std::vector<SweepScene> sweep_scenes(bool quick) {
    std::vector<SweepScene> s;
    const std::size_t max_tris = quick ? 10000 : 1000000;
    const auto rays = decades(1, quick ? 10000 : 1000000);
    for (std::size_t n = 1; n <= max_tris; n *= 10) s.push_back({"soup-" + std::to_string(n), 0, false, rays});
    for (int level = 0; level <= (quick ? 4 : 8); level += 2)
        s.push_back({"icosphere-" + std::to_string(level), 0, false, rays});
    // A real mesh among the fit scenes: scanned meshes cost more per incoherent ray than soups and spheres of
    // the same size (deeper overlap), which moves the BVH2 / wide-tree crossover. Not one of the held-out scenes.
    if (!quick && workloads::is_cached("dragon-res3")) s.push_back({"dragon-res3", 0, false, rays});
    const std::vector<std::size_t> held_rays =
        quick ? std::vector<std::size_t>{3, 300, 3000, 30000} : std::vector<std::size_t>{3, 300, 30000, 300000};
    const char* held[] = {"dragon", "dragon-res2", "dragon-res4", "bunny", "teapot"};
    const char* fallback[] = {"icosphere-7", "icosphere-5", "icosphere-3", "icosphere-1", "soup-3000"};
    for (int i = 0; i < 5; ++i) {
        const bool use = workloads::is_cached(held[i]) && !(quick && i == 0);
        s.push_back({use ? held[i] : fallback[i], 0, true, held_rays});
    }
    return s;
}

SweepResults run_sweep(const SweepConfig& c) {
    SweepResults res;
    res.scenes = sweep_scenes(c.quick);
    for (SweepScene& s : res.scenes) {
        const Mesh mesh = load_scene_with_progress(s.name);
        s.triangles = mesh.size();
        SceneSweep(c, s, mesh).run(res.rows);
    }
    res.model = fit_cost_model(res.rows, c.isa);
    res.checks = check_auto(res.rows, res.model);
    return res;
}

}  // namespace simdbvh::lab
