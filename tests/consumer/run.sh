#!/usr/bin/env bash
# Installs the build tree into a temp prefix, then configures, builds and runs
# the consumer project against it with find_package(simdbvh CONFIG REQUIRED).
set -euo pipefail
build_dir=$1; src_dir=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cmake --install "$build_dir" --prefix "$tmp/prefix" >/dev/null
cmake -S "$src_dir" -B "$tmp/build" -DCMAKE_PREFIX_PATH="$tmp/prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$tmp/build" -j2 >/dev/null
"$tmp/build/consumer"
