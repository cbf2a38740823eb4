#!/usr/bin/env bash
# Build and test under AddressSanitizer + UndefinedBehaviorSanitizer (with
# float-divide-by-zero, no recovery): the `asan` preset of CMakePresets.json,
# compiled -O1 -g1 (line tables for the reports; -O2 -g took 3x as long to
# compile the flattened per-ISA traversals, most of CI).
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
