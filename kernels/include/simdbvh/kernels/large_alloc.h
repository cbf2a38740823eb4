#pragma once
// Allocations of the builds' large arrays (references, Tri8 blocks): from
// kLargeBytes up, 2 MiB aligned and advised as transparent huge pages
// (madvise(MADV_HUGEPAGE): on kernels that use huge pages only where asked,
// as Debian's default "madvise" mode does, a 50 MB array otherwise takes
// 12,800 page faults on first touch). Smaller ones: `align`-aligned new.
// Free with large_free(p, bytes, align), the same bytes and align.
#include <cstddef>

namespace simdbvh {

inline constexpr std::size_t kLargeBytes = std::size_t(4) << 20;

void* large_alloc(std::size_t bytes, std::size_t align);
void large_free(void* p, std::size_t bytes, std::size_t align) noexcept;

// The same advice for memory allocated elsewhere (a std::vector's reserve()
// before its first write): the whole 2 MiB pages inside [p, p + bytes).
void advise_huge_pages(const void* p, std::size_t bytes) noexcept;

}  // namespace simdbvh
