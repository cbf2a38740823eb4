// SPDX-License-Identifier: MIT
// simdbvh bench, the refit sequence: run and report (refit_run.h).
#include "lab.h"
#include "refit_run.h"

#include <algorithm>
#include <chrono>
#include <functional>
#include <sstream>

#include "bench_run.h"
#include "common.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/reference/embree.h"
#include "simdbvh/workloads/deform.h"
#include "simdbvh/workloads/rays.h"

namespace simdbvh::lab {

namespace {

constexpr double kRadiansPerFrame = 0.1;
constexpr workloads::RayKind kKinds[2] = {workloads::RayKind::primary, workloads::RayKind::incoherent};

double ms_of(const std::function<void()>& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

double median_of(int reps, const std::function<double()>& f) {
    std::vector<double> v;
    for (int r = 0; r < std::max(1, reps); ++r) v.push_back(f());
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// Mrays/s of `trace` over `rays`: one untimed warm-up, then the median of `reps`.
double mrays(int reps, std::size_t rays, const std::function<void()>& trace) {
    trace();
    const double ms = median_of(reps, [&] { return ms_of(trace); });
    return ms > 0 ? double(rays) / (ms * 1e3) : 0.0;
}

}  // namespace

std::vector<RefitFrame> run_refit(const BenchConfig& c, const Mesh& mesh) {
    std::vector<RefitFrame> frames;
    if (c.refit_frames <= 0 || mesh.size() == 0) return frames;
    const int reps = std::max(1, c.build_reps);
    progress("refit sequence: " + std::to_string(c.refit_frames) + " frames", true);
    Bvh8 refit = Bvh8::build(mesh);
    reference::EmbreeScene embree_refit(mesh, {reference::EmbreeQuality::refit, false, 1});
    reference::EmbreeScene embree_rebuild(mesh, {reference::EmbreeQuality::medium, false, 1});
    const std::size_t n = std::max<std::size_t>(1024, c.rays / 4);
    for (int f = 1; f <= c.refit_frames; ++f) {
        RefitFrame fr;
        fr.frame = f;
        fr.radians = kRadiansPerFrame * f;
        progress("refit frame " + std::to_string(f) + " (twist " + fmt("%.2f", fr.radians) + " rad)", true);
        const Mesh moved = workloads::twist(mesh, fr.radians);
        // The first refit and update of the frame are untimed (first touch of the new positions).
        refit.refit(moved, 1);
        fr.refit_ms = median_of(reps, [&] { return ms_of([&] { refit.refit(moved, 1); }); });
        fr.refit_ms_all = median_of(reps, [&] { return ms_of([&] { refit.refit(moved, c.threads_all); }); });
        Bvh8 rebuilt = Bvh8::build(moved);
        fr.rebuild_ms = median_of(reps, [&] { return ms_of([&] { rebuilt = Bvh8::build(moved); }); });
        embree_refit.update_vertices(moved);
        fr.embree_refit_ms = median_of(reps, [&] { return embree_refit.update_vertices(moved); });
        embree_rebuild.update_vertices(moved);
        fr.embree_rebuild_ms = median_of(reps, [&] { return embree_rebuild.update_vertices(moved); });
        fr.sah_refit = refit.stats().sah_cost;
        fr.sah_rebuild = rebuilt.stats().sah_cost;
        for (int k = 0; k < 2; ++k) {
            const std::vector<Ray> rays = workloads::generate_rays(moved, kKinds[k], n, 7 + std::uint64_t(f));
            std::vector<Hit> a(rays.size()), b(rays.size());
            fr.mrays_refit[k] = mrays(c.reps, n, [&] { intersect(refit, rays, a); });
            fr.mrays_rebuild[k] = mrays(c.reps, n, [&] { intersect(rebuilt, rays, b); });
            for (std::size_t i = 0; i < rays.size(); ++i) fr.differ += !(a[i] == b[i]);
            fr.mrays_embree_refit[k] = mrays(c.reps, n, [&] { embree_refit.intersect(rays, a); });
            fr.mrays_embree_rebuild[k] = mrays(c.reps, n, [&] { embree_rebuild.intersect(rays, a); });
        }
        frames.push_back(fr);
    }
    return frames;
}

Json refit_json(const std::vector<RefitFrame>& frames) {
    Json a = Json::array();
    for (const RefitFrame& f : frames)
        a.push_back({{"frame", f.frame},
                     {"radians", f.radians},
                     {"refit_ms", f.refit_ms},
                     {"refit_ms_all_cores", f.refit_ms_all},
                     {"rebuild_ms", f.rebuild_ms},
                     {"embree_refit_ms", f.embree_refit_ms},
                     {"embree_rebuild_ms", f.embree_rebuild_ms},
                     {"sah_refit", f.sah_refit},
                     {"sah_rebuild", f.sah_rebuild},
                     {"mrays_refit", {f.mrays_refit[0], f.mrays_refit[1]}},
                     {"mrays_rebuild", {f.mrays_rebuild[0], f.mrays_rebuild[1]}},
                     {"mrays_embree_refit", {f.mrays_embree_refit[0], f.mrays_embree_refit[1]}},
                     {"mrays_embree_rebuild", {f.mrays_embree_rebuild[0], f.mrays_embree_rebuild[1]}},
                     {"differ", f.differ}});
    return a;
}

std::string refit_markdown(const std::vector<RefitFrame>& frames, const std::string& img_dir, bool chart) {
    if (frames.empty()) return "";
    std::ostringstream s;
    s << "The bench scene twisted about its vertical axis by " << kRadiansPerFrame
      << " rad more per frame (workloads::twist). Ours: BVH8 refit (1 thread / all cores) against `Bvh8::build` of the "
         "moved mesh (1 thread); Embree 3, one thread: a dynamic scene with RTC_BUILD_QUALITY_REFIT against a "
         "medium scene, both updated with the new vertex buffer and rtcCommitScene. ms: median of the timed runs "
         "after an untimed one. Mrays/s: closest hit, one thread, primary / incoherent rays. differ: rays whose "
         "refit hit differs in any bit from the rebuild's (both are bit-identical to brute force).\n\n";
    Table t({"frame", "rad", "refit ms", "refit ms all", "rebuild ms", "embree refit ms", "embree rebuild ms",
             "SAH refit/rebuild", "Mrays/s refit", "Mrays/s rebuild", "embree refit", "embree rebuild", "differ"});
    auto pair = [](const double* m) { return fmt("%.2f", m[0]) + " / " + fmt("%.2f", m[1]); };
    for (const RefitFrame& f : frames)
        t.row({std::to_string(f.frame), fmt("%.1f", f.radians), fmt("%.3g", f.refit_ms), fmt("%.3g", f.refit_ms_all),
               fmt("%.4g", f.rebuild_ms), fmt("%.3g", f.embree_refit_ms), fmt("%.4g", f.embree_rebuild_ms),
               fmt("%.3f", f.sah_rebuild > 0 ? f.sah_refit / f.sah_rebuild : 0.0), pair(f.mrays_refit),
               pair(f.mrays_rebuild), pair(f.mrays_embree_refit), pair(f.mrays_embree_rebuild),
               std::to_string(f.differ)});
    s << t.markdown() << "\n";
    if (chart) s << "![refit against rebuild](" << img_dir << "refit.png)\n\n";
    return s.str();
}

}  // namespace simdbvh::lab
