// large_alloc / LargeAllocator: large blocks are mappings of their own, 2 MiB
// aligned, advised as huge pages over their whole length and unmapped in full
// on free; small ones keep the requested alignment. Inside a LargeAllocReuse
// scope, freed blocks (their resident part) go to later large allocations.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "simdbvh/platform/large_alloc.h"

#if defined(__SANITIZE_ADDRESS__)
#define SIMDBVH_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SIMDBVH_TEST_ASAN 1
#endif
#endif

namespace simdbvh {
namespace {

constexpr std::uintptr_t kHuge = std::uintptr_t(2) << 20;

struct Mapping {
    bool found = false;
    std::uintptr_t lo = 0, hi = 0;
    std::string flags;  // VmFlags
};

// The /proc/self/smaps entry that contains address a.
Mapping mapping_of(const void* p) {
    const auto a = reinterpret_cast<std::uintptr_t>(p);
    std::ifstream in("/proc/self/smaps");
    Mapping m, cur;
    std::string line;
    while (std::getline(in, line)) {
        std::uintptr_t lo = 0, hi = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> lo >> dash >> hi && dash == '-') {
            if (cur.found) return cur;
            cur = {};
            if (a >= lo && a < hi) cur = {true, lo, hi, ""};
        } else if (cur.found && line.rfind("VmFlags:", 0) == 0) {
            cur.flags = line;
        }
    }
    return cur.found ? cur : m;
}

TEST(LargeAlloc, LargeBlocksAreAlignedAdvisedAndUnmappedInFull) {
#if defined(SIMDBVH_TEST_ASAN)
    GTEST_SKIP() << "under ASan large blocks stay on operator new (large_alloc.cpp)";
#endif
    const std::size_t bytes = (std::size_t(5) << 20) + 12345;  // a partial 2 MiB page at the end
    void* p = large_alloc(bytes, 64);
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(p) % kHuge, 0u);
    std::memset(p, 0xab, bytes);  // every byte writable
    const Mapping m = mapping_of(static_cast<char*>(p) + bytes - 1);
    ASSERT_TRUE(m.found);
    // The huge-page advice covers the whole block, its partial last page too.
    EXPECT_NE(m.flags.find(" hg"), std::string::npos) << m.flags;
    EXPECT_LE(m.lo, reinterpret_cast<std::uintptr_t>(p));
    large_free(p, bytes, 64);
    EXPECT_FALSE(mapping_of(p).found);
    EXPECT_FALSE(mapping_of(static_cast<char*>(p) + bytes - 1).found);
}

TEST(LargeAlloc, ReuseScopeHandsFreedBlocksToLaterAllocations) {
#if defined(SIMDBVH_TEST_ASAN)
    GTEST_SKIP() << "under ASan large blocks stay on operator new (large_alloc.cpp)";
#endif
    const std::size_t big = std::size_t(12) << 20, small = std::size_t(5) << 20;
    char* kept = nullptr;
    {
        const LargeAllocReuse scope;
        char* a = static_cast<char*>(large_alloc(big, 64));
        std::memset(a, 1, big);
        large_free(a, big, 64);
        EXPECT_TRUE(mapping_of(a).found);                          // kept while the scope lasts
        char* fresh = static_cast<char*>(large_alloc(small, 64));  // outside a LargeAllocTake: not a kept block
        EXPECT_TRUE(fresh < a || fresh >= a + big);
        large_free(fresh, small, 64);  // never touched: nothing kept
        const LargeAllocTake take;
        // Best fit: the front of the freed block; the rest (from 6 MiB) stays kept.
        char* b = static_cast<char*>(large_alloc(small, 64));
        EXPECT_EQ(b, a);
        EXPECT_EQ(b[small - 1], 1);  // the same pages, not fresh ones
        EXPECT_TRUE(mapping_of(a + (std::size_t(6) << 20)).found);
        large_free(b, small, 64);
        {
            const LargeAllocReuse nested;  // scopes nest: the inner end releases nothing
        }
        EXPECT_TRUE(mapping_of(b).found);
        char* c = static_cast<char*>(large_alloc(small, 64));  // either 6 MiB half of a (both fit best)
        EXPECT_TRUE(c == a || c == a + (std::size_t(6) << 20));
        std::memset(c, 2, small);
        large_free(c, small, 64);
        kept = a;
    }
    EXPECT_FALSE(mapping_of(kept).found);  // the last scope's end unmapped every kept block
    EXPECT_FALSE(mapping_of(kept + big - 1).found);
    // Without a scope a freed block is unmapped at once.
    char* d = static_cast<char*>(large_alloc(big, 64));
    d[0] = 1;
    large_free(d, big, 64);
    EXPECT_FALSE(mapping_of(d).found);
}

