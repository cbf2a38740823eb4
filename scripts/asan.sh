#!/usr/bin/env bash
# Build and test under AddressSanitizer + UndefinedBehaviorSanitizer (with
# float-divide-by-zero, no recovery): the `asan` preset of CMakePresets.json,
# compiled -Og -g1 (line tables for the reports). -Og halves GCC's time on the
# instrumented code against -O1 (the whole stage on this 2-vCPU machine:
# 986 s against 1,294 s; the tests themselves 363 s against 330 s); -O0
# builds faster still but runs the flattened traversals 5x slower.
#   scripts/asan.sh [extra ctest args, e.g. -L accuracy]
# Environment: JOBS (build jobs, default 2), TEST_TIMEOUT (seconds per test,
# default 900), TARGETS (build only these targets, default all).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
jobs="${JOBS:-2}"
timeout="${TEST_TIMEOUT:-900}"
# (strict_string_checks is off: it makes every strtof scan the rest of a 30 MB text.)
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
cmake --preset asan -DSIMDBVH_BUILD_BENCH=OFF
if [ -n "${TARGETS:-}" ]; then
  # shellcheck disable=SC2086
  cmake --build --preset asan -j"$jobs" --target $TARGETS
else
  cmake --build --preset asan -j"$jobs"
fi
# The install/consumer test builds an outside project without -fsanitize against
# the instrumented libraries (undefined __asan_*/__ubsan_* symbols): skipped here.
# The isa_objects checks disassemble the per-ISA objects (no code of ours runs;
# the release stage runs them on the same sources): 88 s of objdump over the
# instrumented objects, the slowest test under ASan, skipped here.
ctest --preset asan --timeout "$timeout" -LE 'install|isa_objects' "$@"
