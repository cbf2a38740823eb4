// A worker thread that cannot start (a process limit,
// RLIMIT_NPROC, or an address-space limit, RLIMIT_AS) never terminates the
// process: parallel_for, the threaded BVH2 build (std::async subtrees and
// binning) and threaded BVH2/BVH8 traces finish with the threads that started
// (or the caller alone) and give the single-thread results. Each case runs in
// a forked child under the limit; the child exits 0 when every result equals
// the reference, and the parent checks it exited (not killed by SIGABRT).
#include <gtest/gtest.h>

#include <grp.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>

#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/platform/parallel.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define SIMDBVH_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define SIMDBVH_SANITIZED 1
#endif
#endif

namespace simdbvh {
namespace {

constexpr int kThreads = 256;  // far more than the limits let start
constexpr int kSkip = 77;      // child: the limit could not be set up

enum class Limit { nproc_1, nproc_4, address_space };

// The process's address-space size (VmSize) in bytes.
std::size_t vm_size() {
    long pages = 0;
    if (FILE* f = std::fopen("/proc/self/statm", "r")) {
        if (std::fscanf(f, "%ld", &pages) != 1) pages = 0;
        std::fclose(f);
    }
    return std::size_t(pages) * std::size_t(sysconf(_SC_PAGESIZE));
}

// Applies the limit in the child. RLIMIT_NPROC does not bind root, so a root
// child first becomes nobody (65534).
bool apply(Limit limit) {
    if (limit == Limit::address_space) {
        // Room for a few thread stacks (8 MiB each by default), not hundreds.
        const rlim_t as = rlim_t(vm_size() + (48u << 20));
        const rlimit rl{as, as};
        return setrlimit(RLIMIT_AS, &rl) == 0;
    }
    if (geteuid() == 0 && (setgroups(0, nullptr) != 0 || setgid(65534) != 0 || setuid(65534) != 0)) return false;
    const rlim_t n = limit == Limit::nproc_1 ? 1 : 4;
    const rlimit rl{n, n};
    return setrlimit(RLIMIT_NPROC, &rl) == 0;
}

// Runs `body` in a forked child under `limit`; returns the wait status.
// body returns true when its results equal the reference.
int run_limited(Limit limit, const std::function<bool()>& body) {
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid == 0) {
        if (!apply(limit)) _exit(kSkip);
        bool ok = false;
        try {
            ok = body();
        } catch (const std::exception& e) {
            std::fprintf(stderr, "child: exception: %s\n", e.what());
        } catch (...) {
            std::fprintf(stderr, "child: unknown exception\n");
        }
        std::fflush(nullptr);
        _exit(ok ? 0 : 1);
    }
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) != pid) return -1;
    return status;
}

std::string describe(int status) {
    if (status == -1) return "fork/waitpid failed";
    if (WIFSIGNALED(status))
        return "killed by signal " + std::to_string(WTERMSIG(status)) + " (" + strsignal(WTERMSIG(status)) + ")";
    return "exit " + std::to_string(WEXITSTATUS(status));
}

void expect_child_ok(Limit limit, const std::function<bool()>& body) {
    const int status = run_limited(limit, body);
    if (WIFEXITED(status) && WEXITSTATUS(status) == kSkip) GTEST_SKIP() << "could not set the limit";
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << describe(status);
}

std::vector<Limit> limits() {
#ifdef SIMDBVH_SANITIZED
    return {Limit::nproc_1, Limit::nproc_4};  // sanitizers reserve terabytes of shadow memory: no RLIMIT_AS
#else
    return {Limit::nproc_1, Limit::nproc_4, Limit::address_space};
#endif
}

std::string name(Limit l) {
    switch (l) {
    case Limit::nproc_1: return "nproc_1";
    case Limit::nproc_4: return "nproc_4";
    case Limit::address_space: return "address_space";
    }
    return "?";
}

void PrintTo(Limit l, std::ostream* os) { *os << name(l); }

class ThreadLimits : public testing::TestWithParam<Limit> {};

TEST_P(ThreadLimits, ParallelForCoversEveryIndexOnce) {
    constexpr std::size_t n = 1u << 16;
    parallel_for(n, 2, [](std::size_t, std::size_t) {});  // hwloc topology and first-use state before the limit
    std::vector<std::atomic<int>> seen(n);
    expect_child_ok(GetParam(), [&] {
        ParallelOptions po;
        po.grain = 64;  // 1024 chunks for kThreads workers
        parallel_for(
            n, kThreads,
            [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i) seen[i].fetch_add(1, std::memory_order_relaxed);
            },
            po);
        for (const auto& s : seen)
            if (s.load() != 1) return false;
        return true;
    });
}

TEST_P(ThreadLimits, ThreadedTracesMatchOneThread) {
    const Mesh mesh = workloads::icosphere(5);
    const Bvh2 bvh2 = Bvh2::build(mesh);
    const Bvh8 bvh8 = Bvh8::build(bvh2);
    const auto rays = workloads::generate_rays(mesh, workloads::RayKind::incoherent, 50000, 3);
    std::vector<Hit> want(rays.size()), got2(rays.size()), got8(rays.size());
    intersect(bvh8, rays, want);
    TraceOptions two;
    two.threads = 2;
    intersect(bvh8, rays, got8, two);  // first-use state before the limit
    expect_child_ok(GetParam(), [&] {
        TraceOptions many;
        many.threads = kThreads;
        std::fill(got8.begin(), got8.end(), Hit{});
        intersect(bvh2, rays, got2, many);
        intersect(bvh8, rays, got8, many);
        return got2 == want && got8 == want;
    });
}

// The BVH2 build starts std::async tasks for subtrees of >= 32K triangles and
// bins ranges of >= 128K triangles in several threads: every count gives the
// same tree, so a build that loses its threads must too.
TEST_P(ThreadLimits, ThreadedBuildMatchesOneThread) {
    if (GetParam() == Limit::address_space) GTEST_SKIP() << "a build allocates: covered by the process limits";
    const Mesh mesh = workloads::random_soup(300000, 5);
    const Bvh2 want = Bvh2::build(mesh);
    const Bvh8 want8 = Bvh8::build(want);
    expect_child_ok(GetParam(), [&] {
        BuildOptions bo;
        bo.threads = kThreads;
        const Bvh2 got = Bvh2::build(mesh, bo);
        const Bvh8 got8 = Bvh8::build(got);
        if (got.prim_ids() != want.prim_ids() || got.nodes().size() != want.nodes().size()) return false;
        for (std::size_t i = 0; i < got.nodes().size(); ++i)
            if (std::memcmp(&got.nodes()[i], &want.nodes()[i], sizeof(Node2)) != 0) return false;
        return got8.nodes().size() == want8.nodes().size() &&
               std::memcmp(got8.nodes().data(), want8.nodes().data(), got8.nodes().size() * sizeof(Node8)) == 0;
    });
}

INSTANTIATE_TEST_SUITE_P(Limits, ThreadLimits, testing::ValuesIn(limits()),
                         [](const auto& info) { return name(info.param); });

}  // namespace
}  // namespace simdbvh
