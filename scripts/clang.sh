#!/usr/bin/env bash
# The library under Clang 14: configures build/clang (Release, CXX default
# clang++-14, ccache as the launcher when installed), builds the tests of
# kernels, platform, bvh8, query, accel and scene (every path against brute force, at every ISA this
# CPU runs, and the per-ISA object checks) and the core self-check
# (tests/portable: every width and ISA against brute force, and the brute
# force's hits against the hit file written on x86-64), and runs the self-check
# and every STRIDE-th of the others (default 4; 1 for all). The CLI, lab,
# Python module, benches and the bvh2 tests are not built, to keep the stage
# short (the full suite also passes with Clang: docs/portability.md).
#   scripts/clang.sh      Environment: CXX (default clang++-14), JOBS (default 2), STRIDE
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build/clang"
jobs="${JOBS:-2}"
cxx="${CXX:-clang++-14}"
command -v "$cxx" >/dev/null || { echo "clang.sh: $cxx not found (apt-get install clang-14)" >&2; exit 2; }
stride="${STRIDE:-4}"
targets=(simdbvh_test_kernels simdbvh_test_platform simdbvh_test_bvh8 simdbvh_test_query simdbvh_test_accel simdbvh_test_scene simdbvh_portable_check)

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
mkdir -p "$root/build"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" \
      -DSIMDBVH_BUILD_BENCH=OFF -DSIMDBVH_PYTHON=OFF "${launcher[@]}" >"$build.configure.log" 2>&1 \
  || { cat "$build.configure.log" >&2; exit 2; }
# -ffp-contract=off must reach every object: Clang's default (on) would fuse
# a * b + c in the scalar paths and the SIMD paths would no longer agree.
grep -q -- '-ffp-contract=off' "$build/kernels/CMakeFiles/simdbvh_kernels.dir/flags.make" \
  || { echo "clang.sh: -ffp-contract=off missing from the compile flags" >&2; exit 1; }
cmake --build "$build" -j"$jobs" --target "${targets[@]}"
ctest --test-dir "$build" -j"$jobs" --output-on-failure -L '^portable$'
# Every stride-th test, starting at a rotating offset (the commit count), so
# consecutive commits cover different tests.
offset=$(( $(git -C "$root" rev-list --count HEAD 2>/dev/null || echo 0) % stride + 1 ))
ctest --test-dir "$build" -j"$jobs" --output-on-failure -L '^(kernels|platform|bvh8|query|accel|scene)$' -I "$offset,,$stride"
