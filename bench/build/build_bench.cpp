// SPDX-License-Identifier: MIT
// Build times: BVH2 (Bvh2::build, default options), collapse + pack (Bvh8::build
// from a BVH2 built with WideOptions::bvh2_intersection_cost, as Bvh8::build(mesh) does),
// the whole Bvh8::build(mesh) a user waits for, and Embree 3 medium (the
// EmbreeScene constructor: buffers + rtcCommitScene), on one thread and on all
// hardware threads. Each row: one untimed warm-up build whose time is the
// counter cold_ms (the first build of its kind in the process), then
// repetitions of one timed build each; read the _median rows.
// Scenes: $SIMDBVH_BENCH_BUILD_SCENES, comma separated (default
// "dragon,soup-1000000"; dragon is skipped when not cached); timed builds per
// row: $SIMDBVH_BENCH_BUILD_REPS (default 5, at least 3).
// Refit rows (refit/<scene>/...): Bvh2::refit, Bvh8::refit and Embree's
// refit (RTC_BUILD_QUALITY_REFIT, update_vertices) of a structure built once,
// each repetition alternating between the mesh twisted by 1 rad and the mesh
// itself (workloads::twist), so every timed refit moves every vertex.
// Peak memory: the warm-up build's peak resident bytes above the process's
// resident bytes before it, per triangle (peak_B_per_tri; Linux /proc).
// One-thread figures: run pinned, e.g. taskset -c 1 simdbvh_bench_build --benchmark_filter=/t1.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/reference/embree.h"
#include "simdbvh/kernels/isa.h"
#include "simdbvh/workloads/deform.h"
#include "simdbvh/workloads/scenes.h"

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

const simdbvh::Mesh& mesh_of(const std::string& name) {
    static std::map<std::string, std::unique_ptr<simdbvh::Mesh>> cache;
    auto& m = cache[name];
    if (!m) m = std::make_unique<simdbvh::Mesh>(simdbvh::workloads::load_scene(name));
    return *m;
}

int all_threads() { return int(std::max(1u, std::thread::hardware_concurrency())); }

// Resident memory from /proc/self/status (kB fields VmRSS, VmHWM), in bytes;
// 0 when unreadable. reset_peak() sets VmHWM back to VmRSS (clear_refs 5,
// Linux >= 4.0), so the peak after a build is that build's own.
std::size_t status_bytes(const char* field) {
    std::FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return 0;
    char line[256];
    std::size_t kb = 0;
    const std::size_t n = std::strlen(field);
    while (std::fgets(line, sizeof line, f))
        if (std::strncmp(line, field, n) == 0 && line[n] == ':') kb = std::strtoull(line + n + 1, nullptr, 10);
    std::fclose(f);
    return kb * 1024;
}
bool reset_peak() {
    std::FILE* f = std::fopen("/proc/self/clear_refs", "w");
    if (!f) return false;
    const bool ok = std::fputs("5", f) >= 0;
    return std::fclose(f) == 0 && ok;
}

enum class Row { bvh2, collapse_pack, bvh8, embree_medium };

// One build of `row`; returns its wall time in ms and the SAH cost (0 for Embree).
struct Timed {
    double ms = 0, sah = 0;
    double final_bytes = 0;  // our trees: nodes + triangle blocks (WideStats::bytes_per_triangle); 0 for Embree
    double collapse_ms = 0;  // bvh8: its collapse + pack (WideStats::build_ms), part of ms
};
Timed build_once(Row row, const simdbvh::Mesh& mesh, int threads, const simdbvh::Bvh2* bvh2) {
    simdbvh::BuildOptions bo;
    bo.threads = threads;
    simdbvh::WideOptions wo;
    wo.threads = threads;
    Timed t;
    const auto t0 = Clock::now();
    switch (row) {
    case Row::bvh2: {
        const simdbvh::Bvh2 b = simdbvh::Bvh2::build(mesh, bo);
        t.ms = ms_since(t0);
        t.sah = b.stats().sah_cost;
        break;
    }
    case Row::collapse_pack: {
        const simdbvh::Bvh8 b = simdbvh::Bvh8::build(*bvh2, wo);
        t.ms = ms_since(t0);
        t.sah = b.stats().sah_cost;
        break;
    }
    case Row::bvh8: {
        const simdbvh::Bvh8 b = simdbvh::Bvh8::build(mesh, bo, wo);
        t.ms = ms_since(t0);
        t.sah = b.stats().sah_cost;
        t.final_bytes = b.stats().bytes_per_triangle * double(mesh.size());
        t.collapse_ms = b.stats().build_ms;
        break;
    }
    case Row::embree_medium: {
        simdbvh::reference::EmbreeOptions eo;
        eo.threads = threads;
        const simdbvh::reference::EmbreeScene s(mesh, eo);
        t.ms = ms_since(t0);
        break;
    }
    }
    return t;
}

