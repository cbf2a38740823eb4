#pragma once
// The machine the code runs on: cores, caches, ISA (for benchmark context and
// CLI output), and thread pinning. Uses hwloc when the library was built with
// it, else std::thread::hardware_concurrency() and sysconf cache sizes.
#include <cstddef>
#include <string>

namespace simdbvh {

struct Topology {
    int physical_cores = 0;     // 0 when unknown
    int logical_cpus = 0;       // processing units (hardware threads)
    std::size_t l1d_bytes = 0;  // per core; 0 when unknown
    std::size_t l2_bytes = 0;
    std::size_t l3_bytes = 0;  // per L3 instance
    bool from_hwloc = false;
};

// Detected once (thread-safe).
const Topology& topology();

// One line: CPU brand, cores/threads, caches, supported ISAs and the active one,
// e.g. "Intel(R) Xeon(R) ... | 2 cores, 2 threads | L1d 48 KiB, L2 2 MiB, L3 105 MiB |
// ISAs scalar avx2 avx512 (active avx512) | hwloc".
std::string machine_line();

// Binds the calling thread to the PUs of physical core `core` (0-based, hwloc
// logical index). False when hwloc is unavailable, the core does not exist,
// or the OS refuses.
bool pin_current_thread_to_core(int core);

}  // namespace simdbvh
