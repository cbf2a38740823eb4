#include "simdbvh/kernels/large_alloc.h"

#include <sys/mman.h>

#include <algorithm>
#include <cstdint>
#include <new>

namespace simdbvh {

namespace {
constexpr std::size_t kHugePage = std::size_t(2) << 20;
std::size_t alignment(std::size_t bytes, std::size_t align) {
    return bytes >= kLargeBytes ? std::max(align, kHugePage) : align;
}
}  // namespace

void* large_alloc(std::size_t bytes, std::size_t align) {
    const std::size_t a = alignment(bytes, align);
    void* p = ::operator new(bytes, std::align_val_t(a));
    if (a == kHugePage)  // advice only: failure (no THP support) changes nothing
        madvise(p, bytes / kHugePage * kHugePage, MADV_HUGEPAGE);
    return p;
}

void advise_huge_pages(const void* p, std::size_t bytes) noexcept {
    if (bytes < kLargeBytes) return;
    const auto a = reinterpret_cast<std::uintptr_t>(p);
    const std::uintptr_t lo = (a + kHugePage - 1) / kHugePage * kHugePage;
    const std::uintptr_t hi = (a + bytes) / kHugePage * kHugePage;
    if (hi > lo) madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);
}

void large_free(void* p, std::size_t bytes, std::size_t align) noexcept {
    ::operator delete(p, std::align_val_t(alignment(bytes, align)));
}

}  // namespace simdbvh