void BM_Build(benchmark::State& st, Row row, std::string scene, bool all, std::string key) {
    const int threads = all ? all_threads() : 1;
    const simdbvh::Mesh* mesh = nullptr;
    try {
        mesh = &mesh_of(scene);
    } catch (const std::exception& e) {
        st.SkipWithError(e.what());
        return;
    }
    static std::map<std::string, std::unique_ptr<simdbvh::Bvh2>> bvh2s;  // collapse + pack input, per row
    auto& bvh2 = bvh2s[key];
    if (row == Row::collapse_pack && !bvh2) {
        simdbvh::BuildOptions bo;
        bo.threads = threads;
        // The BVH2 Bvh8::build(mesh) starts from, so bvh2 + collapse_pack ~ bvh8.
        bo.intersection_cost = simdbvh::WideOptions{}.bvh2_intersection_cost;
        bvh2 = std::make_unique<simdbvh::Bvh2>(simdbvh::Bvh2::build(*mesh, bo));
    }
    // The untimed warm-up, once per row (not per repetition): its time is the cold build.
    // Its peak resident memory above what was resident before it (the mesh and
    // anything earlier rows keep), as bytes per triangle: peak_B_per_tri. With
    // the mesh's own bytes (mesh_B_per_tri) and, for Bvh8::build(mesh), the
    // finished tree's (final_B_per_tri), the build target's memory bound
    // (docs/results.md#the-targets) reads mesh + peak <= 1.5 x (mesh + final).
    static std::map<std::string, double> cold, peak;
    if (!cold.count(key)) {
        const bool reset = reset_peak();
        const std::size_t before = status_bytes("VmRSS");
        cold[key] = build_once(row, *mesh, threads, bvh2.get()).ms;
        const std::size_t hwm = status_bytes("VmHWM");
        peak[key] = reset && before > 0 && hwm >= before ? double(hwm - before) : -1.0;
    }
    Timed t;
    for (auto _ : st) {
        t = build_once(row, *mesh, threads, bvh2.get());
        st.SetIterationTime(t.ms / 1000.0);
    }
    st.counters["cold_ms"] = cold[key];
    const double tris = double(std::max<std::size_t>(1, mesh->size()));
    if (peak[key] >= 0) st.counters["peak_B_per_tri"] = peak[key] / tris;
    st.counters["mesh_B_per_tri"] =
        double(mesh->positions.size() * sizeof(simdbvh::Vec3) + mesh->triangles.size() * sizeof(simdbvh::Triangle)) /
        tris;
    if (t.final_bytes > 0) st.counters["final_B_per_tri"] = t.final_bytes / tris;
    st.counters["threads"] = threads;
    st.counters["Mtri/s"] =
        benchmark::Counter(double(mesh->size()) * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
    if (t.sah > 0) st.counters["sah"] = t.sah;
    // The collapse + pack inside this Bvh8::build(mesh), and its share (the build target: at most 15%).
    if (t.collapse_ms > 0) {
        st.counters["collapse_pack_ms"] = t.collapse_ms;
        st.counters["collapse_pack_share"] = t.collapse_ms / t.ms;
    }
}

enum class Refit { bvh2, bvh8, embree };

// Per row: the structure built once and the two meshes it alternates between.
struct RefitState {
    simdbvh::Mesh moved;
    simdbvh::Bvh2 bvh2;
    simdbvh::Bvh8 bvh8;
    std::unique_ptr<simdbvh::reference::EmbreeScene> embree;
    bool at_moved = false;
};

double refit_once(Refit what, RefitState& r, const simdbvh::Mesh& mesh, int threads) {
    r.at_moved = !r.at_moved;
    const simdbvh::Mesh& to = r.at_moved ? r.moved : mesh;
    const auto t0 = Clock::now();
    switch (what) {
    case Refit::bvh2: r.bvh2.refit(to, threads); break;
    case Refit::bvh8: r.bvh8.refit(to, threads); break;
    case Refit::embree: return r.embree->update_vertices(to);  // copy + rtcCommitScene
    }
    return ms_since(t0);
}

void BM_Refit(benchmark::State& st, Refit what, std::string scene, bool all) {
    const int threads = all ? all_threads() : 1;
    const simdbvh::Mesh* mesh = nullptr;
    try {
        mesh = &mesh_of(scene);
    } catch (const std::exception& e) {
        st.SkipWithError(e.what());
        return;
    }
    RefitState r;
    r.moved = simdbvh::workloads::twist(*mesh, 1.0);
    switch (what) {
    case Refit::bvh2: r.bvh2 = simdbvh::Bvh2::build(*mesh); break;
    case Refit::bvh8: r.bvh8 = simdbvh::Bvh8::build(*mesh); break;
    case Refit::embree:
        r.embree = std::make_unique<simdbvh::reference::EmbreeScene>(
            *mesh, simdbvh::reference::EmbreeOptions{simdbvh::reference::EmbreeQuality::refit, false, threads});
        break;
    }
    refit_once(what, r, *mesh, threads);  // untimed warm-up
    refit_once(what, r, *mesh, threads);
    for (auto _ : st) st.SetIterationTime(refit_once(what, r, *mesh, threads) / 1000.0);
    st.counters["threads"] = threads;
    st.counters["Mtri/s"] =
        benchmark::Counter(double(mesh->size()) * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
}

std::vector<std::string> scenes() {
    const char* env = std::getenv("SIMDBVH_BENCH_BUILD_SCENES");
    const std::string list = env && *env ? env : "dragon,soup-1000000";
    std::vector<std::string> out;
    std::size_t at = 0;
    while (at <= list.size()) {
        const std::size_t comma = std::min(list.find(',', at), list.size());
        const std::string s = list.substr(at, comma - at);
        if (!s.empty() && (s != "dragon" || simdbvh::workloads::is_cached(s))) out.push_back(s);
        at = comma + 1;
    }
    return out;
}

// Timed builds per row: $SIMDBVH_BENCH_BUILD_REPS (an integer from 3 to 100, default 5; 3 for long
// scaling runs). Anything else: a message naming the variable and exit 2.
int build_reps() {
    const char* env = std::getenv("SIMDBVH_BENCH_BUILD_REPS");
    if (!env || !*env) return 5;
    char* end = nullptr;
    const long reps = std::strtol(env, &end, 10);
    if (*end != '\0' || reps < 3 || reps > 100) {
        std::fprintf(stderr,
                     "SIMDBVH_BENCH_BUILD_REPS='%s': expected an integer from 3 to 100 (builds are medians of >= 3)\n",
                     env);
        std::exit(2);
    }
    return int(reps);
}

void register_all() {
    const std::pair<Row, const char*> rows[] = {{Row::bvh2, "bvh2"},
                                                {Row::collapse_pack, "collapse_pack"},
                                                {Row::bvh8, "bvh8"},
                                                {Row::embree_medium, "embree_medium"}};
    for (const std::string& s : scenes())
        for (bool all : {false, true})
            for (const auto& [row, label] : rows) {
                const std::string name = "build/" + s + "/" + label + (all ? "/tall" : "/t1");
                benchmark::RegisterBenchmark(name.c_str(), BM_Build, row, s, all, name)
                    ->UseManualTime()
                    ->Unit(benchmark::kMillisecond)
                    ->Iterations(1)
                    ->Repetitions(build_reps())
                    ->DisplayAggregatesOnly(true);
            }
    const std::pair<Refit, const char*> refits[] = {
        {Refit::bvh2, "bvh2"}, {Refit::bvh8, "bvh8"}, {Refit::embree, "embree"}};
    for (const std::string& s : scenes())
        for (bool all : {false, true})
            for (const auto& [what, label] : refits) {
                const std::string name = "refit/" + s + "/" + label + (all ? "/tall" : "/t1");
                benchmark::RegisterBenchmark(name.c_str(), BM_Refit, what, s, all)
                    ->UseManualTime()
                    ->Unit(benchmark::kMillisecond)
                    ->Iterations(1)
                    ->Repetitions(7)
                    ->DisplayAggregatesOnly(true);
            }
}

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    register_all();
    benchmark::AddCustomContext("active_isa", std::string(simdbvh::name(simdbvh::active_isa())));
    benchmark::AddCustomContext("all_threads", std::to_string(all_threads()));
    benchmark::AddCustomContext("embree", simdbvh::reference::EmbreeScene::version());
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
