#include "simdbvh/platform/parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#if __has_include("simdbvh/platform/topology.h")
#include "simdbvh/platform/topology.h"
#define SIMDBVH_CAN_PIN 1
#endif

namespace simdbvh {

namespace {

std::atomic<bool> g_pin{false};
std::mutex g_executor_mutex;
std::shared_ptr<const Executor> g_executor;  // null: our own threads

std::shared_ptr<const Executor> current_executor() {
    std::lock_guard<std::mutex> lock(g_executor_mutex);
    return g_executor;
}

}  // namespace

void set_thread_pinning(bool on) { g_pin.store(on, std::memory_order_relaxed); }
bool thread_pinning() { return g_pin.load(std::memory_order_relaxed); }

void set_executor(Executor executor) {
    auto e = executor ? std::make_shared<const Executor>(std::move(executor)) : nullptr;
    std::lock_guard<std::mutex> lock(g_executor_mutex);
    g_executor = std::move(e);
}

ParallelOptions options_for_cost(std::size_t cost_per_item, std::size_t min_items) {
    constexpr std::size_t kChunkCost = std::size_t(1) << 20;
    ParallelOptions o;
    o.grain = std::clamp<std::size_t>(kChunkCost / std::max<std::size_t>(1, cost_per_item),
                                      std::clamp<std::size_t>(min_items, 1, 2048), 2048);
    return o;
}

void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t, std::size_t)>& body,
                  const ParallelOptions& opts) {
    const std::size_t grain = std::max<std::size_t>(1, opts.grain);
    if (threads <= 1 || n <= grain) {
        if (n) body(0, n);
        return;
    }
    const std::size_t chunks = (n + grain - 1) / grain;
    std::exception_ptr error;
    std::mutex error_mutex;
    if (const std::shared_ptr<const Executor> ex = current_executor()) {
        (*ex)(chunks, [&](std::size_t c) {
            if (c >= chunks) return;
            try {
                body(c * grain, std::min(n, (c + 1) * grain));
            } catch (...) {
                std::lock_guard<std::mutex> lock(error_mutex);
                if (!error) error = std::current_exception();
            }
        });
        if (error) std::rethrow_exception(error);
        return;
    }
    const int workers = int(std::min<std::size_t>(std::size_t(threads), chunks));
    std::atomic<std::size_t> next{0};
    auto work = [&](int k) {
#ifdef SIMDBVH_CAN_PIN
        // Workers we start are pinned one per core; the caller's thread (k = 0)
        // keeps its own affinity: the library never changes it.
        if (opts.pin && k > 0) pin_current_thread_to_core(k % std::max(1, topology().physical_cores));
#else
        (void)k;
#endif
        try {
            for (;;) {
                const std::size_t c = next.fetch_add(1, std::memory_order_relaxed);
                if (c >= chunks) break;
                body(c * grain, std::min(n, (c + 1) * grain));
            }
        } catch (...) {
            std::lock_guard<std::mutex> lock(error_mutex);
            if (!error) error = std::current_exception();
        }
    };
    // A thread that cannot start (std::system_error at a process or memory
    // limit, or std::bad_alloc) is not an error: the chunks are handed out
    // dynamically, so the threads that did start, or the caller alone, finish
    // the work. Never unwind with joinable threads (std::terminate).
    std::vector<std::thread> pool;
    try {
        pool.reserve(std::size_t(workers - 1));
        for (int k = 1; k < workers; ++k) pool.emplace_back(work, k);
    } catch (const std::exception&) {}
    work(0);
    for (std::thread& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

void run_tasks(std::size_t count, const std::function<void(std::size_t)>& task) {
    if (count == 0) return;
    if (count == 1) {
        task(0);
        return;
    }
    std::exception_ptr error;
    std::mutex error_mutex;
    auto guarded = [&](std::size_t k) {
        try {
            task(k);
        } catch (...) {
            std::lock_guard<std::mutex> lock(error_mutex);
            if (!error) error = std::current_exception();
        }
    };
    if (const std::shared_ptr<const Executor> ex = current_executor()) {
        (*ex)(count, [&](std::size_t k) {
            if (k < count) guarded(k);
        });
    } else {
        // Everything allocated before the first thread starts: nothing below
        // throws while a thread is joinable (std::terminate).
        std::vector<std::thread> threads;
        threads.reserve(count - 1);
        std::vector<char> started(count, 0);
        for (std::size_t k = 1; k < count; ++k) {
            try {
                threads.emplace_back(guarded, k);
                started[k] = 1;
            } catch (const std::exception&) {  // no thread (a process or memory limit): run it here below
            }
        }
        guarded(0);
        for (std::size_t k = 1; k < count; ++k)
            if (!started[k]) guarded(k);
        for (std::thread& t : threads) t.join();
    }
    if (error) std::rethrow_exception(error);
}

}  // namespace simdbvh
