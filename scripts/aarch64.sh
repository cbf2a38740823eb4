#!/usr/bin/env bash
# The core library on 64-bit ARM: cross-builds the library and its
# self-check (tests/portable: every width and every ISA the CPU runs against
# the brute force, and the brute force against the hit file written on x86-64)
# with Debian's cross toolchain and cmake/aarch64.cmake into build/aarch64, and
# runs it under qemu-user. Installs g++-aarch64-linux-gnu and qemu-user first
# when missing (apt-get, as root or through sudo). No GoogleTest, Embree or
# hwloc for ARM is needed: the build has no tools, tests or benches.
#   scripts/aarch64.sh            Environment: JOBS (build jobs, default 2)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build/aarch64"
jobs="${JOBS:-2}"

missing=()
for p in g++-aarch64-linux-gnu qemu-user; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "aarch64: installing ${missing[*]}" >&2
  sudo=""; [[ $(id -u) -eq 0 ]] || sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$root" -B "$build" -DCMAKE_TOOLCHAIN_FILE="$root/cmake/aarch64.cmake" -DCMAKE_BUILD_TYPE=Release \
      -DSIMDBVH_BUILD_TOOLS=OFF -DSIMDBVH_BUILD_TESTS=OFF -DSIMDBVH_BUILD_BENCH=OFF -DSIMDBVH_PYTHON=OFF \
      -DSIMDBVH_BUILD_PORTABLE_CHECK=ON "${launcher[@]}" >"$build.configure.log" 2>&1 \
  || { cat "$build.configure.log" >&2; exit 2; }
cmake --build "$build" -j"$jobs" --target simdbvh_portable_check
# The default ISA (the best this CPU runs), then each one forced.
(cd "$build" && ctest --output-on-failure -L portable)
for isa in scalar; do
  echo "== SIMDBVH_ISA=$isa"
  SIMDBVH_ISA=$isa qemu-aarch64 -L /usr/aarch64-linux-gnu "$build/tests/portable/simdbvh_portable_check" \
    --expect "$root/tests/data/portable/hits.bin"
done
