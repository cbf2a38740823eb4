#pragma once
// The threads a build starts, by its size.
#include <cstddef>

namespace simdbvh {

// Builds of fewer primitives than this run on one thread. Measured on AMD EPYC
// Zen 5 (2 vCPUs), Bvh8::build(mesh) with two threads against one, medians of 11
// builds, two rounds, ms (collapse + pack inside): soup-10000 3.85 (1.09) and
// 3.72 (1.08) against 2.97 (0.37) and 3.88 (0.47); soup-30000 14.5 (2.82) and
// 12.9 (2.72) against 12.3 (1.83) and 11.7 (1.94); at soup-60000 the BVH2 build
// gains from its second thread (21.0 and 22.5 against 31.1 and 26.2).
inline constexpr std::size_t kMinPrimsForBuildThreads = 32768;

// `threads`, or one for a build of fewer than kMinPrimsForBuildThreads
// primitives: the trees are the same for any thread count, and a small build
// only pays for the threads it starts.
inline int build_threads(int threads, std::size_t primitives) {
    return primitives < kMinPrimsForBuildThreads && threads > 1 ? 1 : threads;
}

}  // namespace simdbvh
