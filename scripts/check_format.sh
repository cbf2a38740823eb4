#!/usr/bin/env bash
# The C++ sources are as clang-format formats them (.clang-format, Debian's
# clang-format 14: scripts/setup.sh installs it). Lists the unformatted files
# and exits 1; with --fix, formats them in place. *.inc fragments (included
# inside a namespace) are left as written.
set -euo pipefail
cd "$(dirname "$0")/.."
fmt=$(command -v clang-format-14 || command -v clang-format || true)
[[ -n $fmt ]] || { echo "check_format: clang-format not found (bash scripts/setup.sh)" >&2; exit 2; }
mapfile -t files < <(git ls-files '*.h' '*.cpp' | grep -v '^tests/data/')
if [[ ${1:-} == --fix ]]; then
  "$fmt" -i "${files[@]}"
  exit 0
fi
bad=()
for f in "${files[@]}"; do
  "$fmt" --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if ((${#bad[@]})); then
  echo "check_format: ${#bad[@]} files differ from clang-format (bash scripts/check_format.sh --fix):" >&2
  printf '  %s\n' "${bad[@]}" >&2
  exit 1
fi
echo "check_format: ${#files[@]} files formatted" >&2
