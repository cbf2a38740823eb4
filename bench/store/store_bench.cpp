// SPDX-License-Identifier: MIT
// Saved structures (docs/saved_format.md): per scene, save (save_bytes and
// the atomic write), load read and mapped (with and without the payload
// checksum), the checksum pass alone, against a fresh Bvh8::build on one and
// two threads; and the first trace of 65,536 incoherent rays right after a
// mapped load and right after a build (the trees' pages are touched by the
// load's copy or by the build either way). Warm page cache: the file is
// written once and read back by every repetition; the _cold rows evict the
// file's pages first (evict()). Read the _median rows.
// Scenes: $SIMDBVH_BENCH_STORE_SCENES, comma separated (default
// "dragon,soup-1000000"); the files go to $TMPDIR (default /tmp).
#include <benchmark/benchmark.h>

#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/store/store.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

namespace {

using Clock = std::chrono::steady_clock;
using namespace simdbvh;

struct Fixture {
    Mesh mesh;
    Bvh8 bvh;
    std::filesystem::path file;
    std::vector<unsigned char> bytes;
    std::vector<Ray> rays;
};

std::filesystem::path tmp_dir() {
    const char* t = std::getenv("TMPDIR");
    return t && *t ? t : "/tmp";
}

Fixture& fixture(const std::string& scene) {
    static std::map<std::string, std::unique_ptr<Fixture>> cache;
    auto& f = cache[scene];
    if (!f) {
        f = std::make_unique<Fixture>();
        f->mesh = workloads::load_scene(scene);
        f->bvh = Bvh8::build(f->mesh);
        f->file = tmp_dir() / ("simdbvh-bench-" + scene + "-" + std::to_string(::getpid()) + ".simdbvh");
        f->bytes = save_bytes(f->bvh, f->mesh);
        save(f->bvh, f->mesh, f->file);
        f->rays = workloads::generate_rays(f->mesh, workloads::RayKind::incoherent, 65536, 3);
    }
    return *f;
}

void set_counters(benchmark::State& st, const Fixture& f) {
    st.counters["MB"] = double(f.bytes.size()) / 1e6;
    st.counters["triangles"] = double(f.mesh.size());
    st.counters["GB/s"] =
        benchmark::Counter(double(f.bytes.size()) / 1e9, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Save(benchmark::State& st, std::string scene) {
    Fixture& f = fixture(scene);
    for (auto _ : st) save(f.bvh, f.mesh, f.file);
    set_counters(st, f);
}
// Evicts the file's pages from this machine's page cache (POSIX_FADV_DONTNEED on a clean file: only its own
// pages, not the whole cache as drop_caches would; a virtual disk may still serve them from the host's cache).
void evict(const std::filesystem::path& file) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return;
    ::fdatasync(fd);
    ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
    ::close(fd);
}
void BM_Load(benchmark::State& st, std::string scene, bool map, bool verify, bool cold = false) {
    Fixture& f = fixture(scene);
    for (auto _ : st) {
        if (cold) {
            st.PauseTiming();
            evict(f.file);
            st.ResumeTiming();
        }
        benchmark::DoNotOptimize(load<Bvh8>(f.file, {.map = map, .verify = verify}));
    }
    set_counters(st, f);
}
void BM_Checksum(benchmark::State& st, std::string scene) {
    Fixture& f = fixture(scene);
    for (auto _ : st) benchmark::DoNotOptimize(xxh64(f.bytes));
    set_counters(st, f);
}
void BM_Build(benchmark::State& st, std::string scene, int threads) {
    Fixture& f = fixture(scene);
    BuildOptions b;
    b.threads = threads;
    WideOptions w;
    w.threads = threads;
    for (auto _ : st) benchmark::DoNotOptimize(Bvh8::build(f.mesh, b, w));
    set_counters(st, f);
}
// The first trace on a tree just loaded (mapped) or just built; only the trace is timed.
void BM_FirstTrace(benchmark::State& st, std::string scene, bool loaded) {
    Fixture& f = fixture(scene);
    std::vector<Hit> hits(f.rays.size());
    const Isa isa = active_isa();
    for (auto _ : st) {
        const Bvh8 b = loaded ? load<Bvh8>(f.file) : Bvh8::build(f.mesh);
        const auto t0 = Clock::now();
        intersect(b, std::span<const Ray>(f.rays), std::span<Hit>(hits), with_isa({}, isa));
        st.SetIterationTime(std::chrono::duration<double>(Clock::now() - t0).count());
    }
    st.counters["Mrays/s"] =
        benchmark::Counter(double(f.rays.size()) / 1e6, benchmark::Counter::kIsIterationInvariantRate);
    st.SetLabel(std::string(name(isa)));
}

std::vector<std::string> scenes() {
    const char* env = std::getenv("SIMDBVH_BENCH_STORE_SCENES");
    std::string s = env && *env ? env : "dragon,soup-1000000";
    std::vector<std::string> out;
    for (std::size_t p = 0; p <= s.size();) {
        const std::size_t q = std::min(s.find(',', p), s.size());
        if (q > p) out.push_back(s.substr(p, q - p));
        p = q + 1;
    }
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    for (const std::string& s : scenes()) {
        const auto reg = [&](const std::string& n, auto fn) {
            return benchmark::RegisterBenchmark((n + "/" + s).c_str(), fn)
                ->Unit(benchmark::kMillisecond)
                ->Repetitions(5);
        };
        reg("save", [s](benchmark::State& st) { BM_Save(st, s); });
        reg("load_read", [s](benchmark::State& st) { BM_Load(st, s, false, true); });
        reg("load_mapped", [s](benchmark::State& st) { BM_Load(st, s, true, true); });
        reg("load_mapped_cold", [s](benchmark::State& st) { BM_Load(st, s, true, true, true); });
        reg("load_read_cold", [s](benchmark::State& st) { BM_Load(st, s, false, true, true); });
        reg("load_mapped_noverify", [s](benchmark::State& st) { BM_Load(st, s, true, false); });
        reg("checksum", [s](benchmark::State& st) { BM_Checksum(st, s); });
        reg("build_t1", [s](benchmark::State& st) { BM_Build(st, s, 1); });
        reg("build_t2", [s](benchmark::State& st) { BM_Build(st, s, 2); });
        reg("first_trace_after_load", [s](benchmark::State& st) { BM_FirstTrace(st, s, true); })->UseManualTime();
        reg("first_trace_after_build", [s](benchmark::State& st) { BM_FirstTrace(st, s, false); })->UseManualTime();
    }
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    for (const std::string& s : scenes()) {
        std::error_code ec;
        std::filesystem::remove(tmp_dir() / ("simdbvh-bench-" + s + "-" + std::to_string(::getpid()) + ".simdbvh"), ec);
    }
    return 0;
}
