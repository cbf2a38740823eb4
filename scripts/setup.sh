#!/usr/bin/env bash
# Installs the Debian packages simdbvh needs, only those missing (idempotent).
# Runs apt-get as root or through sudo.
set -euo pipefail
pkgs=(build-essential cmake pkg-config git ca-certificates
      libxsimd-dev libembree-dev libhwloc-dev libbenchmark-dev libgtest-dev googletest
      zlib1g-dev libstb-dev python3 python3-matplotlib assimp-testmodels nodejs npm binutils
      clang libclang-rt-14-dev clang-format  # clang + its sanitizer/libFuzzer runtime (scripts/fuzz.sh), the formatter (scripts/check_format.sh)
      libcgal-dev python3-open3d python3-numpy nlohmann-json3-dev  # JSON report layer (cli/report.cpp)
      pybind11-dev python3-dev python3-pytest python3-setuptools python3-wheel python3-pip python3-venv)  # the Python module, its tests and pip install
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# nodejs/npm may come from elsewhere (e.g. nvm); only the commands matter.
if command -v npm >/dev/null 2>&1; then
  missing=("${missing[@]/nodejs}"); missing=("${missing[@]/npm}")
fi
missing=($(printf '%s\n' "${missing[@]}" | sed '/^$/d'))
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}" >&2
  sudo=""; [[ $(id -u) -eq 0 ]] || sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all packages present" >&2
fi
