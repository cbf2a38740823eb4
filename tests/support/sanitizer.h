#pragma once
// Whether this test binary (and so the CLI built with it) runs under a
// sanitizer. AddressSanitizer and ThreadSanitizer reserve terabytes of shadow
// address space at start-up, so an address-space limit (`ulimit -v`,
// RLIMIT_AS) makes the process abort before main(): tests that need such a
// limit skip themselves there and run in the plain builds.
namespace test {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kUnderSanitizer = true;
#else
inline constexpr bool kUnderSanitizer = false;
#endif

#define SIMDBVH_SKIP_ADDRESS_LIMIT_UNDER_SANITIZER()                                          \
    do {                                                                                      \
        if (::test::kUnderSanitizer) GTEST_SKIP() << "an address-space limit cannot apply under a sanitizer"; \
    } while (0)

}  // namespace test
