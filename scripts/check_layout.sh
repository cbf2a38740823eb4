#!/usr/bin/env bash
# The walls between the rooms (docs/architecture.md, "The rooms"):
#  - no include names a path with ../ (a room reaches another only through its
#    public headers or its internal target);
#  - no build file puts another room's src/ on an include path (what a room
#    shares is in <room>/internal/, behind its simdbvh_<room>_internal target);
#  - a room's internal headers are included by their full path
#    simdbvh/<room>/internal/..., never from another room's src/;
#  - folders are namespaces: a namespace below simdbvh:: is a room's name (or
#    the shared detail, or test for the test helpers).
# Exits 1 and lists each offence.
set -euo pipefail
cd "$(dirname "$0")/.."
bad=0
report() { echo "check_layout: $1" >&2; bad=1; }

while IFS= read -r hit; do report "include with ../: $hit"; done < <(
  git grep -nE '#include "\.\./|#include <\.\./' -- '*.h' '*.cpp' '*.inc' || true)

while IFS= read -r hit; do report "another room's src/ on an include path: $hit"; done < <(
  git grep -nE '(PROJECT_SOURCE_DIR\}|CMAKE_SOURCE_DIR\}|\.\.)/[a-z0-9_]+/src' -- '*CMakeLists.txt' '*.cmake' || true)

# Each room's src/ headers: included only from inside the room.
for room in kernels platform bvh2 bvh8 query accel scene io workloads reference store; do
  while IFS= read -r h; do
    name=${h#"$room/src/"}
    while IFS= read -r hit; do
      file=${hit%%:*}
      [[ $file == "$room/"* ]] && continue
      report "$room/src/$name included from another room: $hit"
    done < <(git grep -nF "#include \"$room/src/$name\"" -- '*.h' '*.cpp' '*.inc' || true)
  done < <(git ls-files "$room/src/*.h" "$room/src/*.inc")
done
rooms="kernels platform bvh2 bvh8 query accel scene io workloads reference store cli lab python fuzz"
while IFS= read -r hit; do
  ns=${hit##*namespace simdbvh::}
  ns=${ns%%[^a-z0-9_]*}
  [[ " $rooms detail test " == *" $ns "* ]] || report "namespace simdbvh::$ns is no room's: $hit"
done < <(git grep -nE 'namespace simdbvh::[a-z0-9_]+' -- '*.h' '*.cpp' '*.inc' || true)
[[ $bad == 0 ]] && echo "check_layout: the walls hold" >&2
exit $bad
