#!/usr/bin/env bash
# Prints "<sha256>  <name>" for the images of every built-in scene (PNG and EXR), every shadow
# technique on three scenes (EXR) and the V images of `bench shadows`, so that a change meant to
# keep behaviour can be checked bit for bit:
#   scripts/byte-check.sh build/release/apps/penumbra > before.txt   # on the old tree
#   scripts/byte-check.sh build/release/apps/penumbra > after.txt    # on the new tree
#   diff before.txt after.txt
# Small images keep it to a few minutes on 2 cores. Extra arguments go to every `render`.
set -euo pipefail
bin=$(readlink -f "${1:?usage: byte-check.sh PENUMBRA_BINARY}")
shift
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cd "$dir"
for s in default contact fusion thin complex biglight motion defocus motion-defocus synth1m; do
  "$bin" render --builtin "$s" --width 320 --height 180 -o "$s.png" --exr "$s.exr" "$@" >/dev/null
done
techs=$("$bin" render --list-shadows | awk '/^[a-z]/ {print $1}')
for s in default fusion complex motion; do
  for t in $techs; do
    extra=()
    [ "$t" = reference ] && extra=(--param samples=64)
    "$bin" render --builtin "$s" --width 240 --height 135 --shadow "$t" "${extra[@]}" -o "$s-$t.png" \
      --exr "$s-$t.exr" "$@" >/dev/null
  done
done
"$bin" bench shadows --width 160 --height 90 --runs 1 --gt-samples 256 --out bench >/dev/null 2>&1
sha256sum ./*.png ./*.exr bench/images/*.png | sed 's#  \./#  #'
