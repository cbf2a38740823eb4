#pragma once
// Splits [0, n) over `threads` std::threads (the caller's thread is one of
// them), in chunks handed out dynamically. threads <= 1 runs inline: the
// library never starts a thread the caller did not ask for. Threads that
// cannot start (a process or memory limit) are done without: the ones that
// started, or the caller alone, finish the work; the process never terminates.
#include <cstddef>
#include <functional>

namespace simdbvh {

struct ParallelOptions {
    std::size_t grain = 2048;  // rays per chunk
    bool pin = true;           // pin started worker k to core k (hwloc) when available; never the caller
};

void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t, std::size_t)>& body,
                  const ParallelOptions& opts = {});

}  // namespace simdbvh
