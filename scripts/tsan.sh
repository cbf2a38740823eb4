#!/usr/bin/env bash
# ThreadSanitizer: many threads tracing one BVH2/BVH8, also sorted batches (tests/bvh8/concurrent_test.cpp), and one scene
# (tests/scene/scene_concurrent_test.cpp)
# and the parallel build, under the tsan preset (AVX-512 objects uninstrumented on a
# CPU without AVX-512, cmake/SimdbvhIsa.cmake). Builds only the test targets needed.
set -euo pipefail
cd "$(dirname "$0")/.."
# One SIMD ISA's objects instrumented on a CPU with AVX-512F (cmake/SimdbvhIsa.cmake):
# AVX2 on even commit counts, AVX-512 on odd ones (scripts/lib/simd_isa.sh).
# SANITIZE_SIMD_ISA=all|avx2|avx512 overrides.
# shellcheck source=lib/simd_isa.sh
. scripts/lib/simd_isa.sh
commits=$(git rev-list --count HEAD 2>/dev/null || true)
simd_isa=$(sanitize_simd_isa "${commits:+$(( commits + 1 ))}")
# The tests below trace through the dispatch's choice: force the instrumented ISA.
# (A CPU without AVX-512F: AVX2 is the instrumented one; without AVX2 either: the default.)
grep -qw avx512f /proc/cpuinfo 2>/dev/null || [ "$simd_isa" = all ] || simd_isa=avx2
grep -qw avx2 /proc/cpuinfo 2>/dev/null || simd_isa=all
[ "$simd_isa" = all ] || export SIMDBVH_ISA="$simd_isa"
echo "tsan: SIMD objects instrumented: $simd_isa (the tests run it: SIMDBVH_ISA=${SIMDBVH_ISA:-default})"
cmake --preset tsan -DSIMDBVH_BUILD_BENCH=OFF -DSIMDBVH_BUILD_TOOLS=OFF -DSIMDBVH_SANITIZE_SIMD_ISA="$simd_isa" >/dev/null
# simdbvh_test_tsan: the four test files these filters select from (tests/CMakeLists.txt).
cmake --build --preset tsan -j 2 --target simdbvh_test_tsan
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1"
build/tsan/tests/simdbvh_test_tsan --gtest_filter='Concurrent.*:HostExecutor.*:*SameTreeForAnyThreadCount/sah_binned*'
# The filters must select tests: a renamed test would otherwise pass as nothing run.
n=$(build/tsan/tests/simdbvh_test_tsan --gtest_filter='Concurrent.*:HostExecutor.*:*SameTreeForAnyThreadCount/sah_binned*' \
      --gtest_list_tests | grep -c '^  ')
[ "$n" -ge 7 ] || { echo "tsan: only $n tests selected" >&2; exit 1; }
echo "tsan: passed"
