#pragma once
// Internal: working arrays a batched call keeps from call to call, per calling
// thread. A batch's workers (parallel_for's threads, a host executor's, or the
// caller itself) each take a set for their chunks and give it back, so a batch
// makes at most one set per worker running at once, and the next batch from the
// same thread finds them made. A call that starts on a thread while another
// call from it holds a set (a host executor's waiting thread taking other work)
// takes another one: sets are never shared. Users: the scene batches
// (scene/src/traverse.cpp) and the wide trees' sorted batches
// (bvh8/src/traverse.cpp).
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace simdbvh::detail {

template <class T>
class ScratchPool {
public:
    // The calling thread's pool (its workers' threads end with the call).
    static ScratchPool& of_this_thread() {
        thread_local ScratchPool pool;
        return pool;
    }
    std::unique_ptr<T> take() {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (free_.empty()) return std::make_unique<T>();
        std::unique_ptr<T> x = std::move(free_.back());
        free_.pop_back();
        return x;
    }
    void give(std::unique_ptr<T> x) {
        const std::lock_guard<std::mutex> lock(mutex_);
        free_.push_back(std::move(x));
    }

private:
    std::mutex mutex_;
    std::vector<std::unique_ptr<T>> free_;
};

}  // namespace simdbvh::detail
