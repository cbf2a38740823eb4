#pragma once
// Whether this test binary (and so the CLI built with it) runs under a
// sanitizer. AddressSanitizer and ThreadSanitizer reserve terabytes of shadow
// address space at start-up, so an address-space limit (`ulimit -v`,
// RLIMIT_AS) makes the process abort before main(): tests that need such a
// limit skip themselves there and run in the plain builds.
#include <cstddef>

namespace test {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kUnderSanitizer = true;
#else
inline constexpr bool kUnderSanitizer = false;
#endif

// Under a sanitizer (5 to 20 times slower) the heaviest loops sample their
// cases: every kSanitizerStride-th ray or point, deterministic, the same
// assertions on each; the release run covers them all.
inline constexpr std::size_t kSanitizerStride = kUnderSanitizer ? 8 : 1;
inline std::size_t sampled(std::size_t n, std::size_t at_least = 1) {
    const std::size_t s = n / kSanitizerStride;
    return s < at_least ? (n < at_least ? n : at_least) : s;
}

#define SIMDBVH_SKIP_ADDRESS_LIMIT_UNDER_SANITIZER()                                                          \
    do {                                                                                                      \
        if (::test::kUnderSanitizer) GTEST_SKIP() << "an address-space limit cannot apply under a sanitizer"; \
    } while (0)

}  // namespace test
