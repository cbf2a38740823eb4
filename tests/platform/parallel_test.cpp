// parallel_for: chunks cover [0, n) once; the library's workers are unpinned
// unless set_thread_pinning(true); a host executor takes the chunks instead of
// library threads, exceptions come back to the caller.
#include <gtest/gtest.h>
#include <sched.h>

#include <atomic>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "simdbvh/platform/build_threads.h"
#include "simdbvh/platform/parallel.h"
#include "simdbvh/platform/topology.h"

namespace simdbvh {
namespace {

int cpus_allowed() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof(set), &set) != 0) return -1;
    return CPU_COUNT(&set);
}

// The fewest CPUs any thread running a chunk may use.
int min_cpus_in_workers() {
    std::atomic<int> least{1 << 20};
    parallel_for(
        64, 2,
        [&](std::size_t, std::size_t) {
            const int c = cpus_allowed();
            for (int l = least.load(); c < l && !least.compare_exchange_weak(l, c);) {}
            std::this_thread::sleep_for(std::chrono::milliseconds(2));  // let the second thread take chunks
        },
        ParallelOptions{.grain = 1});
    return least.load();
}

TEST(Parallel, WorkersAreNotPinnedUnlessAsked) {
    ASSERT_FALSE(thread_pinning());
    EXPECT_FALSE(ParallelOptions{}.pin);
    const int mine = cpus_allowed();
    if (mine < 2) GTEST_SKIP() << "one CPU allowed: pinning cannot be seen";
    EXPECT_EQ(min_cpus_in_workers(), mine) << "a worker was pinned by default";
    set_thread_pinning(true);
    EXPECT_TRUE(ParallelOptions{}.pin);
    const int pinned = min_cpus_in_workers();
    set_thread_pinning(false);
    if (topology().from_hwloc) EXPECT_EQ(pinned, 1);
    EXPECT_EQ(cpus_allowed(), mine) << "the caller's thread must keep its affinity";
}

TEST(Parallel, HostExecutorRunsEveryChunkOnItsThreads) {
    std::mutex m;
    std::set<std::thread::id> host_threads;
    std::atomic<int> calls{0};
    set_executor([&](std::size_t chunks, const std::function<void(std::size_t)>& run) {
        ++calls;
        std::atomic<std::size_t> next{0};
        std::vector<std::thread> pool;
        for (int k = 0; k < 3; ++k)
            pool.emplace_back([&] {
                {
                    std::lock_guard<std::mutex> lock(m);
                    host_threads.insert(std::this_thread::get_id());
                }
                for (std::size_t c; (c = next.fetch_add(1)) < chunks;) run(c);
            });
        for (auto& t : pool) t.join();
    });
    const std::size_t n = 10007;
    std::vector<int> seen(n, 0);
    std::set<std::thread::id> ran_on;
    parallel_for(
        n, 2,
        [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) ++seen[i];
            std::lock_guard<std::mutex> lock(m);
            ran_on.insert(std::this_thread::get_id());
        },
        ParallelOptions{.grain = 100});
    EXPECT_EQ(calls.load(), 1);
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(seen[i], 1) << i;
    for (const auto& id : ran_on)
        EXPECT_TRUE(host_threads.count(id)) << "a chunk ran on a thread the host did not give";
    // threads <= 1 still runs inline, without the executor.
    const std::thread::id caller = std::this_thread::get_id();
    parallel_for(n, 1, [&](std::size_t, std::size_t) { EXPECT_EQ(std::this_thread::get_id(), caller); });
    EXPECT_EQ(calls.load(), 1);
    // An exception in a chunk comes back to the caller, after the executor returned.
    EXPECT_THROW(parallel_for(
                     n, 2,
                     [&](std::size_t b, std::size_t) {
                         if (b == 500) throw std::runtime_error("chunk 5");
                     },
                     ParallelOptions{.grain = 100}),
                 std::runtime_error);
    EXPECT_EQ(calls.load(), 2);
    set_executor({});
    parallel_for(n, 2, [&](std::size_t, std::size_t) {});
    EXPECT_EQ(calls.load(), 2) << "an empty executor restores the library's own threads";
}

// Small builds run on one thread; larger ones on the threads asked for.
TEST(BuildThreads, SmallBuildsRunOnOneThread) {
    EXPECT_EQ(build_threads(2, 1000), 1);
    EXPECT_EQ(build_threads(8, kMinPrimsForBuildThreads - 1), 1);
    EXPECT_EQ(build_threads(8, kMinPrimsForBuildThreads), 8);
    EXPECT_EQ(build_threads(2, 871414), 2);
    EXPECT_EQ(build_threads(1, 1u << 30), 1);
}

}  // namespace
}  // namespace simdbvh
