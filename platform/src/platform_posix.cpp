// The platform layer (simdbvh/platform/internal/platform.h) on POSIX systems;
// mremap, mincore's page vector and the cache-size sysconf names are Linux's.
#include "simdbvh/platform/internal/platform.h"

#include <sys/mman.h>
#include <unistd.h>

namespace simdbvh::platform {

void* map_pages(std::size_t bytes) noexcept {
    void* m = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    return m == MAP_FAILED ? nullptr : m;
}

void unmap_pages(void* p, std::size_t bytes) noexcept { munmap(p, bytes); }

void advise_huge_pages(void* p, std::size_t bytes) noexcept {
#if defined(MADV_HUGEPAGE)
    madvise(p, bytes, MADV_HUGEPAGE);  // no THP support changes nothing
#else
    (void)p, (void)bytes;
#endif
}

bool resident_pages(const void* p, std::size_t bytes, unsigned char* resident) noexcept {
#if defined(__linux__)
    return mincore(const_cast<void*>(p), bytes, resident) == 0;
#else
    (void)p, (void)bytes, (void)resident;
    return false;
#endif
}

bool move_pages(void* from, std::size_t bytes, void* to) noexcept {
#if defined(__linux__)
    return mremap(from, bytes, bytes, MREMAP_MAYMOVE | MREMAP_FIXED, to) != MAP_FAILED;
#else
    (void)from, (void)bytes, (void)to;
    return false;
#endif
}

std::size_t cache_bytes(int level) noexcept {
    long v = 0;
#if defined(_SC_LEVEL1_DCACHE_SIZE)
    if (level == 1) v = sysconf(_SC_LEVEL1_DCACHE_SIZE);
    if (level == 2) v = sysconf(_SC_LEVEL2_CACHE_SIZE);
    if (level == 3) v = sysconf(_SC_LEVEL3_CACHE_SIZE);
#else
    (void)level;
#endif
    return v > 0 ? static_cast<std::size_t>(v) : 0;
}

std::uint64_t physical_memory_bytes() noexcept {
#if defined(_SC_PHYS_PAGES)
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0) return 0;
    std::uint64_t r;
    return __builtin_mul_overflow(std::uint64_t(pages), std::uint64_t(page), &r) ? ~std::uint64_t(0) : r;
#else
    return 0;
#endif
}

}  // namespace simdbvh::platform
