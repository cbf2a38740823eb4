#!/usr/bin/env bash
# The library under Clang 14: configures build/clang (Release, CXX default
# clang++-14, ccache as the launcher when installed), builds the core rooms'
# tests (kernels, bvh2, bvh8, scene: every path against brute force, at every
# ISA this CPU runs, plus the per-ISA object checks) and the core self-check
# (tests/portable, which also compares the brute force's hits with the hit file
# written by GCC on x86-64), and runs them. The CLI, lab, Python module and
# benches are not built (the full suite also passes with Clang: docs/portability.md).
#   scripts/clang.sh      Environment: CXX (default clang++-14), JOBS (default 2)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build/clang"
jobs="${JOBS:-2}"
cxx="${CXX:-clang++-14}"
command -v "$cxx" >/dev/null || { echo "clang.sh: $cxx not found (apt-get install clang-14)" >&2; exit 2; }
targets=(simdbvh_test_kernels simdbvh_test_bvh2 simdbvh_test_bvh8 simdbvh_test_scene simdbvh_portable_check)

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
ctest --test-dir "$build" -j"$jobs" --output-on-failure -L '^(kernels|bvh2|bvh8|scene|portable)$'
