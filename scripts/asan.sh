#!/usr/bin/env bash
# Build and test under AddressSanitizer + UndefinedBehaviorSanitizer (with
# float-divide-by-zero, no recovery): the `asan` preset of CMakePresets.json,
# compiled -Og -g1 (line tables for the reports). -Og halves GCC's time on the
# instrumented code against -O1 (the whole stage on this 2-vCPU machine:
# 986 s against 1,294 s; the tests themselves 363 s against 330 s); -O0
# builds faster still but runs the flattened traversals 5x slower.
# On a CPU without AVX-512F the preset's SIMDBVH_SANITIZE_HOST_ISAS_ONLY
# compiles the src/avx512/ objects (kernels, bvh8) without instrumentation
# (cmake/SimdbvhIsa.cmake): the dispatch never runs them there, so their
# instrumentation checked nothing, and bvh8's traverse_avx512.cpp was the
# costliest file of the build (137 s of CPU instrumented, 12 s not; the
# kernels' 20 -> 4 s). On a CPU with AVX-512 one SIMD ISA is instrumented per run (below).
# The per-ISA traversal instantiations (src/<isa>/traverse_*.cpp,
# shape_traverse_*.cpp) drop UBSan's alignment, null, pointer-overflow and
# vptr checks (SIMDBVH_TRAVERSAL_SANITIZE_FLAGS in the preset; ASan checks the
# same accesses): 275 -> 188 s of compile CPU for the four host-ISA files.
#   scripts/asan.sh [extra ctest args, e.g. -L accuracy]
# Environment: JOBS (build jobs, default 2), TEST_TIMEOUT (seconds per test,
# default 900), TARGETS (build only these targets, default all),
# ASAN_SAMPLE (sixth, the default: every sixth test; fifth; quarter; third; half:
# every second; all: the whole suite).
# Sampling, not skipping: the instrumented suite took 462 s of CI's 2,360 s
# (2026-11-26, commit 988721b), 268 s for half of it (commit 43390b7), so by
# default ctest ran every third test (-I start,,3, which takes every third
# case of every test binary), starting at the first, second or third by
# HEAD's commit count modulo 3: consecutive commits on main ran the three
# thirds. CI then took 1,840 s (ASan 818 s, the sampled tests 199 s of it;
# 2026-11-27, commit 5703ff3), so the default became a quarter (-I start,,4,
# by the commit count modulo 4). CI then took 1,664-1,780 s (ASan 732-850 s,
# 182 sampled tests; 2026-11-27, commit 6c0eb88), near the 30-minute cap, so
# the default became a fifth (-I start,,5): every test ran under ASan every
# fifth commit on main. CI then took 1,944 s on an Intel Xeon (tests 780 s,
# ASan 855 s of which the fifth's tests 149 s; 2026-11-28, commit 5bae8c4):
# the default is now a sixth.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
jobs="${JOBS:-2}"
timeout="${TEST_TIMEOUT:-900}"
# (strict_string_checks is off: it makes every strtof scan the rest of a 30 MB text.)
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
sample=()
mode="${ASAN_SAMPLE:-sixth}"
case "$mode" in
  sixth) k=6 ;;
  fifth) k=5 ;;
  quarter) k=4 ;;
  third) k=3 ;;
  half) k=2 ;;
  all) k=0 ;;
  *) echo "asan: ASAN_SAMPLE must be sixth, fifth, quarter, third, half or all (got '$mode')" >&2; exit 2 ;;
esac
commits=$(git -C "$root" rev-list --count HEAD 2>/dev/null || true)
if [ "$k" -gt 0 ] && [ -n "$commits" ]; then
  sample=(-I "$(( 1 + commits % k )),,$k")
  echo "asan: sampling every test $k from test $(( 1 + commits % k )) (commit $commits; ASAN_SAMPLE=all runs all)"
fi
# On a CPU with AVX-512F one SIMD ISA's objects are instrumented per run
# (SIMDBVH_SANITIZE_SIMD_ISA, cmake/SimdbvhIsa.cmake): AVX-512 and AVX2 by turns
# of the sample's cycle (commit count / k, so every sample meets both ISAs: with
# count % 2 a sixth would always meet the same one). SANITIZE_SIMD_ISA=all|avx2|avx512
# overrides (scripts/lib/simd_isa.sh).
# shellcheck source=lib/simd_isa.sh
. "$root/scripts/lib/simd_isa.sh"
simd_isa=$(sanitize_simd_isa "${commits:+$(( commits / (k > 0 ? k : 1) ))}")
echo "asan: SIMD objects instrumented: $simd_isa (on a CPU with AVX-512F; without it: avx2)"
cmake --preset asan -DSIMDBVH_BUILD_BENCH=OFF -DSIMDBVH_SANITIZE_SIMD_ISA="$simd_isa"
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
ctest --preset asan --timeout "$timeout" -LE 'install|isa_objects' "${sample[@]}" "$@"
