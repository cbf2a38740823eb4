#!/usr/bin/env bash
# ThreadSanitizer: many threads tracing one BVH2/BVH8 (tests/bvh8/concurrent_test.cpp)
# and the parallel build, under the tsan preset. Builds only the test targets needed.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset tsan -DSIMDBVH_BUILD_BENCH=OFF -DSIMDBVH_BUILD_TOOLS=OFF >/dev/null
cmake --build --preset tsan -j 2 --target simdbvh_test_bvh8 simdbvh_test_bvh2
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1"
build/tsan/tests/bvh8/simdbvh_test_bvh8 --gtest_filter='Concurrent.*:HostExecutor.*'
build/tsan/tests/simdbvh_test_bvh2 --gtest_filter='*SameTreeForAnyThreadCount/sah_binned*'
echo "tsan: passed"
