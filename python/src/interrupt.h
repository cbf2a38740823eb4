#pragma once
// Ctrl-C during a long query. Python runs its signal handlers (SIGINT's
// raises KeyboardInterrupt) only on the main thread and only when that thread
// runs Python code, so a batch traced without the GIL used to take the
// interrupt when it returned. A batch now asks Interrupt::stop() between its
// chunks: on the thread that called the query, when it is Python's main
// thread, at most every kInterruptCheck it takes the GIL for a moment and
// runs the pending handlers (PyErr_CheckSignals); once one raised, every
// thread skips its remaining chunks and the query raises that exception
// instead of returning. A handler that does not raise lets the batch go on
// (a handler must not refit the BVH being queried: the query holds it).
// The chunks that are traced are traced as before: answers are unchanged.
#include <pybind11/pybind11.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <chrono>
#include <thread>

namespace simdbvh::python {

namespace py = pybind11;

// At most 10 GIL acquisitions a second on the main thread: each costs a
// microsecond uncontended, at most the interpreter's switch interval (5 ms)
// when another thread runs Python code.
inline constexpr std::chrono::milliseconds kInterruptCheck{100};

// Python's main thread (threading.main_thread().ident), set when the module is imported.
inline unsigned long g_main_thread_ident = 0;

class Interrupt {
public:
    // With the GIL, on the thread that runs the query.
    Interrupt()
        : caller_(std::this_thread::get_id()),
          checks_(PyThread_get_thread_ident() == g_main_thread_ident),
          next_(std::chrono::steady_clock::now() + kInterruptCheck) {}
    Interrupt(const Interrupt&) = delete;
    Interrupt& operator=(const Interrupt&) = delete;

    // Whether this query is checked at all (run from Python's main thread).
    bool checks() const { return checks_; }

    // Without the GIL, from any thread: whether the query is to stop now.
    bool stop() {
        if (stopped_.load(std::memory_order_relaxed)) return true;
        if (!checks_ || std::this_thread::get_id() != caller_) return false;
        const auto now = std::chrono::steady_clock::now();
        if (now < next_) return false;
        next_ = now + kInterruptCheck;
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() == 0) return false;
        PyObject *type = nullptr, *value = nullptr, *trace = nullptr;
        PyErr_Fetch(&type, &value, &trace);  // kept for raise_if_stopped, not left pending on this thread
        type_ = py::reinterpret_steal<py::object>(type);
        value_ = py::reinterpret_steal<py::object>(value);
        trace_ = py::reinterpret_steal<py::object>(trace);
        stopped_.store(true, std::memory_order_relaxed);
        return true;
    }

    // With the GIL, after the batch: raises the handler's exception (KeyboardInterrupt for Ctrl-C), if any.
    void raise_if_stopped() {
        if (!stopped_.load(std::memory_order_relaxed)) return;
        PyErr_Restore(type_.release().ptr(), value_.release().ptr(), trace_.release().ptr());
        throw py::error_already_set();
    }

private:
    std::thread::id caller_;
    bool checks_;                                 // signals are handled on Python's main thread only
    std::chrono::steady_clock::time_point next_;  // read and written by the calling thread only
    std::atomic<bool> stopped_{false};
    py::object type_, value_, trace_;  // set and released with the GIL
};

// Work per block of for_blocks: interrupts wait at most about this long.
inline constexpr std::chrono::milliseconds kBlockTime{250};
// Work left after the first block that is done in one more call: not worth
// blocks (their calls, and for point queries the sort, cost a few percent of
// a cheap query) and stopped at most this late.
inline constexpr std::chrono::milliseconds kWholeTime{1000};

// The tests' handle on the timing (simdbvh._set_block_times): kBlockTime and
// kWholeTime times this factor, so that a test can force blocks on any
// machine instead of guessing a query long enough; and the library calls
// for_blocks and for_point_blocks made, so that it can see them.
inline std::atomic<double> g_block_time_scale{1.0};
inline std::atomic<std::size_t> g_block_calls{0};

inline double block_seconds() {
    return std::chrono::duration<double>(kBlockTime).count() * g_block_time_scale.load(std::memory_order_relaxed);
}
inline double whole_seconds() {
    return std::chrono::duration<double>(kWholeTime).count() * g_block_time_scale.load(std::memory_order_relaxed);
}

// Whether `items` more at `seconds_per_item` come within kWholeTime.
inline bool fits_whole(double seconds_per_item, std::size_t items) {
    return seconds_per_item * double(items) < whole_seconds();
}

// Calls f(begin, end) on the calling thread for consecutive blocks of [0, n)
// (f may spread its block over threads), stopping between blocks when
// interrupted: for the library's batched queries that take their whole span
// in one call, and for loops over single points or rays. The blocks start at
// 256 items and grow (at most 8x a block, at most max_block) toward
// kBlockTime of work each, so a cheap query makes few calls and an expensive
// one is still stopped within a fraction of a second; once the rest fits
// within kWholeTime it is one call. When the query cannot be interrupted (not
// on Python's main thread) it is one call. Without the GIL.
template <class F>
void for_blocks(std::size_t n, std::size_t max_block, Interrupt& interrupt, F&& f) {
    if (!interrupt.checks()) {
        if (n) f(std::size_t(0), n);
        return;
    }
    std::size_t block = std::min<std::size_t>(256, max_block);
    for (std::size_t b = 0; b < n && !interrupt.stop();) {
        const std::size_t e = std::min(n, b + block);
        const auto t0 = std::chrono::steady_clock::now();
        g_block_calls.fetch_add(1, std::memory_order_relaxed);
        f(b, e);
        const double per_item =
            std::max(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1e-7) /
            double(e - b);
        b = e;
        if (b < n && fits_whole(per_item, n - b)) {
            if (!interrupt.stop()) {
                g_block_calls.fetch_add(1, std::memory_order_relaxed);
                f(b, n);
            }
            return;
        }
        const double fit = block_seconds() / per_item;
        block = std::size_t(std::clamp(fit, 1.0, double(std::min(8 * block, max_block))));
    }
}

}  // namespace simdbvh::python
