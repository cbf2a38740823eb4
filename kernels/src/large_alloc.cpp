#include "simdbvh/kernels/large_alloc.h"

#include <sys/mman.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <new>
#include <vector>

namespace simdbvh {

// From kLargeBytes up: an anonymous mapping of its own, 2 MiB aligned and
// advised as huge pages in full (the tail's partial 2 MiB page included).
// Through malloc a large block can come from the heap (once glibc's dynamic
// mmap threshold has risen past its size), where the 4 KiB-page ends outside
// the advised range and a brk-grown heap fault page by page: measured on the
// dragon's BVH8 pack, about 450 first-touch faults for 8 MB of nodes.
// Smaller blocks: aligned operator new.
// Under AddressSanitizer large blocks stay on operator new (2 MiB aligned,
// advised inside), so its redzones still catch a write past a block's end.
namespace {
constexpr std::size_t kHugePage = std::size_t(2) << 20;
std::size_t round_up(std::size_t n) { return (n + kHugePage - 1) / kHugePage * kHugePage; }
#if defined(__SANITIZE_ADDRESS__)  // GCC
#define SIMDBVH_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)  // Clang (the fuzz build)
#define SIMDBVH_ASAN 1
#endif
#endif
#if defined(SIMDBVH_ASAN)
constexpr bool kOwnMappings = false;
#else
constexpr bool kOwnMappings = true;
#endif

// The whole 2 MiB pages inside [p, p + bytes) advised as huge pages (the
// ASan path, whose blocks come from operator new).
void advise_huge_pages(const void* p, std::size_t bytes) noexcept {
    if (bytes < kLargeBytes) return;
    const auto a = reinterpret_cast<std::uintptr_t>(p);
    const std::uintptr_t lo = (a + kHugePage - 1) / kHugePage * kHugePage;
    const std::uintptr_t hi = (a + bytes) / kHugePage * kHugePage;
    if (hi > lo) madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);
}

// Blocks freed while a LargeAllocReuse scope is open, for the next large
// allocations of the same build: best fit, the unused rest of the block
// unmapped at once (kept, it would stay resident and raise the build's peak);
// all unmapped when the last scope closes.
struct FreeBlock {
    std::uintptr_t p;
    std::size_t size;
};
std::mutex g_mutex;
std::vector<FreeBlock> g_free;  // guarded by g_mutex
std::atomic<int> g_scopes{0};

void* reuse(std::size_t size) {
    std::lock_guard<std::mutex> lock(g_mutex);
    std::size_t best = g_free.size();
    for (std::size_t i = 0; i < g_free.size(); ++i)
        if (g_free[i].size >= size && (best == g_free.size() || g_free[i].size < g_free[best].size)) best = i;
    if (best == g_free.size()) return nullptr;
    const FreeBlock b = g_free[best];
    g_free.erase(g_free.begin() + std::ptrdiff_t(best));
    if (b.size > size) munmap(reinterpret_cast<void*>(b.p + size), b.size - size);
    return reinterpret_cast<void*>(b.p);
}

bool keep(void* p, std::size_t size) noexcept {
    std::lock_guard<std::mutex> lock(g_mutex);
    if (g_scopes.load() == 0) return false;  // read under the lock: release_all cannot miss it
    try {
        g_free.push_back({reinterpret_cast<std::uintptr_t>(p), size});
    } catch (...) {
        return false;
    }
    return true;
}

void release_all() {
    std::vector<FreeBlock> blocks;
    {
        std::lock_guard<std::mutex> lock(g_mutex);
        blocks.swap(g_free);
    }
    for (const FreeBlock& b : blocks) munmap(reinterpret_cast<void*>(b.p), b.size);
}
}  // namespace

LargeAllocReuse::LargeAllocReuse() noexcept { g_scopes.fetch_add(1); }
LargeAllocReuse::~LargeAllocReuse() {
    if (g_scopes.fetch_sub(1) == 1) release_all();
}

void* large_alloc(std::size_t bytes, std::size_t align) {
    if (bytes < kLargeBytes || align > kHugePage) return ::operator new(bytes, std::align_val_t(align));
    if (!kOwnMappings) {
        void* p = ::operator new(bytes, std::align_val_t(kHugePage));
        advise_huge_pages(p, bytes);
        return p;
    }
    const std::size_t size = round_up(bytes);
    if (size < bytes) throw std::bad_alloc();
    if (g_scopes.load() > 0)
        if (void* p = reuse(size)) return p;
    void* m = mmap(nullptr, size + kHugePage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (m == MAP_FAILED) throw std::bad_alloc();
    const auto a = reinterpret_cast<std::uintptr_t>(m);
    const std::uintptr_t p = (a + kHugePage - 1) / kHugePage * kHugePage;
    if (p > a) munmap(m, p - a);                              // the unaligned head
    if (a + kHugePage > p) munmap(reinterpret_cast<void*>(p + size), a + kHugePage - p);  // and tail
    madvise(reinterpret_cast<void*>(p), size, MADV_HUGEPAGE);  // advice only: no THP support changes nothing
    return reinterpret_cast<void*>(p);
}

void large_free(void* p, std::size_t bytes, std::size_t align) noexcept {
    if (!p) return;
    if (bytes < kLargeBytes || align > kHugePage) ::operator delete(p, std::align_val_t(align));
    else if (!kOwnMappings) ::operator delete(p, std::align_val_t(kHugePage));
    else if (!keep(p, round_up(bytes))) munmap(p, round_up(bytes));
}

}  // namespace simdbvh
