#pragma once
// Splits [0, n) over `threads` std::threads (the caller's thread is one of
// them), in chunks handed out dynamically. threads <= 1 runs inline: the
// library never starts a thread the caller did not ask for. Threads that
// cannot start (a process or memory limit) are done without: the ones that
// started, or the caller alone, finish the work; the process never terminates.
//
// A host with its own thread pool can take the work instead (set_executor):
// then no thread is started by the library at all. Worker threads are not
// pinned to cores unless the host asks (set_thread_pinning), so they never
// fight a host's own placement.
#include <cstddef>
#include <functional>

namespace simdbvh {

// Process-wide: pin each worker thread the library starts to one core (hwloc,
// worker k to core k; the caller's thread is never moved). Off by default;
// the bench turns it on for its all-core rows. Safe to call at any time.
void set_thread_pinning(bool on);
bool thread_pinning();

struct ParallelOptions {
    std::size_t grain = 2048;     // items per chunk
    bool pin = thread_pinning();  // pin the threads this call starts (see set_thread_pinning)
};

// Options for items whose cost is known up front (a brute-force ray costs one
// test per triangle): chunks of about 2^20 unit costs, at most 2048 items and
// at least min_items, so that a few hundred expensive items still spread over
// every thread instead of fitting in one default-sized chunk.
ParallelOptions options_for_cost(std::size_t cost_per_item, std::size_t min_items = 1);

// A host executor: must call run(c) exactly once for every chunk c in
// [0, chunks), on any of its threads (the calling thread included), and
// return when every call has returned. run never throws (parallel_for
// captures the first exception and rethrows it after the executor returns).
using Executor = std::function<void(std::size_t chunks, const std::function<void(std::size_t chunk)>& run)>;
// Process-wide: with an executor set, parallel_for with threads > 1 and
// run_tasks give their chunks to it instead of starting threads (threads <= 1
// still runs inline): the builds (BVH2 subtrees and binning, collapse, pack)
// and the batched traces then start no thread of their own.
// An empty function restores the library's own threads. Safe to call at any
// time; a parallel_for already running keeps the executor it started with.
void set_executor(Executor executor);

void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t, std::size_t)>& body,
                  const ParallelOptions& opts = {});

// Fork-join: runs task(k) for every k in [0, count) and returns when all have
// returned, rethrowing the first exception. With a host executor the tasks
// are its chunks (the builders call this recursively, one level per subtree
// split: the executor must allow a chunk to call it again, as TBB's and
// OpenMP's task pools do). Without one, task 0 runs on the calling thread and
// each other task on a thread of its own (unpinned); a task whose thread
// cannot start runs on the calling thread. count <= 1 runs inline.
void run_tasks(std::size_t count, const std::function<void(std::size_t)>& task);

}  // namespace simdbvh
