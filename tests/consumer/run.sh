#!/usr/bin/env bash
# Installs the build tree into a temp prefix, then configures, builds and runs
# the consumer project against it with find_package(simdbvh CONFIG REQUIRED).
# The consumer is compiled the way a careless outside project might be:
# -march=haswell (FMA available) with -ffp-contract=fast. The exported target
# must put -ffp-contract=off after it, or the inline kernels change their bits.
set -euo pipefail
build_dir=$1; src_dir=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail() { echo "consumer: $*" >&2; exit 1; }
cmake --install "$build_dir" --prefix "$tmp/prefix" >/dev/null

# The licence travels with the package.
[[ -f "$tmp/prefix/share/doc/simdbvh/LICENSE" ]] || fail "LICENSE is not installed"
grep -q "MIT License" "$tmp/prefix/share/doc/simdbvh/LICENSE" || fail "the installed LICENSE is not the MIT licence"
config=$(find "$tmp/prefix" -name simdbvhConfig.cmake | head -n1)
grep -q "SPDX-License-Identifier: MIT" "$config" || fail "no SPDX line in $config"

cmake -S "$src_dir" -B "$tmp/build" -DCMAKE_PREFIX_PATH="$tmp/prefix" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_CXX_FLAGS="-march=haswell -ffp-contract=fast" >/dev/null
cmake --build "$tmp/build" -j2 -v > "$tmp/build.log" 2>&1 || { cat "$tmp/build.log"; fail "the build failed"; }
line=$(grep -E -- "-c .*main\.cpp" "$tmp/build.log" | head -n1)
[[ -n "$line" ]] || fail "no compile command for main.cpp in the build log"
# The last -ffp-contract on the command line wins.
last=$(grep -oE -- "-ffp-contract=[a-z]+" <<<"$line" | tail -n1)
[[ "$last" == "-ffp-contract=off" ]] || fail "the consumer compiles with $last (command: $line)"
grep -q -- "-fno-fast-math" <<<"$line" || fail "no -fno-fast-math on the consumer's command line"

if grep -q avx2 /proc/cpuinfo && grep -q fma /proc/cpuinfo; then
  "$tmp/build/consumer"
else
  echo "consumer built (this CPU cannot run -march=haswell code; not run)"
fi