TEST(LargeAlloc, ReuseScopeKeepsOnlyTheResidentPartOfAFreedBlock) {
#if defined(SIMDBVH_TEST_ASAN)
    GTEST_SKIP() << "under ASan large blocks stay on operator new (large_alloc.cpp)";
#endif
    const LargeAllocReuse scope;
    const std::size_t big = std::size_t(16) << 20, touched = std::size_t(3) << 20;
    char* never = static_cast<char*>(large_alloc(big, 64));  // nothing touched at all: nothing kept
    large_free(never, big, 64);
    EXPECT_FALSE(mapping_of(never).found);
    char* a = static_cast<char*>(large_alloc(big, 64));
    std::memset(a, 7, touched);  // as a vector reserved far beyond its size
    large_free(a, big, 64);
    EXPECT_TRUE(mapping_of(a + touched - 1).found);              // the touched 2 MiB pages: kept
    EXPECT_FALSE(mapping_of(a + (std::size_t(4) << 20)).found);  // the untouched rest: unmapped
}

TEST(LargeAlloc, ReuseScopeMovesKeptBlocksIntoAnAllocationNoneFits) {
#if defined(SIMDBVH_TEST_ASAN)
    GTEST_SKIP() << "under ASan large blocks stay on operator new (large_alloc.cpp)";
#endif
    const LargeAllocReuse scope;
    const std::size_t mib = std::size_t(1) << 20;
    char* a = static_cast<char*>(large_alloc(4 * mib, 64));
    char* b = static_cast<char*>(large_alloc(6 * mib, 64));
    std::memset(a, 1, 4 * mib);
    std::memset(b, 2, 6 * mib);
    large_free(a, 4 * mib, 64);
    large_free(b, 6 * mib, 64);
    // 12 MiB: neither block fits, so both are moved into one range, the
    // larger first, and the last 2 MiB are fresh (zero) pages.
    const LargeAllocTake take;
    char* c = static_cast<char*>(large_alloc(12 * mib, 64));
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(c) % kHuge, 0u);
    EXPECT_EQ(c[0], 2);
    EXPECT_EQ(c[6 * mib - 1], 2);
    EXPECT_EQ(c[6 * mib], 1);
    EXPECT_EQ(c[10 * mib - 1], 1);
    EXPECT_EQ(c[10 * mib], 0);
    EXPECT_EQ(c[12 * mib - 1], 0);
    EXPECT_FALSE(mapping_of(a).found);  // moved, not copied
    EXPECT_FALSE(mapping_of(b).found);
    std::memset(c, 3, 12 * mib);  // every byte writable
    large_free(c, 12 * mib, 64);
}

TEST(LargeAlloc, SmallBlocksKeepTheirAlignment) {
    for (std::size_t align : {std::size_t(16), std::size_t(64), std::size_t(4096)}) {
        void* p = large_alloc(1000, align);
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(p) % align, 0u) << align;
        large_free(p, 1000, align);
    }
}

TEST(LargeAlloc, LargeVectorFillsWhenAskedAndKeepsValuesWhenItGrows) {
    LargeVector<std::uint32_t, 64> v;
    v.resize(std::size_t(3) << 20, 7u);  // 12 MiB: a large block
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % kHuge, 0u);
    for (std::size_t i = 0; i < v.size(); i += 4099) ASSERT_EQ(v[i], 7u) << i;
    v[123] = 42;
    v.resize(std::size_t(5) << 20, 9u);  // moves to a new block
    EXPECT_EQ(v[123], 42u);
    EXPECT_EQ(v[(std::size_t(3) << 20) - 1], 7u);
    EXPECT_EQ(v.back(), 9u);
}

}  // namespace
}  // namespace simdbvh
