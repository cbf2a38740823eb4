#pragma once
// The operating system under the library: virtual memory for the large
// allocations (large_alloc.cpp), the cache sizes and the physical memory
// (topology.cpp, io's read limits). One implementation per OS family:
// platform/src/platform_posix.cpp (Linux; the mremap and mincore parts report
// "unsupported" on other POSIX systems). A macOS or Windows port is this file's
// functions (docs/portability.md). Every function is noexcept and reports
// failure by its result: the callers fall back (operator new, no reuse, the
// read limits' constants).
#include <cstddef>
#include <cstdint>

namespace simdbvh::platform {

// Virtual memory in whole pages of kPageBytes (the callers pass 2 MiB multiples).
inline constexpr std::size_t kPageBytes = 4096;
// A fresh anonymous read-write mapping of `bytes`; nullptr when refused.
void* map_pages(std::size_t bytes) noexcept;
// Returns [p, p + bytes) of a mapping from map_pages to the OS.
void unmap_pages(void* p, std::size_t bytes) noexcept;
// Asks for transparent huge pages over [p, p + bytes); advice only.
void advise_huge_pages(void* p, std::size_t bytes) noexcept;
// resident[i] bit 0: the i-th kPageBytes page of [p, p + bytes) is in memory.
// False when the OS cannot tell (the caller then assumes all are).
bool resident_pages(const void* p, std::size_t bytes, unsigned char* resident) noexcept;
// Moves the pages of [from, from + bytes) to `to` (replacing what is mapped
// there) by their page tables, no copy; false when refused or unsupported.
bool move_pages(void* from, std::size_t bytes, void* to) noexcept;

// The machine: the data or unified cache of level 1, 2 or 3 in bytes, and the
// physical memory; 0 when unknown.
std::size_t cache_bytes(int level) noexcept;
std::uint64_t physical_memory_bytes() noexcept;

}  // namespace simdbvh::platform
