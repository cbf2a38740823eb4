#pragma once
// Allocations of the builds' large arrays (references, BVH2 and wide nodes,
// the collapse's tables, Tri8 blocks): from kLargeBytes up, a mapping of their
// own, 2 MiB aligned and advised as transparent huge pages in full
// (madvise(MADV_HUGEPAGE): on kernels that use huge pages only where asked,
// as Debian's default "madvise" mode does, a 50 MB array otherwise takes
// 12,800 page faults on first touch). Smaller ones: `align`-aligned new.
// Free with large_free(p, bytes, align), the same bytes and align.
#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace simdbvh {

inline constexpr std::size_t kLargeBytes = std::size_t(2) << 20;

void* large_alloc(std::size_t bytes, std::size_t align);
void large_free(void* p, std::size_t bytes, std::size_t align) noexcept;

// While one of these is alive (in any thread), large blocks freed are kept
// instead of being unmapped (only their resident part: the untouched tail of
// an over-reserved vector is unmapped at once), and large allocations made
// inside a LargeAllocTake scope take them: a build's temporaries (the BVH2's
// references and nodes, the collapse's tables) become its output (wide nodes,
// Tri8 blocks) without the kernel clearing fresh pages again (dragon BVH8:
// 44 MB of blocks). A taking allocation gets the best-fitting kept block (the
// rest stays kept) or, when none is large enough, all of them moved into one
// range (mremap: page tables only, no copy) with fresh memory after them.
// When the last scope ends, the blocks still kept are unmapped. Kept blocks
// are not zeroed (LargeAllocator does not zero either).
class LargeAllocReuse {
public:
    LargeAllocReuse() noexcept;
    ~LargeAllocReuse();
    LargeAllocReuse(const LargeAllocReuse&) = delete;
    LargeAllocReuse& operator=(const LargeAllocReuse&) = delete;
};

// While one of these is alive on a thread, that thread's large allocations
// take kept blocks (above). Open it only around arrays written in full: kept
// pages given to a vector reserved beyond what it uses would sit idle and
// raise the build's peak memory.
class LargeAllocTake {
public:
    LargeAllocTake() noexcept;
    ~LargeAllocTake();
    LargeAllocTake(const LargeAllocTake&) = delete;
    LargeAllocTake& operator=(const LargeAllocTake&) = delete;
};

// A std::vector allocator over large_alloc, kAlign-aligned (at least
// alignof(T)). resize(n) default-initializes (no zero fill: the builds write
// every element they allocate, on the threads that use them); resize(n, v)
// and assign(n, v) fill as usual. On this repository's 2-vCPU PVM guests a
// first-touched 4 KiB page costs about 12 us and a 2 MiB one about 0.26 ms
// (the per-page figures behind kLargeBytes' huge-page threshold).
template <class T, std::size_t kAlign = alignof(T)>
struct LargeAllocator {
    static_assert(kAlign >= alignof(T));
    using value_type = T;
    template <class U>
    struct rebind {
        using other = LargeAllocator<U, (kAlign > alignof(U) ? kAlign : alignof(U))>;
    };
    LargeAllocator() = default;
    template <class U, std::size_t A>
    LargeAllocator(const LargeAllocator<U, A>&) noexcept {}
    T* allocate(std::size_t n) { return static_cast<T*>(large_alloc(n * sizeof(T), kAlign)); }
    void deallocate(T* p, std::size_t n) noexcept { large_free(p, n * sizeof(T), kAlign); }
    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
    template <class U, std::size_t A>
    bool operator==(const LargeAllocator<U, A>&) const noexcept {
        return true;
    }
};

template <class T, std::size_t kAlign = alignof(T)>
using LargeVector = std::vector<T, LargeAllocator<T, kAlign>>;

}  // namespace simdbvh
