// Builds on a host's executor (set_executor): every parallel part of the BVH2
// build (subtree tasks, parallel binning), the collapse and the pack goes to
// the host's executor, and the library starts no thread of its own; the tree
// is byte-identical to the one-thread build, whatever runs the tasks.
//
// Threads are counted by interposing pthread_create in this test binary (not
// under a sanitizer, whose runtime interposes it too).
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <functional>
#include <thread>
#include <vector>

#include "simdbvh/bvh2/bvh2.h"
#include "simdbvh/bvh8/bvh8.h"
#include "simdbvh/platform/parallel.h"
#include "simdbvh/workloads/rays.h"
#include "simdbvh/workloads/scenes.h"
#include "support/sanitizer.h"

#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#include <dlfcn.h>
#include <pthread.h>

namespace {
std::atomic<int> g_pthread_creates{0};
}

extern "C" int pthread_create(pthread_t* thread, const pthread_attr_t* attr, void* (*start)(void*), void* arg) {
    using Fn = int (*)(pthread_t*, const pthread_attr_t*, void* (*)(void*), void*);
    static const Fn real = reinterpret_cast<Fn>(dlsym(RTLD_NEXT, "pthread_create"));
    g_pthread_creates.fetch_add(1);
    return real(thread, attr, start, arg);
}
#define SIMDBVH_COUNTS_THREADS 1
#endif

namespace simdbvh {
namespace {

const Mesh& mesh() {  // large enough for subtree tasks (32k) and parallel binning (128k)
    static const Mesh m = workloads::load_scene("icosphere-7");
    return m;
}

template <int N>
void expect_same_tree(const BvhN<N>& a, const BvhN<N>& b) {
    ASSERT_EQ(a.nodes().size(), b.nodes().size());
    ASSERT_EQ(a.blocks().size(), b.blocks().size());
    EXPECT_EQ(std::memcmp(a.nodes().data(), b.nodes().data(), a.nodes().size() * sizeof(typename BvhN<N>::Node)), 0);
    EXPECT_EQ(std::memcmp(a.blocks().data(), b.blocks().data(), a.blocks().size() * sizeof(Tri8)), 0);
}

Bvh8 build(int threads) {
    BuildOptions b;
    b.threads = threads;
    WideOptions w;
    w.threads = threads;
    return Bvh8::build(mesh(), b, w);
}

struct ExecutorScope {
    explicit ExecutorScope(Executor e) { set_executor(std::move(e)); }
    ~ExecutorScope() { set_executor({}); }
};

TEST(HostExecutor, BuildStartsNoThreadOfItsOwn) {
#ifndef SIMDBVH_COUNTS_THREADS
    GTEST_SKIP() << "thread counting needs pthread_create, which the sanitizer runtime interposes";
#else
    const Bvh8 one = build(1);
    // Without an executor, a two-thread build starts threads: the counter sees them.
    const int before_own = g_pthread_creates.load();
    const Bvh8 own = build(2);
    EXPECT_GT(g_pthread_creates.load(), before_own) << "the counter does not see the library's threads";
    expect_same_tree(own, one);

    // An executor that runs every chunk on the calling thread, in order.
    std::atomic<int> calls{0};
    std::atomic<std::size_t> chunks_run{0};
    ExecutorScope scope([&](std::size_t chunks, const std::function<void(std::size_t)>& run) {
        ++calls;
        for (std::size_t c = 0; c < chunks; ++c, ++chunks_run) run(c);
    });
    const int before = g_pthread_creates.load();
    const Bvh8 hosted = build(2);
    EXPECT_EQ(g_pthread_creates.load(), before) << "the build started a thread despite the host's executor";
    EXPECT_GT(calls.load(), 2) << "subtree tasks, binning, collapse and pack should all reach the executor";
    EXPECT_GT(chunks_run.load(), std::size_t(calls.load()));
    expect_same_tree(hosted, one);
#endif
}

TEST(HostExecutor, NestedTasksOnHostThreadsGiveTheSameTree) {
    const Bvh8 one = build(1);
    // Every call runs its chunks on threads of its own, in reverse order of
    // start (the right subtree often first); nested calls nest.
    std::atomic<int> calls{0};
    ExecutorScope scope([&](std::size_t chunks, const std::function<void(std::size_t)>& run) {
        ++calls;
        std::vector<std::thread> pool;
        for (std::size_t c = chunks; c-- > 0;) pool.emplace_back([&run, c] { run(c); });
        for (std::thread& t : pool) t.join();
    });
    expect_same_tree(build(2), one);
    if (!test::kUnderSanitizer) expect_same_tree(build(4), one);  // (TSan: 5 s a build)
    EXPECT_GT(calls.load(), 0);
    // An exception inside a task comes back to the caller of run_tasks.
    EXPECT_THROW(run_tasks(3,
                           [](std::size_t k) {
                               if (k == 2) throw std::runtime_error("task 2");
                           }),
                 std::runtime_error);
}

TEST(HostExecutor, RunTasksRunsEveryTaskOnceWithOrWithoutAnExecutor) {
    for (bool hosted : {false, true}) {
        if (hosted)
            set_executor([](std::size_t chunks, const std::function<void(std::size_t)>& run) {
                for (std::size_t c = chunks; c-- > 0;) run(c);
            });
        std::vector<std::atomic<int>> ran(5);
        run_tasks(5, [&](std::size_t k) { ran[k]++; });
        for (std::size_t k = 0; k < ran.size(); ++k) EXPECT_EQ(ran[k].load(), 1) << "task " << k;
        const std::thread::id caller = std::this_thread::get_id();
        run_tasks(1, [&](std::size_t) { EXPECT_EQ(std::this_thread::get_id(), caller); });
        set_executor({});
    }
}

// A sorted batch's blocks on a host executor whose thread, while the batch
// waits for its blocks, runs another sorted trace (a work-stealing pool's
// thread taking other work): each keeps its own order, both give the BVH2's hits.
TEST(HostExecutor, SortedTraceStartedWhileAnotherWaits) {
    const Mesh soup = workloads::random_soup(20000, 3);
    const Bvh2 bvh2 = Bvh2::build(soup);
    const Bvh8 bvh = Bvh8::build(bvh2);
    const std::vector<Ray> outer = workloads::generate_rays(soup, workloads::RayKind::diffuse, 40000, 1);
    const std::vector<Ray> inner = workloads::generate_rays(soup, workloads::RayKind::incoherent, 30000, 2);
    std::vector<Hit> want_outer(outer.size()), want_inner(inner.size());
    intersect(bvh2, outer, want_outer);
    intersect(bvh2, inner, want_inner);
    TraceOptions sorted;
    sorted.reorder = Reorder::on;
    std::vector<Hit> got_inner(inner.size());
    int stolen = 0;
    {
        ExecutorScope scope([&](std::size_t chunks, const std::function<void(std::size_t)>& run) {
            if (stolen++ == 0) intersect(bvh, inner, got_inner, sorted);  // one thread: no executor
            for (std::size_t c = 0; c < chunks; ++c) run(c);
        });
        TraceOptions two = sorted;
        two.threads = 2;
        std::vector<Hit> got_outer(outer.size());
        intersect(bvh, outer, got_outer, two);
        ASSERT_GE(stolen, 1) << "the blocks went to the executor";
        for (std::size_t i = 0; i < outer.size(); ++i) ASSERT_EQ(got_outer[i], want_outer[i]) << "outer ray " << i;
    }
    for (std::size_t i = 0; i < inner.size(); ++i) ASSERT_EQ(got_inner[i], want_inner[i]) << "inner ray " << i;
}

}  // namespace
}  // namespace simdbvh
