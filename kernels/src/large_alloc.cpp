#include "simdbvh/kernels/large_alloc.h"

#include <sys/mman.h>

#include <algorithm>
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

void large_free(void* p, std::size_t bytes, std::size_t align) noexcept {
    ::operator delete(p, std::align_val_t(alignment(bytes, align)));
}

}  // namespace simdbvh
