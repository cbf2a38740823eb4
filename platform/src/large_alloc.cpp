#include "simdbvh/platform/large_alloc.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <new>
#include <vector>

#include "simdbvh/platform/internal/platform.h"

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
    if (hi > lo) platform::advise_huge_pages(reinterpret_cast<void*>(lo), hi - lo);
}

// A fresh anonymous mapping of `size` bytes (a multiple of 2 MiB), 2 MiB
// aligned, advised as huge pages; nullptr when the kernel refuses.
void* map_aligned(std::size_t size) noexcept {
    void* m = platform::map_pages(size + kHugePage);
    if (!m) return nullptr;
    const auto a = reinterpret_cast<std::uintptr_t>(m);
    const std::uintptr_t p = (a + kHugePage - 1) / kHugePage * kHugePage;
    if (p > a) platform::unmap_pages(m, p - a);  // the unaligned head
    if (a + kHugePage > p) platform::unmap_pages(reinterpret_cast<void*>(p + size), a + kHugePage - p);  // and tail
    platform::advise_huge_pages(reinterpret_cast<void*>(p), size);  // advice only: no THP support changes nothing
    return reinterpret_cast<void*>(p);
}

// Blocks freed while a LargeAllocReuse scope is open, for the next large
// allocations of the same build (those inside a LargeAllocTake). Only their
// resident part is kept (a vector reserved at twice what it used, as the
// BVH2's nodes are, keeps the pages it touched; the untouched tail is unmapped
// at once), so what is kept is memory the kernel has already cleared: an
// allocation that takes it costs no page faults. It takes the best-fitting
// block (the rest of it stays kept); when none is large enough, the kept
// blocks are moved into one fresh range (mremap: page tables only, no copy),
// largest first, and the rest of the range is fresh memory. All are unmapped
// when the last scope ends.
struct FreeBlock {
    std::uintptr_t p;
    std::size_t size;
};
std::mutex g_mutex;
std::vector<FreeBlock> g_free;  // guarded by g_mutex
std::atomic<int> g_scopes{0};
thread_local int t_take = 0;  // LargeAllocTake scopes open on this thread

// [p, p + size) up to the end of the 2 MiB page holding its last resident
// 4 KiB page (0: nothing resident; size when mincore cannot tell).
std::size_t resident_prefix(std::uintptr_t p, std::size_t size) noexcept {
    constexpr std::size_t kPage = platform::kPageBytes;
    const std::size_t pages = size / kPage;
    std::vector<unsigned char> in;
    try {
        in.resize(pages);
    } catch (...) {
        return size;
    }
    if (!platform::resident_pages(reinterpret_cast<const void*>(p), size, in.data())) return size;
    std::size_t last = pages;
    while (last > 0 && !(in[last - 1] & 1)) --last;
    return round_up(last * kPage);
}

void* reuse(std::size_t size) {
    std::lock_guard<std::mutex> lock(g_mutex);
    if (g_free.empty()) return nullptr;
    std::size_t best = g_free.size();
    for (std::size_t i = 0; i < g_free.size(); ++i)
        if (g_free[i].size >= size && (best == g_free.size() || g_free[i].size < g_free[best].size)) best = i;
    if (best < g_free.size()) {
        FreeBlock& b = g_free[best];
        const std::uintptr_t p = b.p;
        if (b.size == size) g_free.erase(g_free.begin() + std::ptrdiff_t(best));
        else b = {b.p + size, b.size - size};  // the rest stays kept
        return reinterpret_cast<void*>(p);
    }
    void* m = map_aligned(size);
    if (!m) return nullptr;
    std::sort(g_free.begin(), g_free.end(), [](const FreeBlock& a, const FreeBlock& b) { return a.size < b.size; });
    auto dst = reinterpret_cast<std::uintptr_t>(m);
    const std::uintptr_t end = dst + size;
    while (dst < end && !g_free.empty()) {
        FreeBlock& b = g_free.back();
        const std::size_t take = std::min(b.size, end - dst);
        if (!platform::move_pages(reinterpret_cast<void*>(b.p), take, reinterpret_cast<void*>(dst)))
            break;  // the rest of the range stays fresh memory
        dst += take;
        if (take == b.size) g_free.pop_back();
        else b = {b.p + take, b.size - take};
    }
    return m;
}

bool keep(void* p, std::size_t size) noexcept {
    std::lock_guard<std::mutex> lock(g_mutex);
    if (g_scopes.load() == 0) return false;  // read under the lock: release_all cannot miss it
    const auto a = reinterpret_cast<std::uintptr_t>(p);
    const std::size_t resident = resident_prefix(a, size);
    if (resident == 0) return false;
    try {
        g_free.push_back({a, resident});
    } catch (...) {
        return false;
    }
    if (resident < size) platform::unmap_pages(reinterpret_cast<void*>(a + resident), size - resident);
    return true;
}

void release_all() {
    std::vector<FreeBlock> blocks;
    {
        std::lock_guard<std::mutex> lock(g_mutex);
        blocks.swap(g_free);
    }
    for (const FreeBlock& b : blocks) platform::unmap_pages(reinterpret_cast<void*>(b.p), b.size);
}
}  // namespace

LargeAllocReuse::LargeAllocReuse() noexcept { g_scopes.fetch_add(1); }
LargeAllocReuse::~LargeAllocReuse() {
    if (g_scopes.fetch_sub(1) == 1) release_all();
}

LargeAllocTake::LargeAllocTake() noexcept { ++t_take; }
LargeAllocTake::~LargeAllocTake() { --t_take; }

void* large_alloc(std::size_t bytes, std::size_t align) {
    if (bytes < kLargeBytes || align > kHugePage) return ::operator new(bytes, std::align_val_t(align));
    if (!kOwnMappings) {
        void* p = ::operator new(bytes, std::align_val_t(kHugePage));
        advise_huge_pages(p, bytes);
        return p;
    }
    const std::size_t size = round_up(bytes);
    if (size < bytes) throw std::bad_alloc();
    if (t_take > 0 && g_scopes.load() > 0)
        if (void* p = reuse(size)) return p;
    void* p = map_aligned(size);
    if (!p) throw std::bad_alloc();
    return p;
}

void large_free(void* p, std::size_t bytes, std::size_t align) noexcept {
    if (!p) return;
    if (bytes < kLargeBytes || align > kHugePage) ::operator delete(p, std::align_val_t(align));
    else if (!kOwnMappings) ::operator delete(p, std::align_val_t(kHugePage));
    else if (!keep(p, round_up(bytes))) platform::unmap_pages(p, round_up(bytes));
}

}  // namespace simdbvh
