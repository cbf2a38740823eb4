#pragma once
// A readers-writer lock for one BVH: queries share it, refit has it alone.
// Unlike glibc's std::shared_mutex (readers first), a waiting writer holds
// back new readers, so a refit is not starved by queries that overlap without
// end on other threads. Not recursive: a thread takes it once per call. Take
// it without the GIL (a thread waiting here while holding the GIL would stop
// the thread that has the lock from ever returning to Python).
#include <condition_variable>
#include <mutex>

namespace simdbvh::python {

class RwLock {
public:
    void lock_shared() {
        std::unique_lock<std::mutex> l(m_);
        cv_.wait(l, [&] { return !writer_ && writers_waiting_ == 0; });
        ++readers_;
    }
    void unlock_shared() {
        std::lock_guard<std::mutex> l(m_);
        if (--readers_ == 0) cv_.notify_all();
    }
    void lock() {
        std::unique_lock<std::mutex> l(m_);
        ++writers_waiting_;
        cv_.wait(l, [&] { return !writer_ && readers_ == 0; });
        --writers_waiting_;
        writer_ = true;
    }
    void unlock() {
        std::lock_guard<std::mutex> l(m_);
        writer_ = false;
        cv_.notify_all();
    }

private:
    std::mutex m_;
    std::condition_variable cv_;
    int readers_ = 0;
    int writers_waiting_ = 0;
    bool writer_ = false;
};

}  // namespace simdbvh::python
