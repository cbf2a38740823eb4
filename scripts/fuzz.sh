#!/usr/bin/env bash
# Fuzz the mesh loaders and the ray/hit readers with libFuzzer + ASan + UBSan
# (docs/accuracy.md). Configures a Clang build in build/fuzz (fuzz/ as the top
# level), builds fuzz_load_mesh and fuzz_read_rays, and runs each for SECONDS
# (default 60) over a working copy of fuzz/corpus/<target>, JOBS (default 2) at a time.
# fuzz_load_store (the saved-structure loader, store/) links the trees and is
# run when named: scripts/fuzz.sh 60 fuzz_load_store.
# The targets link simdbvh_io (the loaders and the ray/hit file readers)
# and simdbvh_kernels only, so the instrumented build compiles those 22 files
# and not the BVH libraries or the rest of the scene code, which the fuzzed
# readers never call. CI's fuzz stage (30 s per target, 2 cores, builds of
# others sharing the machine): 545 -> 276 s wall, 576 -> 118 s of CPU of which
# 60 s is the fuzzing itself.
#   scripts/fuzz.sh [SECONDS] [TARGET...]
# Environment: JOBS (build jobs, default 2), FUZZ_RSS_MB (default 2048),
# CXX (default clang++).
# Findings land in build/fuzz/artifacts/<target>-crash-*: keep each under
# tests/data/fuzz/<target>-<name>.<ext> (tests/accuracy/fuzz_regression_test.cpp
# loads them expecting a mesh or a clean simdbvh::Error) and fix the loader.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
secs="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(fuzz_load_mesh fuzz_read_rays)
build="$root/build/fuzz"
jobs="${JOBS:-2}"
rss="${FUZZ_RSS_MB:-2048}"
cxx="${CXX:-clang++}"
command -v "$cxx" >/dev/null || { echo "fuzz.sh: $cxx not found (apt-get install clang)" >&2; exit 2; }

mkdir -p "$build"
flags="-fsanitize=address,undefined,fuzzer-no-link -fsanitize=float-divide-by-zero -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g"
cmake -S "$root/fuzz" -B "$build" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >"$build.configure.log" 2>&1 \
  || { cat "$build.configure.log" >&2; exit 2; }
cmake --build "$build" -j"$jobs" --target "${targets[@]}"

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:symbolize=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
# The targets run side by side, up to JOBS at a time (each libFuzzer run is one
# process): CI's two 30 s runs take 30 s of wall time on 2 cores, not 60.
run_one() {
  local t="$1" max_len work log
  case "$t" in
    fuzz_load_mesh) max_len=65536 ;;
    fuzz_read_rays) max_len=4096 ;;
    fuzz_load_store) max_len=65536 ;;
    *) max_len=4096 ;;
  esac
  work="$build/corpus/$t"
  log="$build/$t.log"
  "$build/$t" "$work" -max_total_time="$secs" -max_len="$max_len" -rss_limit_mb="$rss" -timeout=20 \
    -seed=1 -print_final_stats=1 -artifact_prefix="$build/artifacts/$t-" >"$log" 2>&1
}
status=0
pids=()
for t in "${targets[@]}"; do
  work="$build/corpus/$t"
  mkdir -p "$work" "$build/artifacts"
  cp -n "$root/fuzz/corpus/$t"/* "$work"/ 2>/dev/null || true
  echo "== $t: ${secs}s, corpus $(ls "$work" | wc -l) inputs, -rss_limit_mb=$rss"
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do sleep 1; done
  run_one "$t" &
  pids+=($!)
done
for i in "${!targets[@]}"; do
  t="${targets[$i]}"
  log="$build/$t.log"
  if wait "${pids[$i]}"; then
    echo "== $t ok: $(grep -E '^#[0-9]+.*DONE' "$log" | tail -1 || tail -1 "$log")"
    grep -E 'stat::number_of_executed_units|stat::peak_rss_mb' "$log" | sed 's/^/   /'
  else
    status=1
    echo "   FINDING ($t): see $log and $build/artifacts/" >&2
    grep -E 'ERROR|SUMMARY|runtime error|Test unit written' "$log" | head -20 >&2
  fi
done
exit $status
